//! `obbcd bench`: every engine and parry3d on the surgical scene and on uniform scenes, in one
//! run, with the growth of the run time from the smallest to the largest uniform scene.

use crate::neighbour::Neighbour;
use crate::parry::ParryScene;
use crate::timing::{median, race, turn, warm_median_ms, Contender};
use anyhow::{Context, Result};
use clap::Args;
use obb_model::generate::{surgical, uniform, SURGICAL_DEFAULT_N, UNIFORM_DEFAULT_DENSITY};
use obb_model::sat::obbs_collide;
use obb_model::simd::Vectors;
use obb_model::{Counters, Engine, EngineKind, GroupMask, Pair, Prepared, Scene};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, SystemTime};

#[derive(Args)]
pub struct BenchArgs {
    /// Uniform scene sizes.
    #[arg(long, value_delimiter = ',', default_value = "1000,4000,16000,64000")]
    sizes: Vec<usize>,
    /// Surgical scene size.
    #[arg(long, default_value_t = SURGICAL_DEFAULT_N)]
    surgical_n: usize,
    /// Timed runs per measurement (the median is reported).
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Untimed runs before each measurement, for this long (ms; at least one run): the
    /// figures are of the steady state, as a loop running frame after frame sees it.
    #[arg(long, default_value_t = 300)]
    warmup_ms: u64,
    /// The grid (on all threads and on 1) and parry3d take turns of this long (ms), ...
    #[arg(long, default_value_t = 100)]
    turn_ms: u64,
    /// ... for at least this many rounds (and until each has `--repeat` timed runs).
    #[arg(long, default_value_t = 5)]
    rounds: usize,
    /// Races of the grid against parry3d per scene: each gives a speed-up of its own, and the
    /// `speedup` lines list them with their min, median and max (the table: the medians).
    #[arg(long, default_value_t = 1)]
    runs: usize,
    /// Quadratic engines (brute, sap, improved-sap) only up to this many boxes.
    #[arg(long, default_value_t = 20_000)]
    quadratic_max: usize,
    /// Also write the table as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// While the bench runs, a thread of its own reads random lines of a buffer of this many MB
    /// (eight chains of dependent loads), as a tenant of the CPU that keeps its own lines in
    /// the shared L3 does (12 MB brought about the slow spells of a shared Zen 3 machine). It
    /// needs a core beside the worker threads (`obbcd --threads N bench`, N below the cores).
    #[arg(long)]
    neighbour_mb: Option<usize>,
}

/// The grid's speed-up over parry3d (parry3d's median frame over the grid's) in each race on
/// one scene, with the grid on `threads` threads.
struct Speedup {
    scene: String,
    n: usize,
    groups: GroupMask,
    threads: usize,
    runs: Vec<f64>,
}

struct Row {
    scene: String,
    n: usize,
    groups: GroupMask,
    engine: String,
    threads: usize,
    ms: f64,
    pairs: usize,
    visits: u64,
}

/// Times `kind` alone on `scene`: the median of `--repeat` frames after `--warmup-ms`.
fn time_engine(
    kind: EngineKind,
    scene: &Scene,
    mask: &GroupMask,
    a: &BenchArgs,
) -> (f64, Vec<Pair>, u64) {
    let mut run = FrameLoop::new(kind);
    // The frame loop runs on a worker of the current pool, as a real-time loop should: a call
    // from outside the pool pays a thread wake-up per parallel phase (README, "Measured figures").
    let (ms, ()) = rayon::scope(|_| {
        warm_median_ms(Duration::from_millis(a.warmup_ms), a.repeat, || {
            run.frame(scene, mask)
        })
    });
    (ms, run.pairs, run.counters.visits)
}

/// One engine's frame loop, kept from frame to frame (and from turn to turn of a race).
struct FrameLoop {
    engine: Box<dyn Engine>,
    boxes: Prepared,
    pairs: Vec<Pair>,
    counters: Counters,
}

impl FrameLoop {
    fn new(kind: EngineKind) -> Self {
        FrameLoop {
            engine: kind.build(),
            boxes: Prepared::default(),
            pairs: Vec::new(),
            counters: Counters::default(),
        }
    }

    fn frame(&mut self, scene: &Scene, mask: &GroupMask) {
        let frame = self.boxes.update(&scene.obbs);
        self.counters = self.engine.detect(&frame, mask, &mut self.pairs);
    }
}

/// The grid on all threads, the grid on one (when there are more) and parry3d, timed in turns
/// (`race`): their ratios compare them over the same stretch of time. Returns the medians in
/// that order (two when there is one thread), the grid's pairs and visits, and parry3d's pairs.
fn race_grid(
    scene: &Scene,
    mask: &GroupMask,
    a: &BenchArgs,
    single: &rayon::ThreadPool,
) -> (Vec<f64>, (Vec<Pair>, u64), Vec<Pair>) {
    let (mut all, mut one) = (
        FrameLoop::new(EngineKind::Grid),
        FrameLoop::new(EngineKind::Grid),
    );
    let parry = ParryScene::new(scene);
    let mut parry_pairs = Vec::new();
    // Each runs its turns on a worker of its pool, as `time_engine` does.
    let mut on_all = |length, times: &mut Vec<f64>| {
        rayon::scope(|_| turn(length, times, || all.frame(scene, mask)));
    };
    let mut on_one = |length, times: &mut Vec<f64>| {
        single.install(|| rayon::scope(|_| turn(length, times, || one.frame(scene, mask))));
    };
    let mut on_parry = |length, times: &mut Vec<f64>| {
        turn(length, times, || parry.detect(mask, &mut parry_pairs));
    };
    let mut contenders: Vec<Contender> = vec![&mut on_all];
    if rayon::current_num_threads() > 1 {
        contenders.push(&mut on_one);
    }
    contenders.push(&mut on_parry);
    let medians = race(
        &mut contenders,
        Duration::from_millis(a.warmup_ms),
        a.repeat,
        a.rounds,
        Duration::from_millis(a.turn_ms),
    );
    drop(contenders);
    (medians, (all.pairs, all.counters.visits), parry_pairs)
}

fn bench_scene(
    name: &str,
    scene: &Scene,
    mask: &GroupMask,
    a: &BenchArgs,
    rows: &mut Vec<Row>,
    speedups: &mut Vec<Speedup>,
) -> Result<()> {
    let n = scene.obbs.len();
    let all_threads = rayon::current_num_threads();
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let mut reference: Option<Vec<Pair>> = None;
    let mut parry = None;
    let mut add = |engine: &str, threads, ms, pairs: &[Pair], visits| {
        rows.push(Row {
            scene: name.into(),
            n,
            groups: mask.clone(),
            engine: engine.into(),
            threads,
            ms,
            pairs: pairs.len(),
            visits,
        });
    };
    for kind in EngineKind::ALL {
        let quadratic = matches!(
            kind,
            EngineKind::Brute | EngineKind::Sap | EngineKind::ImprovedSap
        );
        if quadratic && n > a.quadratic_max {
            continue;
        }
        let pairs = if kind == EngineKind::Grid {
            // Each race's medians: the grid on all threads, on 1 (when more), parry3d last.
            let mut races = Vec::new();
            let mut found = None;
            for _ in 0..a.runs {
                let (medians, grid, pairs_parry) = race_grid(scene, mask, a, &single);
                races.push(medians);
                found = Some((grid, pairs_parry));
            }
            let ((pairs, visits), pairs_parry) = found.context("--runs is at least 1")?;
            let last = races[0].len() - 1;
            let over_races = |k: usize| median(&mut races.iter().map(|m| m[k]).collect::<Vec<_>>());
            let mut threads = vec![all_threads];
            if all_threads > 1 {
                threads.push(1);
            }
            for (k, &t) in threads.iter().enumerate() {
                add(kind.name(), t, over_races(k), &pairs, visits);
                speedups.push(Speedup {
                    scene: name.into(),
                    n,
                    groups: mask.clone(),
                    threads: t,
                    runs: races.iter().map(|m| m[last] / m[k]).collect(),
                });
            }
            parry = Some((over_races(last), pairs_parry));
            pairs
        } else {
            let (ms, pairs, visits) = time_engine(kind, scene, mask, a);
            add(kind.name(), all_threads, ms, &pairs, visits);
            pairs
        };
        match &reference {
            None => reference = Some(pairs),
            Some(r) => anyhow::ensure!(
                *r == pairs,
                "{kind} disagrees with the other engines on {name}"
            ),
        }
    }
    let (ms, pairs) = parry.context("the grid ran beside parry3d")?;
    add("parry3d", 1, ms, &pairs, 0);
    let ours = reference.context("at least one engine ran")?;
    report_disagreement(name, scene, mask, &ours, &pairs)
}

/// Relative size of single precision's rounding, with room: parry3d works in f32.
const F32_TOLERANCE: f64 = 1e-6;

/// Prints where parry3d (f32) and our engines (f64, conservative) disagree, and whether each
/// pair only parry3d reports is within f32 rounding of touching: it must collide once both
/// boxes grow by `F32_TOLERANCE` times the scene's extent. A pair beyond that would be one we
/// miss: an error.
fn report_disagreement(
    name: &str,
    scene: &Scene,
    mask: &GroupMask,
    ours: &[Pair],
    parry: &[Pair],
) -> Result<()> {
    let only = |x: &[Pair], y: &[Pair]| -> Vec<Pair> {
        x.iter()
            .filter(|p| y.binary_search(p).is_err())
            .copied()
            .collect()
    };
    let (only_parry, only_ours) = (only(parry, ours), only(ours, parry));
    let extent = scene
        .obbs
        .iter()
        .flat_map(|o| {
            o.center
                .iter()
                .map(|c| c.abs() + o.half.iter().sum::<f64>())
        })
        .fold(0.0, f64::max);
    let grow = F32_TOLERANCE * extent;
    let grown = |i: u32| {
        let mut o = scene.obbs[i as usize].clone();
        o.half = o.half.map(|h| h + grow);
        o
    };
    let near = only_parry
        .iter()
        .filter(|p| obbs_collide(&grown(p[0]), &grown(p[1])))
        .count();
    println!(
        "parry3d vs ours, {name} {} groups={mask}: only parry3d {} ({near} within {grow:.1e} of touching), only ours {}",
        scene.obbs.len(),
        only_parry.len(),
        only_ours.len()
    );
    anyhow::ensure!(
        near == only_parry.len(),
        "parry3d finds {} pairs on {name} that our engines miss by more than f32 rounding",
        only_parry.len() - near
    );
    Ok(())
}

/// When and where the figures were measured: they differ from CPU to CPU and from hour to hour
/// on a shared machine (README, "Measured figures"), so a run says which it was.
fn measured_on(neighbour_mb: Option<usize>) -> String {
    let beside = neighbour_mb
        .map(|mb| format!(", beside random reads over {mb} MB"))
        .unwrap_or_default();
    format!(
        "bench {}, {}, vector code {:?}, {} threads{beside}",
        humantime::format_rfc3339_seconds(SystemTime::now()),
        cpu().unwrap_or_else(|| "CPU unknown".into()),
        Vectors::detected(),
        rayon::current_num_threads()
    )
}

/// The CPU's name, family and model, as Linux's `/proc/cpuinfo` gives them (x86's numbering;
/// elsewhere only the fields there are).
fn cpu() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    let field = |key: &str| {
        info.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            (k.trim() == key).then(|| v.trim().to_string())
        })
    };
    let name = field("model name")?;
    Some(match (field("cpu family"), field("model")) {
        (Some(family), Some(model)) => format!("{name} (family {family}, model {model})"),
        _ => name,
    })
}

pub fn run(a: BenchArgs) -> Result<()> {
    anyhow::ensure!(a.runs >= 1, "--runs must be at least 1");
    let neighbour = a.neighbour_mb.map(Neighbour::beside_workers).transpose()?;
    println!("{}", measured_on(a.neighbour_mb));
    let mut rows = Vec::new();
    let mut speedups = Vec::new();
    let surg = surgical(a.surgical_n, 1)?;
    for mask in [GroupMask::All, GroupMask::Cross] {
        eprintln!("surgical {} groups={mask}", a.surgical_n);
        bench_scene("surgical", &surg, &mask, &a, &mut rows, &mut speedups)?;
    }
    for &n in &a.sizes {
        eprintln!("uniform {n}");
        let scene = uniform(n, 1, UNIFORM_DEFAULT_DENSITY)?;
        bench_scene(
            "uniform",
            &scene,
            &GroupMask::All,
            &a,
            &mut rows,
            &mut speedups,
        )?;
    }
    if let Some(n) = neighbour {
        let c = n.finish()?;
        println!(
            "neighbour: random reads over {} MB, a load every {:.1} ns in each of its chains ({:.1} s)",
            c.mb,
            c.ns_per_load(),
            c.elapsed.as_secs_f64()
        );
    }
    let mut table = String::from("scene,n,groups,engine,threads,time_ms,pairs,visits\n");
    for r in &rows {
        writeln!(
            table,
            "{},{},{},{},{},{:.3},{},{}",
            r.scene, r.n, r.groups, r.engine, r.threads, r.ms, r.pairs, r.visits
        )?;
    }
    print!("{table}");
    for s in &mut speedups {
        let list: Vec<String> = s.runs.iter().map(|r| format!("{r:.1}")).collect();
        // `median` sorts the runs: the least and the greatest are then at the ends.
        let mid = median(&mut s.runs);
        let (min, max) = (s.runs[0], s.runs[s.runs.len() - 1]);
        println!(
            "speedup {} {} groups={} threads={}: {}x (min {min:.1}, median {mid:.1}, max {max:.1})",
            s.scene,
            s.n,
            s.groups,
            s.threads,
            list.join(" ")
        );
    }
    // How the time grows over the uniform sizes: the exponent k in time ~ n^k.
    if let (Some(&lo), Some(&hi)) = (a.sizes.iter().min(), a.sizes.iter().max()) {
        if hi > lo {
            let at = |n, engine: &str, threads| {
                rows.iter()
                    .find(|r| {
                        r.scene == "uniform"
                            && r.n == n
                            && r.engine == engine
                            && r.threads == threads
                    })
                    .map(|r| r.ms)
            };
            for (engine, threads) in [
                ("grid", rayon::current_num_threads()),
                ("grid", 1),
                ("sweep", rayon::current_num_threads()),
                ("parry3d", 1),
            ] {
                if let (Some(t0), Some(t1)) = (at(lo, engine, threads), at(hi, engine, threads)) {
                    let k = (t1 / t0).ln() / (hi as f64 / lo as f64).ln();
                    println!("growth {engine} threads={threads}: {lo} -> {hi} boxes, {t0:.3} -> {t1:.3} ms, time ~ n^{k:.2}");
                }
            }
        }
    }
    if let Some(path) = &a.csv {
        std::fs::write(path, &table).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
