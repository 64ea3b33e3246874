//! The command-line aims of a planned configuration (`obb_model::fixed::plan`), shared by
//! `obbcd plan` and `gen-rtl --scene`: the scenes the core must take and what the user wants
//! of it.

use anyhow::{Context, Result};
use clap::Args;
use obb_model::fixed::plan::{plan, Aims, Plan};
use obb_model::{GroupMask, Scene};
use std::path::PathBuf;

#[derive(Args, Clone, Debug)]
pub struct AimArgs {
    /// Scene JSON file, each a frame the core must take (repeat for several).
    #[arg(long = "scene")]
    pub scenes: Vec<PathBuf>,
    /// Which group pairs: `all` (default, as the CPU engines), `cross`, or a list like
    /// `0-1,0-2,1-2`.
    #[arg(long, default_value = "all")]
    pub groups: GroupMask,
    /// The largest false-positive rate (false positives over reported pairs) on any scene: the
    /// data width is the narrowest that meets it.
    #[arg(long, default_value_t = Aims::default().fp_rate)]
    pub fp_rate: f64,
    /// Frames per second to reach on every scene at `--period-ns` (the grid's lanes).
    #[arg(long)]
    pub rate_hz: Option<f64>,
    /// Clock period in ns the frame rate assumes (the configuration's `clock_ns`).
    #[arg(long, default_value_t = Aims::default().period_ns)]
    pub period_ns: f64,
}

impl AimArgs {
    /// Loads the scenes and plans for them.
    pub fn plan(&self) -> Result<Plan> {
        let scenes = self
            .scenes
            .iter()
            .map(|p| Scene::load(p).map_err(anyhow::Error::from))
            .collect::<Result<Vec<_>>>()?;
        let aims = Aims {
            groups: self.groups.clone(),
            fp_rate: self.fp_rate,
            rate_hz: self.rate_hz,
            period_ns: self.period_ns,
        };
        let plan = plan(&scenes, &aims).context("cannot plan a configuration for the scenes")?;
        for aim in &plan.unmet {
            eprintln!("warning: aim not met: {aim}");
        }
        Ok(plan)
    }
}
