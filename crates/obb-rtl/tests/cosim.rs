//! The emitted core on whole scenes, through the test bench `sim/tb_obb_core.v`: in Verilator,
//! in Icarus as a second opinion, and as the yosys netlist at gate level. Every frame's pair
//! stream (in order), counters and clock count must equal the bit-exact model's
//! (`obb_rtl::cosim::compare`), as `obbcd cosim` checks them.

mod common;

use common::scenes::{dense, first, stiff, touching_pairs};
use obb_model::fixed::HwConfig;
use obb_model::generate::{surgical, SURGICAL_DEFAULT_N};
use obb_model::Scene;
use obb_rtl::cosim::{build, compare, prepare, stimulus, Expected, Level, RunOptions, SimFrame};
use obb_rtl::verilator::{scratch_dir, Simulator};
use std::path::PathBuf;
use std::time::Instant;

/// Builds are cached across the test binaries and runs, below cargo's scratch directory.
fn cache() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cosim-cache")
}

/// Simulates one frame of `scene` on `design` (the Verilog for `cfg`) and checks it against
/// the model; `ready_every` throttles the pair stream.
fn cosim(
    cfg: &HwConfig,
    design: &str,
    level: Level,
    sim: Simulator,
    scene: &Scene,
    ready_every: u32,
    name: &str,
) -> SimFrame {
    let (model, boxes) = prepare(scene, cfg).unwrap_or_else(|e| panic!("{name}: {e}"));
    let bench = build(design, level, sim, false, &cache()).unwrap();
    let dir = scratch_dir("cosim").unwrap();
    let stim = dir.join("stim.hex");
    std::fs::write(&stim, stimulus(&boxes, cfg)).unwrap();
    let opts = RunOptions {
        ready_every,
        ..RunOptions::default()
    };
    let start = Instant::now();
    let got = bench.run(&stim, boxes.len(), &opts, |_| {}).unwrap();
    let secs = start.elapsed().as_secs_f64();
    let run = model.map(|m| m.run());
    let want = run.as_ref().map_or(Expected::OverCapacity, Expected::Frame);
    if let Err(e) = compare(&got, &want, ready_every > 1) {
        panic!("{name} ({sim:?}, {level:?}): {e}");
    }
    eprintln!(
        "{name} ({sim:?}, {level:?}): {} boxes, {} pairs, {} cycles, {:.2} s simulated ({:.0} clocks/s)",
        boxes.len(),
        got.stream.len(),
        got.cycles,
        secs,
        got.clocks as f64 / secs
    );
    got
}

/// The default configuration from no box and one box to the whole 17,500-OBB surgical scene.
#[test]
fn default_core_from_one_box_to_the_full_surgical_scene() {
    let cfg = HwConfig::default();
    let design = obb_rtl::generate::core(&cfg).unwrap();
    let full = surgical(SURGICAL_DEFAULT_N, 1).unwrap();
    let scenes = [
        ("no box", Scene { obbs: vec![] }),
        ("one box", first(touching_pairs(), 1)),
        ("touching", touching_pairs()),
        ("surgical 1000", surgical(1000, 1).unwrap()),
        ("surgical 17500", full),
    ];
    for (name, scene) in &scenes {
        cosim(
            &cfg,
            &design,
            Level::Rtl,
            Simulator::Verilator,
            scene,
            1,
            name,
        );
    }
}

#[test]
fn tmp_small() {
    let cfg = HwConfig {
        capacity: 512,
        ..HwConfig::default()
    }
    .fitted(&touching_pairs());
    let design = obb_rtl::generate::core(&cfg).unwrap();
    cosim(
        &cfg,
        &design,
        Level::Rtl,
        Simulator::Verilator,
        &touching_pairs(),
        1,
        "touching 512",
    );
}
