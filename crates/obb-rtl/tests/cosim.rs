//! The emitted core on whole scenes, through the test bench `sim/tb_obb_core.v`: in Verilator,
//! and in Icarus as a second opinion. Every frame's pair
//! stream (in order), counters and clock count must equal the bit-exact model's
//! (`obb_rtl::flow::cosim::compare`), as `obbcd cosim` checks them.

use crate::common::{self, cache};

use common::scenes::{
    dense, first, instruments, shared_buckets, stiff, three_groups, touching_pairs,
};
use obb_model::fixed::stream::{interleave, STREAM_WAYS};
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame};
use obb_model::generate::{surgical, SURGICAL_DEFAULT_N};
use obb_model::{GroupMask, Scene};
use obb_rtl::flow::cosim::{
    build, compare, frame_clocks, prepare, stimulus, Expected, Level, RunOptions, SimFrame, Taken,
};
use obb_rtl::flow::synth;
use obb_rtl::flow::verilator::{scratch_dir, Simulator};
use obb_rtl::flow::waves::Waves;
use std::time::Instant;

/// Simulates one frame of `scene` on `design` (the RTL for `cfg`, or its netlist at `Gates`)
/// and checks it against the model; `ready_every` throttles the pair stream.
#[allow(clippy::too_many_arguments)]
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
    let bench = build(design, level, sim, None, &cache()).unwrap();
    let dir = scratch_dir("cosim").unwrap();
    let stim = dir.join("stim.hex");
    std::fs::write(&stim, stimulus(&[(true, &boxes)], cfg)).unwrap();
    let run = model.map(|m| m.run());
    let clocks = frame_clocks(scene, cfg, run.as_ref()).unwrap();
    let pairs = run.as_ref().map_or(0, |r| r.reported());
    let opts = RunOptions {
        ready_every,
        timeout: 2 * (clocks + pairs * u64::from(ready_every)) + 10_000,
        ..RunOptions::default()
    };
    let start = Instant::now();
    let got = bench.run(&stim, 1, &opts, |_| {}).unwrap().remove(0);
    let secs = start.elapsed().as_secs_f64();
    let mut kept = None;
    let want = Expected::for_frame(run.as_ref(), &mut kept, scene, cfg).unwrap();
    if let Err(e) = compare(&got, &want, Taken::of(ready_every, cfg.lanes)) {
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

/// The default configuration (the grid, cross-group) from no box and one box to the whole
/// 17,500-OBB surgical scene, and buckets shared by two cells in every one of its 81 list
/// copies (entries forwarded, lists mixed, skipped and walked: `scenes::shared_buckets`).
#[test]
fn default_core_from_one_box_to_the_full_surgical_scene() {
    let cfg = HwConfig::default();
    assert_eq!(cfg.broad_phase, BroadPhase::Grid);
    let design = obb_rtl::flow::generate::core(&cfg).unwrap();
    let full = surgical(SURGICAL_DEFAULT_N, 1).unwrap();
    let scenes = [
        ("no box", Scene { obbs: vec![] }),
        ("one box", first(touching_pairs(), 1)),
        ("touching", touching_pairs()),
        ("surgical 1000", surgical(1000, 1).unwrap()),
        ("surgical 17500", full),
        ("shared buckets", shared_buckets()),
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

/// The sweep core (default formats) on the whole surgical scene, the stiff and extreme suite,
/// and the dense worst case with the receiver always ready and then taking a pair one clock in
/// 16 (fewer than the core finds): the FIFO fills, the broad phase stalls, and no pair is lost
/// or reordered.
#[test]
fn sweep_core_on_surgical_stiff_and_dense_scenes_with_back_pressure() {
    let cfg = HwConfig {
        broad_phase: BroadPhase::Sweep,
        ..HwConfig::default()
    };
    let design = obb_rtl::flow::generate::core(&cfg).unwrap();
    let run = |scene: &Scene, ready, name: &str| {
        cosim(
            &cfg,
            &design,
            Level::Rtl,
            Simulator::Verilator,
            scene,
            ready,
            name,
        )
    };
    run(
        &surgical(SURGICAL_DEFAULT_N, 1).unwrap(),
        1,
        "sweep, surgical 17500",
    );
    run(&stiff(), 1, "sweep, stiff");
    dense_under_back_pressure("sweep", |ready, name| run(&dense(400), ready, name));
}

/// The dense case, 400 boxes, with the receiver always ready and then taking a pair one clock
/// in 16 (`run(ready_every, name)`): the throttled run must take more clocks, else the
/// receiver never stalled the core and the case tested nothing.
fn dense_under_back_pressure(core: &str, run: impl Fn(u32, &str) -> SimFrame) {
    let free = run(1, &format!("{core}, dense 400"));
    let throttled = run(
        16,
        &format!("{core}, dense 400, pair_ready one clock in 16"),
    );
    assert!(
        throttled.cycles > free.cycles,
        "{core}: the receiver never stalled the core ({} cycles)",
        throttled.cycles
    );
}

/// The grid core on the whole 17,500-OBB surgical scene, all pairs; and, with 16 mm cells, the
/// dense case (its groups folded into the grid's three) with the receiver taking a pair one
/// clock in 16: the pair FIFO holds the SAT tests, their queue the walker, the credits the load
/// (the test bench offers each box until the core takes it), and no pair is lost or reordered.
#[test]
fn grid_core_on_all_pairs_and_under_back_pressure() {
    let all = HwConfig {
        groups: GroupMask::All,
        ..HwConfig::default()
    };
    let design = obb_rtl::flow::generate::core(&all).unwrap();
    cosim(
        &all,
        &design,
        Level::Rtl,
        Simulator::Verilator,
        &surgical(SURGICAL_DEFAULT_N, 1).unwrap(),
        1,
        "grid, surgical 17500, all pairs",
    );
    let dense_cfg = HwConfig {
        grid_cell_mm: 16.0,
        ..all
    };
    let design = obb_rtl::flow::generate::core(&dense_cfg).unwrap();
    let run = |ready, name: &str| {
        cosim(
            &dense_cfg,
            &design,
            Level::Rtl,
            Simulator::Verilator,
            &three_groups(dense(400)),
            ready,
            name,
        )
    };
    dense_under_back_pressure("grid", run);
}

/// Cores planned for their scenes (`obbcd plan`: narrower widths, the capacity, the broad phase
/// and the cell from the scene): each in Verilator on its scene equals the model, clock for
/// clock, and takes the clocks the plan reports.
#[test]
fn planned_cores_on_their_scenes() {
    use obb_model::fixed::plan::{plan, Aims};
    for (name, scene, groups) in [
        ("stiff, planned", stiff(), GroupMask::All),
        (
            "surgical 2000 cross-group, planned",
            surgical(2000, 3).unwrap(),
            GroupMask::Cross,
        ),
    ] {
        let aims = Aims {
            groups,
            ..Aims::default()
        };
        let p = plan(std::slice::from_ref(&scene), &aims).unwrap();
        assert_ne!(
            p.cfg.capacity,
            HwConfig::default().capacity,
            "{}",
            p.summary()
        );
        let design = obb_rtl::flow::generate::core(&p.cfg).unwrap();
        let got = cosim(
            &p.cfg,
            &design,
            Level::Rtl,
            Simulator::Verilator,
            &scene,
            1,
            name,
        );
        assert_eq!(got.cycles, p.scenes[0].clocks, "{name}: {}", p.summary());
        eprintln!("{name}: {}", p.summary());
    }
}

/// Resident tissue (`resident_groups = [0]`, cross-group, the default core otherwise) on the
/// surgical scene in Verilator, frames back to back: an update frame, haptic frames with the
/// instruments moving, a second update, a haptic frame after it; and the same with the pair
/// stream throttled. Every frame as the model's, the haptic frames' clocks
/// printed (the README's figures).
#[test]
fn resident_tissue_with_haptic_frames() {
    let cfg = HwConfig {
        resident_groups: vec![0],
        ..HwConfig::default()
    };
    let design = obb_rtl::flow::generate::core(&cfg).unwrap();
    let bench = build(&design, Level::Rtl, Simulator::Verilator, None, &cache()).unwrap();
    let scene = surgical(SURGICAL_DEFAULT_N, 1).unwrap();
    for ready_every in [1, 4] {
        let moved = |k: f64| {
            let mut m = instruments(&scene);
            for o in &mut m.obbs {
                o.center[0] += 0.2 * k;
                o.center[2] -= 0.1 * k;
            }
            m
        };
        let update = ModelFrame::new(&scene, &cfg).unwrap();
        let mut models = vec![("update", update.clone())];
        for k in 1..=3 {
            // The first in the scene's order, the others interleaved as the host streams them.
            let ways = if k == 1 { 1 } else { STREAM_WAYS };
            let m = interleave(&moved(k as f64), ways);
            let h = models.last().unwrap().1.haptic(&m).unwrap();
            models.push(("haptic", h));
        }
        models.push(("update", update.clone()));
        let m = interleave(&moved(4.0), STREAM_WAYS);
        models.push(("haptic", update.haptic(&m).unwrap()));
        let frames: Vec<(bool, &[_])> = models
            .iter()
            .map(|(_, m)| (m.resident.is_none(), m.streamed()))
            .collect();
        let dir = scratch_dir("cosim").unwrap();
        let stim = dir.join("stim.hex");
        std::fs::write(&stim, stimulus(&frames, &cfg)).unwrap();
        let runs: Vec<_> = models.iter().map(|(_, m)| m.run()).collect();
        let clocks: u64 = runs
            .iter()
            .map(|r| r.cycles.total + r.reported() * u64::from(ready_every))
            .sum();
        let opts = RunOptions {
            ready_every,
            timeout: 2 * clocks + 10_000,
            ..RunOptions::default()
        };
        let got = bench.run(&stim, frames.len(), &opts, |_| {}).unwrap();
        for (k, ((kind, m), (sim, run))) in models.iter().zip(got.iter().zip(&runs)).enumerate() {
            if let Err(e) = compare(sim, &Expected::of(run), Taken::of(ready_every, 1)) {
                panic!("ready one clock in {ready_every}, frame {k} ({kind}): {e}");
            }
            eprintln!(
                "ready one clock in {ready_every}, frame {k} ({kind}): {} boxes streamed, {} \
                 pairs, {} cycles",
                m.streamed().len(),
                sim.stream.len(),
                sim.cycles
            );
        }
        // A haptic frame streams the instruments only: far fewer clocks than an update.
        assert!(
            got[1].cycles < got[0].cycles * 2 / 3,
            "{:?}",
            runs[1].cycles
        );
    }
}

/// Small cores (capacity 512, all pairs), the sweep and the grid, equal to the model in
/// Verilator and, as a second opinion, in Icarus: the sweep on the touching, stiff and dense
/// scenes (boxes the default grid refuses: 240 mm long, groups beyond 2); the grid on the
/// touching cases and a surgical scene; each on a frame over capacity, which it flags,
/// reporting nothing (the grid after walking the boxes it took). Icarus runs the grid's 27
/// banks at under a hundred clocks a second, so the grid's longer frames run in Verilator
/// alone, here and in the other tests.
#[test]
fn small_cores_in_verilator_and_icarus() {
    // All pairs, as in `aborted_frames_give_the_whole_new_frame`: the two share the Verilator
    // builds.
    let grid = HwConfig {
        capacity: 512,
        groups: GroupMask::All,
        ..HwConfig::default()
    };
    let sweep = HwConfig {
        broad_phase: BroadPhase::Sweep,
        ..grid.clone()
    };
    // (name, scene, also in Icarus)
    let sweep_scenes = [
        ("touching", touching_pairs(), true),
        ("stiff", stiff(), true),
        ("dense 60", dense(60), true),
        (
            "surgical 600, over capacity",
            surgical(600, 2).unwrap(),
            true,
        ),
    ];
    let grid_scenes = [
        ("touching", touching_pairs(), true),
        ("surgical 300", surgical(300, 3).unwrap(), false),
        (
            "surgical 600, over capacity",
            surgical(600, 2).unwrap(),
            false,
        ),
    ];
    for (cfg, scenes) in [(&sweep, &sweep_scenes[..]), (&grid, &grid_scenes[..])] {
        let design = obb_rtl::flow::generate::core(cfg).unwrap();
        for (name, scene, icarus) in scenes {
            let name = format!("{}, {name}", cfg.broad_phase);
            let v = cosim(
                cfg,
                &design,
                Level::Rtl,
                Simulator::Verilator,
                scene,
                1,
                &name,
            );
            if *icarus {
                let i = cosim(cfg, &design, Level::Rtl, Simulator::Icarus, scene, 1, &name);
                assert_eq!(v, i, "{name}: Verilator and Icarus differ");
            }
        }
    }
}

/// `Bench::record`: a window of clocks at a depth, in VCD and FST, in Verilator and Icarus. The
/// window holds two value changes of the clock a clock (and the edges at its ends); depth 1 is
/// the test bench's signals only, depth 2 reaches into `obb_core`; FST is the smaller file.
#[test]
fn waves_record_a_window_at_a_depth() {
    let cfg = HwConfig {
        broad_phase: BroadPhase::Sweep,
        capacity: 256,
        ..HwConfig::default()
    };
    let design = obb_rtl::flow::generate::core(&cfg).unwrap();
    let (_, boxes) = prepare(&touching_pairs(), &cfg).unwrap();
    let dir = scratch_dir("waves").unwrap();
    let stim = dir.join("stim.hex");
    std::fs::write(&stim, stimulus(&[(true, &boxes)], &cfg)).unwrap();
    let (from, to) = (20, 60);
    let record = |sim: Simulator, file: &str, depth: u32| {
        let waves = Waves::new(&dir.join(file), from, Some(to), depth).unwrap();
        let bench = build(&design, Level::Rtl, sim, Some(waves.trace()), &cache()).unwrap();
        bench
            .record(&stim, 1, &RunOptions::default(), &waves, |_| {})
            .unwrap_or_else(|e| panic!("{sim:?} {file}: {e}"));
        waves.path
    };
    for sim in [Simulator::Verilator, Simulator::Icarus] {
        let vcd = std::fs::read_to_string(record(sim, "d1.vcd", 1)).unwrap();
        let times = vcd.lines().filter(|l| l.starts_with('#')).count() as u64;
        assert!(
            (2 * (to - from) - 1..=2 * (to - from) + 2).contains(&times),
            "{sim:?}: {times} time steps in a window of {} clocks",
            to - from
        );
        assert!(vcd.contains(" clock "), "{sim:?}: no clock in the VCD");
        assert!(
            !vcd.contains("module dut"),
            "{sim:?}: depth 1 reaches into the core"
        );
    }
    let deep = std::fs::read_to_string(record(Simulator::Icarus, "d2.vcd", 2)).unwrap();
    assert!(
        deep.contains("module dut"),
        "depth 2 does not reach the core"
    );
    let fst = std::fs::metadata(record(Simulator::Verilator, "d2.fst", 2)).unwrap();
    assert!(
        fst.len() > 0 && fst.len() < deep.len() as u64,
        "FST {} bytes, VCD {}",
        fst.len(),
        deep.len()
    );
}

/// yosys' netlist of a small sweep core (capacity 256, mapped for simulation: no block RAM,
/// see `synth::Mapping`), one synthesis for two checks. The gate-level run: the netlist in
/// Verilator, with yosys' models of the Virtex-6 primitives, equals the model (and so the RTL)
/// on the touching and stiff scenes, pairs, counters and cycles; that checks the DSP48E1
/// cascades and post-adders as yosys maps them. The analysis: it counts the same cells as
/// yosys' own `stat`, finds every DSP48E1 pipelined and some paths. Long (the synthesis and
/// the netlist's Verilator build take about ten minutes of the two cores): run with
/// `cargo test -p obb-rtl --test rtl -- --ignored cosim::the_netlist`.
#[test]
#[ignore = "long: yosys' synthesis of a core and its gate-level run (run with --ignored)"]
fn the_netlist_matches_the_model_and_the_analysis_counts_what_yosys_counts() {
    let cfg = HwConfig {
        capacity: 256,
        broad_phase: BroadPhase::Sweep,
        ..HwConfig::default()
    };
    let rtl = obb_rtl::flow::generate::core(&cfg).unwrap();
    let (dir, _) = synth::netlist(
        &rtl,
        "obb_core",
        synth::Mapping::Simulation,
        &cache().join("synth"),
    )
    .unwrap();
    let gates = std::fs::read_to_string(dir.join("syn.v")).unwrap();
    for (name, scene) in [("touching", touching_pairs()), ("stiff", stiff())] {
        let rtl_frame = cosim(
            &cfg,
            &rtl,
            Level::Rtl,
            Simulator::Verilator,
            &scene,
            1,
            name,
        );
        let gate_frame = cosim(
            &cfg,
            &gates,
            Level::Gates,
            Simulator::Verilator,
            &scene,
            1,
            name,
        );
        assert!(
            gate_frame.sat_tests > 0,
            "{name}: the SAT's DSPs were exercised"
        );
        assert_eq!(
            gate_frame, rtl_frame,
            "{name}: the netlist and the RTL differ"
        );
    }
    let report = synth::analyze(&dir.join("net.json"), "obb_core").unwrap();
    let stat = std::fs::read_to_string(dir.join("stat.txt")).unwrap();
    let yosys = |cell: &str| -> u64 {
        stat.lines()
            .filter_map(|l| {
                let mut w = l.split_whitespace();
                (w.next() == Some(cell)).then(|| w.next()?.parse::<u64>().ok())?
            })
            .sum()
    };
    let r = &report.resources;
    assert_eq!(r.dsp, yosys("DSP48E1"), "DSP48E1 in {stat}");
    assert_eq!(r.ramb36, yosys("RAMB36E1"), "RAMB36E1");
    assert_eq!(r.ramb18, yosys("RAMB18E1"), "RAMB18E1");
    assert_eq!(r.carry4, yosys("CARRY4"), "CARRY4");
    let luts: u64 = ["LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6", "INV"]
        .map(yosys)
        .iter()
        .sum();
    assert_eq!(r.luts, luts, "LUTs");
    let flops: u64 = ["FDRE", "FDSE", "FDCE", "FDPE"].map(yosys).iter().sum();
    assert_eq!(r.registers, flops, "registers");
    // A RAM32M or RAM64M is four LUTs of a SLICEM, a RAM64X1D two, a shift register one.
    let sum = |cells: &[&str]| -> u64 { cells.iter().map(|c| yosys(c)).sum() };
    let lutram = 4 * sum(&["RAM32M", "RAM64M", "RAM128X1D", "RAM256X1S"])
        + 2 * sum(&["RAM32X1D", "RAM64X1D", "RAM128X1S"])
        + sum(&["RAM32X1S", "RAM64X1S", "SRL16E", "SRLC32E"]);
    assert_eq!(r.lutram, lutram, "LUTs as memory");
    assert!(r.dsp > 0, "DSP48E1s in {stat}");
    assert_eq!(
        (report.dsp_without_mreg, report.dsp_without_preg),
        (0, 0),
        "every DSP48E1 has MREG and PREG"
    );
    let w = &report.worst;
    assert!(
        w.delay_ns > 0.0 && !w.from.is_empty() && !w.to.is_empty(),
        "{w:?}"
    );
    assert!(
        report.deepest.luts >= w.luts,
        "the deepest path has the most LUT levels"
    );
    eprintln!("{report:?}");
}

/// A `frame_start` in the middle of a frame aborts it (docs/hardware.md, "Abort"). Each broad
/// phase (capacity 512, a surgical scene of 300 boxes) runs three frames, each aborted once at
/// the same clock of it and sent again whole: in the load, in the walk, and near the end; the
/// receiver always ready and taking a pair one clock in 4. Before the abort the core offers
/// only true pairs of the old frame; after it, nothing of the old frame: the frame sent again
/// is whole and equal to the model's, pairs, order, counters and cycles. With resident tissue
/// (the grid, `resident_groups = [0]`), an aborted update frame and haptic frames after it; and
/// a haptic frame with no whole update frame before it is refused (`capacity_exceeded`), for
/// its resident boxes are unsure.
#[test]
fn aborted_frames_give_the_whole_new_frame() {
    let base = HwConfig {
        capacity: 512,
        ..HwConfig::default()
    };
    let scene = surgical(300, 3).unwrap();
    let dir = scratch_dir("cosim").unwrap();
    let stim = dir.join("stim.hex");
    let phases = [
        BroadPhase::Brute,
        BroadPhase::Sweep,
        BroadPhase::ImprovedSap,
        BroadPhase::Grid,
    ];
    for broad_phase in phases {
        let cfg = HwConfig {
            broad_phase,
            groups: GroupMask::All,
            ..base.clone()
        };
        let design = obb_rtl::flow::generate::core(&cfg).unwrap();
        let bench = build(&design, Level::Rtl, Simulator::Verilator, None, &cache()).unwrap();
        let model = ModelFrame::new(&scene, &cfg).unwrap();
        let run = model.run();
        let total = run.cycles.total;
        std::fs::write(&stim, stimulus(&[(true, model.streamed()); 3], &cfg)).unwrap();
        for ready_every in [1, 4] {
            for abort_at in [3, total / 2, total - 20] {
                let opts = RunOptions {
                    ready_every,
                    timeout: 20 * (total + run.reported() * u64::from(ready_every)) + 10_000,
                    abort_at,
                    ..RunOptions::default()
                };
                let got = bench.run(&stim, 3, &opts, |_| {}).unwrap();
                for (k, frame) in got.iter().enumerate() {
                    let what = format!(
                        "{broad_phase}, ready 1 in {ready_every}, aborted at clock {abort_at}, \
                         frame {k}"
                    );
                    let before = frame.before_abort.as_ref();
                    assert!(before.is_some(), "{what}: not aborted");
                    let taken = Taken::of(ready_every, cfg.lanes);
                    if let Err(e) = compare(frame, &Expected::of(&run), taken) {
                        panic!("{what}: {e}");
                    }
                    eprintln!(
                        "{what}: {} pairs before the abort, then {} pairs, {} cycles",
                        before.map_or(0, Vec::len),
                        frame.stream.len(),
                        frame.cycles
                    );
                }
            }
        }
    }
    // Resident tissue: update (aborted), haptic, haptic; then a core whose first frame is
    // haptic.
    let cfg = HwConfig {
        resident_groups: vec![0],
        ..base
    };
    let design = obb_rtl::flow::generate::core(&cfg).unwrap();
    let bench = build(&design, Level::Rtl, Simulator::Verilator, None, &cache()).unwrap();
    let update = ModelFrame::new(&scene, &cfg).unwrap();
    let haptic = update.haptic(&instruments(&scene)).unwrap();
    let runs = [update.run(), haptic.run(), haptic.run()];
    let frames = [
        (true, update.streamed()),
        (false, haptic.streamed()),
        (false, haptic.streamed()),
    ];
    std::fs::write(&stim, stimulus(&frames, &cfg)).unwrap();
    let opts = RunOptions {
        timeout: 100 * runs[0].cycles.total + 10_000,
        abort_at: runs[0].cycles.total / 2,
        ..RunOptions::default()
    };
    let got = bench.run(&stim, 3, &opts, |_| {}).unwrap();
    assert!(got[0].before_abort.is_some(), "the update frame is aborted");
    for (k, (frame, run)) in got.iter().zip(&runs).enumerate() {
        if let Err(e) = compare(frame, &Expected::of(run), Taken::Freely) {
            panic!("resident tissue, frame {k}: {e}");
        }
    }
    std::fs::write(&stim, stimulus(&frames[1..], &cfg)).unwrap();
    let got = bench.run(&stim, 2, &RunOptions::default(), |_| {}).unwrap();
    for (k, frame) in got.iter().enumerate() {
        if let Err(e) = compare(frame, &Expected::OverCapacity, Taken::Freely) {
            panic!("haptic frame {k} with no update frame before it: {e}");
        }
    }
}
