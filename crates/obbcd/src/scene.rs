//! `obbcd scene`: generate a scene.

use crate::builtin::DEFAULT_SEED;
use anyhow::Result;
use clap::{Args, ValueEnum};
use obb_model::generate::{surgical, uniform, SURGICAL_DEFAULT_N, UNIFORM_DEFAULT_DENSITY};
use std::path::PathBuf;

#[derive(Clone, Copy, ValueEnum)]
pub enum Kind {
    /// Tissue surface and two laparoscopic grippers (the paper's scenario).
    Surgical,
    /// Randomly rotated boxes in a cube.
    Uniform,
}

#[derive(Args)]
pub struct SceneArgs {
    kind: Kind,
    /// Number of boxes (surgical: 17,500; uniform: 10,000).
    #[arg(long)]
    n: Option<usize>,
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
    /// uniform: total box volume over cube volume.
    #[arg(long, default_value_t = UNIFORM_DEFAULT_DENSITY)]
    density: f64,
    /// Output JSON file.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
}

pub fn run(a: SceneArgs) -> Result<()> {
    let scene = match a.kind {
        Kind::Surgical => surgical(a.n.unwrap_or(SURGICAL_DEFAULT_N), a.seed)?,
        Kind::Uniform => uniform(a.n.unwrap_or(10_000), a.seed, a.density)?,
    };
    scene.validate()?;
    scene.save(&a.output)?;
    eprintln!("wrote {} obbs to {}", scene.obbs.len(), a.output.display());
    Ok(())
}
