//! `obbcd detect`: the colliding pairs of a scene.

use crate::timing::median_ms;
use anyhow::{Context, Result};
use clap::Args;
use obb_model::{EngineKind, GroupMask, Pair, Prepared, Scene};
use serde::Serialize;
use std::path::PathBuf;

#[derive(Args)]
pub struct DetectArgs {
    /// Scene JSON file.
    #[arg(long)]
    scene: PathBuf,
    /// brute, sap, improved-sap, sweep or grid.
    #[arg(long, default_value = "grid")]
    engine: EngineKind,
    /// Which group pairs: `all`, `cross` (different groups only) or a list like `0-1,0-2,1-2`.
    #[arg(long, default_value = "all")]
    groups: GroupMask,
    /// Run the detection N times and report the median time.
    #[arg(long, default_value_t = 1)]
    repeat: usize,
    /// Pairs JSON file to write.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
}

/// The pairs file: `{"pairs":[[i,j], ...]}`, i < j, sorted ascending.
#[derive(Serialize)]
struct PairsFile<'a> {
    pairs: &'a [Pair],
}

pub fn run(a: DetectArgs) -> Result<()> {
    let scene = Scene::load(&a.scene)?;
    let mut engine = a.engine.build();
    let mut boxes = Prepared::default();
    let mut pairs = Vec::new();
    // Timed: the per-frame work (AABBs, SAT slack, broad and narrow phase), scene already loaded.
    // The loop runs on a pool worker, as a real-time loop should: a call from outside the pool
    // pays a thread wake-up per parallel phase (README, "Performance").
    let (ms, counters) = rayon::scope(|_| {
        median_ms(a.repeat, || {
            let frame = boxes.update(&scene.obbs);
            engine.detect(&frame, &a.groups, &mut pairs)
        })
    });
    if let Some(path) = &a.output {
        let json = serde_json::to_string(&PairsFile { pairs: &pairs })?;
        std::fs::write(path, json).with_context(|| format!("cannot write {}", path.display()))?;
    }
    println!(
        "engine={} obbs={} groups={} candidates={} sat={} pairs={} time_ms={:.3} threads={}",
        a.engine,
        scene.obbs.len(),
        a.groups,
        counters.candidates,
        counters.sat,
        counters.pairs,
        ms,
        rayon::current_num_threads()
    );
    Ok(())
}
