//! `obbcd plan`: a hardware configuration planned from scenes and the user's aims
//! (`obb_model::fixed::plan`), written as TOML with the figure that decided each key.

use anyhow::{bail, Context, Result};
use clap::Args;
use obb_rtl::flow::aims::AimArgs;
use std::path::PathBuf;

#[derive(Args)]
pub struct PlanArgs {
    #[command(flatten)]
    aims: AimArgs,
    /// Write the configuration here (default: standard output).
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
}

pub fn run(a: PlanArgs) -> Result<()> {
    if a.aims.scenes.is_empty() {
        bail!("plan needs at least one --scene");
    }
    let plan = a.aims.plan()?;
    let toml = plan.to_toml();
    // The figures go to standard error when the configuration goes to standard output.
    let mut lines = vec![format!("planned: {}", plan.summary())];
    for (path, f) in a.aims.scenes.iter().zip(&plan.scenes) {
        lines.push(format!(
            "scene={} obbs={} clocks={} frame_ms={:.4} pairs={} false_positives={}",
            path.display(),
            f.boxes,
            f.clocks,
            f.clocks as f64 * plan.cfg.clock_ns * 1e-6,
            f.pairs,
            f.false_positives
        ));
    }
    match &a.output {
        Some(path) => {
            std::fs::write(path, toml)
                .with_context(|| format!("cannot write {}", path.display()))?;
            lines.iter().for_each(|l| println!("{l}"));
            println!("wrote {}", path.display());
        }
        None => {
            print!("{toml}");
            lines.iter().for_each(|l| eprintln!("{l}"));
        }
    }
    Ok(())
}
