//! `obbcd stats`: what each broad phase does on a scene.

use anyhow::Result;
use clap::Args;
use obb_model::engines::Grid;
use obb_model::stats::{scene_stats, STATS_ENGINES};
use obb_model::{Engine, GroupMask, Prepared, Scene};
use std::path::PathBuf;

#[derive(Args)]
pub struct StatsArgs {
    /// Scene JSON file.
    #[arg(long)]
    scene: PathBuf,
}

pub fn run(a: StatsArgs) -> Result<()> {
    let scene = Scene::load(&a.scene)?;
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&scene.obbs);
    let rows = scene_stats(&boxes);
    let mut header = vec![
        "groups",
        "pairs",
        "overlap_x",
        "overlap_y",
        "overlap_z",
        "overlap_xyz",
    ];
    let engine_cols: Vec<String> = STATS_ENGINES
        .iter()
        .flat_map(|k| [format!("{k}_visits"), format!("{k}_sat_tests")])
        .collect();
    header.extend(engine_cols.iter().map(String::as_str));
    header.push("collisions");
    println!("{}", header.join("\t"));
    for r in rows {
        let mut cells = vec![
            r.mask.to_string(),
            r.pairs.to_string(),
            r.overlap[0].to_string(),
            r.overlap[1].to_string(),
            r.overlap[2].to_string(),
            r.overlap_xyz.to_string(),
        ];
        for (_, c) in &r.engines {
            cells.push(c.visits.to_string());
            cells.push(c.sat_tests.to_string());
        }
        cells.push(r.collisions.to_string());
        println!("{}", cells.join("\t"));
    }
    let mut grid = Grid::default();
    grid.detect(&boxes, &GroupMask::All, &mut Vec::new());
    let g = grid.stats();
    println!(
        "grid layout={} cell_mm={:.4} dims={}x{}x{} entries={} entries_per_box={:.2} max_per_cell={} large={}",
        if g.corner { "corner" } else { "regular" },
        g.geometry.cell,
        g.geometry.dims[0],
        g.geometry.dims[1],
        g.geometry.dims[2],
        g.entries,
        g.entries as f64 / boxes.len().max(1) as f64,
        g.max_per_cell,
        g.large
    );
    Ok(())
}
