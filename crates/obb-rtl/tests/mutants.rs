//! Mutation testing of the core's emitted Verilog (`scripts/mutants.sh` runs it; out of the
//! default suite, for each mutant takes a Verilator build of the whole core). A sample of the
//! single mutants of the default core (`mutation::mutants`: a compare, an operator, a constant
//! +-1, a negated condition, two wires swapped, a register bypassed) each runs frames against
//! the bit-exact model: the touching cases, the whole 17,500-box surgical scene, the stiff
//! cases, the surgical contact, the dense case, boxes larger than a cell (the grid's slow path),
//! small boxes of three groups close together and spread wide, back to back with the pair
//! stream taken freely (pairs in order, counters, clock count); then the dense case, the large
//! boxes and the close small ones with it taken one clock in three. A mutant is killed when a
//! frame differs, the run fails or never finishes; it survives when every frame agrees. Its
//! Verilator build gets a directory of its own, removed after the run.
//!
//! The default tests here check the mutator itself on the default core's Verilog.

mod common;
mod mutation;

use common::scenes::{dense, stiff, surgical_contact, three_groups, touching_pairs};
use mutation::{mutants, Kind, Mutant};
use obb_model::fixed::{HwConfig, ModelRun, QObb};
use obb_model::generate::{surgical, uniform, SURGICAL_DEFAULT_N};
use obb_model::{Obb, Scene};
use obb_rtl::flow::cosim::{build, compare, prepare, stimulus, Expected, Level, RunOptions, Taken};
use obb_rtl::flow::generate;
use obb_rtl::flow::verilator::Simulator;
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Every kind of mutant is made on the default core, each changes only its own lines (one, or
/// two for a swap, which exchanges their right-hand sides; checked on a sample), and the
/// operators and constants are found where they stand in the key check's overlap expression.
#[test]
fn the_mutator_makes_each_kind_of_single_mutant() {
    let verilog = generate::core(&HwConfig::default()).unwrap();
    let all = mutants(&verilog);
    let lines: Vec<&str> = verilog.lines().collect();
    let mut by_kind = BTreeMap::new();
    for (k, m) in all.iter().enumerate() {
        *by_kind.entry(m.kind).or_insert(0) += 1;
        let edited: Vec<usize> = m.edits.iter().map(|e| e.0).collect();
        assert_eq!(edited.len(), 1 + usize::from(m.kind == Kind::Swap));
        for (at, line) in &m.edits {
            assert_ne!(lines[*at], line, "{}", m.describe(&verilog));
        }
        // Applying one copies the whole core: every 97th is checked for touching nothing else.
        if k % 97 == 0 {
            let changed: Vec<usize> = m
                .apply(&verilog)
                .lines()
                .zip(&lines)
                .enumerate()
                .filter(|(_, (a, b))| a != *b)
                .map(|(k, _)| k)
                .collect();
            assert_eq!(changed, edited, "{}", m.describe(&verilog));
        }
    }
    eprintln!("{} mutants of the default core: {by_kind:?}", all.len());
    for kind in Kind::ALL {
        assert!(
            by_kind.get(&kind).is_some_and(|&n| n > 0),
            "no {kind} mutant"
        );
    }
    let overlap = lines
        .iter()
        .position(|l| {
            l.trim_start()
                .starts_with("overlap = (key_min_a$0$q <= key_max_b$0$q)")
        })
        .expect("the key check's overlap expression");
    let here: Vec<String> = all
        .iter()
        .filter(|m| m.edits[0].0 == overlap)
        .map(|m| format!("{} {}", m.kind, m.edits[0].1.trim()))
        .collect();
    // Six `<=` compares, each made `<`, and five `&`s made `|`.
    assert_eq!(here.len(), 11, "{here:#?}");
    assert!(here[0].starts_with("compare overlap = (key_min_a$0$q < key_max_b$0$q) &"));
    assert!(here.iter().any(|h| h.starts_with(
        "logic overlap = (key_min_a$0$q <= key_max_b$0$q) | (key_min_b$0$q <= key_max_a$0$q) &"
    )));
}

#[test]
fn constants_move_by_one_within_their_width_and_swaps_keep_widths() {
    let verilog = "module m(clock,a,b,c);
    input wire  clock;
    input wire  [3:0] a;
    input wire  [3:0] b;
    output reg  [3:0] c;
    reg  [3:0] d;
    reg  e;
    localparam  mode = 1'b1;
    // Update code
    always @(*) begin
        c = a;
        d = b;
        e = a[32'h0];
        if (a == 4'hf) begin
            c = ~b + 4'h3;
        end
    end
endmodule
";
    let got: Vec<String> = mutants(verilog)
        .iter()
        .map(|m| format!("{} {}", m.kind, m.describe(verilog)))
        .collect();
    let want = [
        "constant m line 8 constant: `localparam  mode = 1'b1;` -> `localparam  mode = 1'b0;`",
        "swap m line 11 swap: `c = a;` -> `c = b;`, `d = b;` -> `d = a;`",
        "constant m line 13 constant: `e = a[32'h0];` -> `e = a[32'h1];`",
        "condition m line 14 condition: `if (a == 4'hf) begin` -> `if (!(a == 4'hf)) begin`",
        "compare m line 14 compare: `if (a == 4'hf) begin` -> `if (a != 4'hf) begin`",
        "constant m line 14 constant: `if (a == 4'hf) begin` -> `if (a == 4'he) begin`",
        "invert m line 15 invert: `c = ~b + 4'h3;` -> `c = b + 4'h3;`",
        "arithmetic m line 15 arithmetic: `c = ~b + 4'h3;` -> `c = ~b - 4'h3;`",
        "constant m line 15 constant: `c = ~b + 4'h3;` -> `c = ~b + 4'h4;`",
    ];
    assert_eq!(got, want);
}

/// A run of frames back to back with the pair stream taken one clock in `ready_every`.
struct Run {
    ready_every: u32,
    stim: String,
    frames: Vec<(String, ModelRun)>,
    timeout: u64,
}

/// The surgical contact scene with instrument boxes larger than the default 2 mm cell (3 to 12
/// cells on each axis, rotated), which the grid's slow path takes, among the tissue's boxes.
fn with_large_boxes(mut scene: Scene) -> Scene {
    let halves = [
        [6.0, 2.0, 1.5],
        [1.5, 6.0, 2.0],
        [2.0, 1.5, 6.0],
        [3.0, 3.0, 3.0],
    ];
    let n = scene.obbs.len();
    for (k, half) in halves.iter().enumerate() {
        let at = scene.obbs[k * n / halves.len()].center;
        let mut b = Obb::aligned(at, *half, 1 + k as u32 % 2);
        let (s, c) = (0.4 * k as f64 + 0.3).sin_cos();
        b.axes = [
            [c, s, 0.0],
            [-s * 0.6, c * 0.6, 0.8],
            [s * 0.8, -c * 0.8, 0.6],
        ];
        scene.obbs.insert(k * n / halves.len(), b);
    }
    scene
}

/// 600 boxes with half-lengths of 0.15 to 0.45 mm, rotated at random, in a 6.4 mm cube, in
/// groups 0, 1, 2 in turn: boxes smaller than a cell, each in its home cell's list, and 993
/// pairs of every two groups (the surgical scenes' cross-group pairs are all with group 0).
fn scattered() -> Scene {
    let mut s = uniform(600, 7, 0.5).expect("a uniform scene");
    for (i, o) in s.obbs.iter_mut().enumerate() {
        o.group = i as u32 % 3;
        o.center = o.center.map(|c| 0.3 * c);
        o.half = o.half.map(|h| 0.3 * h);
    }
    s
}

/// 3,000 boxes as small, in groups 0, 1, 2 in turn, spread over a 36 mm cube (about 6,000
/// cells): lists of every group whose buckets hold boxes of two cells (their fingerprints
/// differ), which the walkers must skip or, once mixed, walk.
fn spread() -> Scene {
    let mut s = uniform(3000, 11, 0.5).expect("a uniform scene");
    for (i, o) in s.obbs.iter_mut().enumerate() {
        o.group = i as u32 % 3;
        o.half = o.half.map(|h| 0.3 * h);
    }
    s
}

fn runs(cfg: &HwConfig) -> Vec<Run> {
    let scenes: [(&str, Scene); 8] = [
        ("touching", touching_pairs()),
        (
            "surgical 17500",
            surgical(SURGICAL_DEFAULT_N, 1).expect("the built-in surgical scene"),
        ),
        ("stiff", stiff()),
        ("surgical contact 300", surgical_contact(300)),
        ("dense 100", three_groups(dense(100))),
        ("large boxes", with_large_boxes(surgical_contact(300))),
        ("scattered 600", scattered()),
        ("spread 3000", spread()),
    ];
    let prepared: Vec<(&str, Vec<QObb>, ModelRun)> = scenes
        .iter()
        .map(|(name, scene)| {
            let (model, boxes) = prepare(scene, cfg).unwrap();
            let model = model.expect("the suite's scenes fit the default core");
            (*name, boxes, model.run())
        })
        .collect();
    // All of them taken freely; the dense, large and close small boxes throttled.
    [(1, &prepared[..]), (3, &prepared[4..7])]
        .into_iter()
        .map(|(ready_every, frames)| {
            let timeout = 10_000
                + frames
                    .iter()
                    .map(|(_, _, run)| {
                        2 * (run.cycles.total + run.reported() * u64::from(ready_every))
                    })
                    .sum::<u64>();
            let bench: Vec<_> = frames
                .iter()
                .map(|(_, b, _)| (true, b.as_slice()))
                .collect();
            Run {
                ready_every,
                stim: stimulus(&bench, cfg),
                frames: frames
                    .iter()
                    .map(|(name, _, run)| (name.to_string(), run.clone()))
                    .collect(),
                timeout,
            }
        })
        .collect()
}

/// What became of a mutant.
enum Verdict {
    Killed(String),
    Survived,
    /// Verilator would not build it.
    Invalid(String),
}

fn first_line(e: impl std::fmt::Display) -> String {
    e.to_string()
        .lines()
        .next()
        .unwrap_or("")
        .chars()
        .take(160)
        .collect()
}

/// Builds `design` in `cache` and runs the suite on it.
fn judge(design: &str, cfg: &HwConfig, suite: &[Run], cache: &Path) -> Verdict {
    let bench = match build(design, Level::Rtl, Simulator::Verilator, None, cache) {
        Ok(b) => b,
        Err(e) => return Verdict::Invalid(first_line(format!("{e:#}"))),
    };
    for (k, run) in suite.iter().enumerate() {
        let stim = cache.join(format!("stim{k}.hex"));
        std::fs::write(&stim, &run.stim).unwrap();
        let opts = RunOptions {
            ready_every: run.ready_every,
            timeout: run.timeout,
            ..RunOptions::default()
        };
        let got = match bench.run(&stim, run.frames.len(), &opts, |_| {}) {
            Ok(g) => g,
            Err(e) => return Verdict::Killed(first_line(format!("{e:#}"))),
        };
        for ((name, want), got) in run.frames.iter().zip(&got) {
            let taken = Taken::of(run.ready_every, cfg.lanes);
            if let Err(e) = compare(got, &Expected::of(Some(want)), taken) {
                let how = format!("ready 1/{}", run.ready_every);
                return Verdict::Killed(format!("{name}, {how}: {}", first_line(e)));
            }
        }
    }
    Verdict::Survived
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name}={v} is not a number"))
        })
        .unwrap_or(default)
}

/// The sample: `MUTANTS` mutants (default 40) drawn with seed `MUTANTS_SEED` (default 1) from
/// those whose module or kind contains `MUTANTS_MATCH` (default: all); of it, with
/// `MUTANTS_ONLY` (numbers as the run prints them, e.g. `7,12`), only those.
#[test]
#[ignore = "mutation testing: about 26 s a mutant; scripts/mutants.sh runs it"]
fn mutants_of_the_default_core() {
    let cfg = HwConfig::default();
    let verilog = generate::core(&cfg).unwrap();
    let count: usize = env_or("MUTANTS", 40);
    let seed: u64 = env_or("MUTANTS_SEED", 1);
    let pattern = std::env::var("MUTANTS_MATCH").unwrap_or_default();
    let all: Vec<Mutant> = mutants(&verilog)
        .into_iter()
        .filter(|m| m.module.contains(&pattern) || m.kind.to_string() == pattern)
        .collect();
    let mut rng = StdRng::seed_from_u64(seed);
    let mut picked = rand::seq::index::sample(&mut rng, all.len(), count.min(all.len())).into_vec();
    picked.sort_unstable();
    if let Ok(only) = std::env::var("MUTANTS_ONLY") {
        let keep: Vec<usize> = only
            .split(',')
            .map(|n| match n.trim().parse::<usize>() {
                Ok(n) if (1..=picked.len()).contains(&n) => picked[n - 1],
                _ => panic!(
                    "MUTANTS_ONLY: `{n}` is not a number from 1 to {}",
                    picked.len()
                ),
            })
            .collect();
        picked = keep;
    }
    eprintln!(
        "{} of {} mutants (seed {seed}, match `{pattern}`)",
        picked.len(),
        all.len()
    );

    let suite = runs(&cfg);
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    match judge(&verilog, &cfg, &suite, &root.join("cosim-cache")) {
        Verdict::Survived => {}
        Verdict::Killed(e) | Verdict::Invalid(e) => panic!("the unmutated core fails: {e}"),
    }
    let start = Instant::now();
    let mut tally: BTreeMap<Kind, [usize; 3]> = BTreeMap::new();
    let mut survivors = Vec::new();
    for (n, &k) in picked.iter().enumerate() {
        let m = &all[k];
        let dir = root.join(format!("mutant-{}", std::process::id()));
        let t = Instant::now();
        let verdict = judge(&m.apply(&verilog), &cfg, &suite, &dir);
        let _ = std::fs::remove_dir_all(&dir);
        let (slot, word, why) = match &verdict {
            Verdict::Killed(e) => (0, "killed", e.as_str()),
            Verdict::Survived => (1, "SURVIVED", ""),
            Verdict::Invalid(e) => (2, "invalid", e.as_str()),
        };
        tally.entry(m.kind).or_default()[slot] += 1;
        if slot == 1 {
            survivors.push(m.describe(&verilog));
        }
        eprintln!(
            "[{}/{}] {word} ({:.0} s) {}{}{why}",
            n + 1,
            picked.len(),
            t.elapsed().as_secs_f64(),
            m.describe(&verilog),
            if why.is_empty() { "" } else { " :: " },
        );
    }
    let killed: usize = tally.values().map(|t| t[0]).sum();
    let survived: usize = tally.values().map(|t| t[1]).sum();
    let invalid: usize = tally.values().map(|t| t[2]).sum();
    eprintln!("\nkind: killed survived invalid");
    for (kind, t) in &tally {
        eprintln!("{kind}: {} {} {}", t[0], t[1], t[2]);
    }
    let judged = killed + survived;
    eprintln!(
        "mutants={} killed={killed} survived={survived} invalid={invalid} killed_pct={:.1} \
         s_per_mutant={:.1}",
        picked.len(),
        100.0 * killed as f64 / judged.max(1) as f64,
        start.elapsed().as_secs_f64() / picked.len().max(1) as f64
    );
    for s in &survivors {
        eprintln!("survivor: {s}");
    }
}
