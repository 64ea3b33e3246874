//! Mutation testing of the core's emitted Verilog (`scripts/mutants.sh` runs it; out of the
//! default suite, for each mutant takes a Verilator build of the whole core). A sample of the
//! single mutants of the default core (`mutation::mutants`: a compare, an operator, a constant
//! +-1, a negated condition, two wires swapped, a register bypassed) each runs frames against
//! the bit-exact model: the touching cases, the whole 17,500-box surgical scene, the stiff
//! cases, the surgical contact, the dense case, boxes larger than a cell (the grid's slow path),
//! small boxes of three groups close together and spread wide, buckets shared by two cells in
//! every list copy of the grid, back to back with the pair stream taken freely (pairs in order,
//! counters, clock count); then the dense case, the large boxes, the close small ones and the
//! shared buckets with it taken one clock in three. A mutant of the SAT that every frame passes
//! then runs in the standalone SAT, every axis' sides compared (the frames compare verdicts,
//! behind the margins' slack). A mutant is killed when a frame or a side differs, the run fails
//! or never finishes; it survives when all agree. Its Verilator builds get a directory of their
//! own, removed after the run.
//!
//! The default tests here check the mutator itself on the default core's Verilog.

use crate::common;
use crate::mutation;

use common::scenes::{
    dense, shared_buckets, stiff, surgical_contact, three_groups, touching_pairs,
};
use common::whole_sat::{self, SIDES_AT};
use common::{disagreement, pairs, sat_sides};
use mutation::{mutants, Kind, Mutant};
use obb_model::fixed::grid::{GridShape, BANKS};
use obb_model::fixed::grid_clocks::grid_schedule;
use obb_model::fixed::{keys, project, HwConfig, Margins, ModelFrame, ModelRun, QObb};
use obb_model::generate::{surgical, uniform, SURGICAL_DEFAULT_N};
use obb_model::{Obb, Scene};
use obb_rtl::flow::cosim::{build, compare, prepare, stimulus, Expected, Level, RunOptions, Taken};
use obb_rtl::flow::verilator::Simulator;
use obb_rtl::flow::{emit, generate};
use obb_rtl::sat::Sat;
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::collections::{BTreeMap, BTreeSet, HashMap};
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

/// The core's SAT is the standalone SAT's Verilog line for line (modules `obb_core$sat...`
/// and `sat...`), so that a mutant of the core's SAT moves to the standalone one, whose sides
/// the script compares; the standalone SAT is built for the default formats at the LSB of the
/// scene it is run on, which the Verilog does not hold.
#[test]
fn the_cores_sat_is_the_standalone_sat() {
    let core = generate::core(&HwConfig::default()).unwrap();
    let sat = standalone_sat().verilog;
    // Per module named `<prefix>sat...`, its lines with the prefix taken out of every name.
    let modules = |verilog: &str, prefix: &str| -> BTreeMap<String, Vec<String>> {
        let mut out: BTreeMap<String, Vec<String>> = BTreeMap::new();
        let mut within: Option<String> = None;
        for line in verilog.lines() {
            let line = line.replace(&format!("{prefix}sat"), "sat");
            if let Some(rest) = line.strip_prefix("module ") {
                let name = rest.split('(').next().unwrap_or(rest);
                within = (name == "sat" || name.starts_with("sat$")).then(|| name.to_string());
            }
            if let Some(name) = &within {
                let end = line.starts_with("endmodule");
                out.entry(name.clone()).or_default().push(line);
                if end {
                    within = None;
                }
            }
        }
        out
    };
    let in_core = modules(&core, "obb_core$");
    let alone = modules(&sat, "");
    assert!(
        in_core.len() > 100,
        "{} SAT modules in the core",
        in_core.len()
    );
    assert_eq!(
        in_core.keys().collect::<Vec<_>>(),
        alone.keys().collect::<Vec<_>>()
    );
    for (name, lines) in &in_core {
        let other = &alone[name];
        let differ = (0..lines.len().max(other.len())).find(|&k| lines.get(k) != other.get(k));
        assert_eq!(differ, None, "module {name}: a line differs");
    }
}

/// The shared-bucket frame does in every one of the default grid's 81 list copies (27 banks x
/// 3 groups) what `shared_buckets` says, by the model's keys, cells and acceptance clocks: two
/// boxes of one cell entering on consecutive clocks; a pure list probed from another cell, on
/// the clock after an entry (its head forwarded) and later (read from the table); a list mixed
/// by the entry of the clock before (forwarded) and one mixed by an entry read from the table,
/// each then probed from both of its cells (from its first cell, a list taken as pure would be
/// skipped: the pairs there are found only if it is mixed), the first on the clock after it
/// was mixed.
#[test]
fn shared_buckets_reach_every_list_copy() {
    let cfg = HwConfig::default();
    let (model, boxes) = prepare(&shared_buckets(), &cfg).unwrap();
    let model = model.expect("the scene fits the default core");
    let accepts = grid_schedule(&model.grid_walk(&cfg.groups)).accepts;
    let shape = GridShape::new(&cfg);
    let margins = Margins::new(&cfg);
    // Per box: its home cell's bank, its group, the cell's bucket and fingerprint.
    let homes: Vec<(usize, u32, usize, usize)> = boxes
        .iter()
        .map(|b| {
            let (lo, hi) = keys(&project(b, &cfg, &margins), &cfg);
            assert!(shape.is_small(&lo, &hi), "a box of one cell");
            let home = shape.home(&lo);
            let bank = GridShape::bank(&home);
            (bank, b.group, shape.bucket(&home), shape.fingerprint(&home))
        })
        .collect();
    // Per list (bank, group, bucket): the first fingerprint and, once another entered, how and
    // its fingerprint.
    type Mixed = Option<(&'static str, usize)>;
    let mut lists: HashMap<(usize, u32, usize), (usize, Mixed)> = HashMap::new();
    let mut befell: BTreeMap<(usize, u32), BTreeSet<String>> = BTreeMap::new();
    for (i, &(bank, g, bucket, fp)) in homes.iter().enumerate() {
        // The box before, if it was taken on the clock before.
        let before = (i > 0 && accepts[i] == accepts[i - 1] + 1).then(|| homes[i - 1]);
        // Cross-group: the box probes its home cell's lists of the other groups.
        for h in (0..3).filter(|&h| h != g) {
            let event = match lists.get(&(bank, h, bucket)) {
                Some(&(owner, None)) if owner != fp => {
                    "a pure list probed from another cell".into()
                }
                Some(&(owner, Some((how, second)))) if fp == owner || fp == second => {
                    let from = if fp == owner { "first" } else { "second" };
                    format!("mixed by {how}, probed from its {from} cell")
                }
                _ => continue,
            };
            let event = match before {
                Some((b, g, u, _)) if (b, g, u) == (bank, h, bucket) => {
                    format!("{event}, on the clock after an entry")
                }
                _ => event,
            };
            befell.entry((bank, h)).or_default().insert(event);
        }
        let forwarded = before.is_some_and(|(b, h, u, _)| (b, h, u) == (bank, g, bucket));
        if forwarded && homes[i - 1].3 == fp {
            let events = befell.entry((bank, g)).or_default();
            events.insert("two boxes of a cell on consecutive clocks".into());
        }
        let list = lists.entry((bank, g, bucket)).or_insert((fp, None));
        if list.0 != fp && list.1.is_none() {
            let how = if forwarded {
                "the entry of the clock before"
            } else {
                "a stored entry"
            };
            list.1 = Some((how, fp));
        }
    }
    let wanted = [
        "two boxes of a cell on consecutive clocks",
        "a pure list probed from another cell, on the clock after an entry",
        "a pure list probed from another cell",
        "mixed by the entry of the clock before, probed from its second cell, on the clock after \
         an entry",
        "mixed by the entry of the clock before, probed from its first cell",
        "mixed by a stored entry, probed from its first cell",
        "mixed by a stored entry, probed from its second cell",
    ];
    assert_eq!(befell.len(), BANKS * 3, "list copies reached");
    for (copy, events) in &befell {
        for want in wanted {
            assert!(
                events.contains(want),
                "bank and group {copy:?}: not `{want}` but {events:#?}"
            );
        }
    }
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
    let scenes: [(&str, Scene); 9] = [
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
        ("shared buckets", shared_buckets()),
    ];
    let prepared: Vec<(&str, Vec<QObb>, ModelRun)> = scenes
        .iter()
        .map(|(name, scene)| {
            let (model, boxes) = prepare(scene, cfg).unwrap();
            let model = model.expect("the suite's scenes fit the default core");
            (*name, boxes, model.run())
        })
        .collect();
    // All of them taken freely; the dense, large and close small boxes and the shared buckets
    // throttled.
    let throttled: Vec<_> = [4, 5, 6, 8].map(|k| prepared[k].clone()).into();
    [(1, &prepared[..]), (3, &throttled[..])]
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

/// The standalone SAT and a run of it: 300 pairs reported and 300 separated of a surgical
/// scene, with every axis' sides compared (`tests/sat.rs`).
struct SatSides {
    verilog: String,
    stim: sat_sides::Stimulus,
}

fn standalone_sat() -> SatSides {
    let scene = surgical(600, 9).expect("a surgical scene");
    let cfg = HwConfig::default().fitted(&scene);
    let m = ModelFrame::new(&scene, &cfg).expect("the scene fits");
    SatSides {
        verilog: emit::verilog(&mut Sat::new(&cfg), "sat").unwrap(),
        stim: whole_sat::stimulus(&m, &pairs(&m, 300)),
    }
}

/// How `verilog`, a standalone SAT built in `dir`, differs from the model and the reference
/// sides: a verdict, a side, or the lint of the block tests refusing it.
fn sides_differ(verilog: &str, sat: &SatSides, dir: &Path) -> Option<String> {
    std::fs::create_dir_all(dir).unwrap();
    let got = match whole_sat::try_in_verilator(verilog, &sat.stim.vectors, dir, None) {
        Ok(got) => got,
        Err(e) => return Some(e),
    };
    let verdicts = sat_sides::verdicts(&got);
    let want = &sat.stim.want;
    if let Some(k) = disagreement(&verdicts, want) {
        return Some(format!(
            "clock {k}: verdict {:?}, want {:?}",
            verdicts[k], sat.stim.want[k]
        ));
    }
    sat_sides::differ(&got, &sat.stim.want_sides, SIDES_AT, 2)
}

/// A mutant of the core's SAT run in the standalone SAT (built in `dir`), if it is one.
fn judge_sides(m: &Mutant, core: &str, sat: &SatSides, dir: &Path) -> Option<Verdict> {
    let name = m.module.strip_prefix("obb_core$")?;
    if !(name == "sat" || name.starts_with("sat$")) {
        return None;
    }
    let moved = m
        .moved(core, &sat.verilog, name)
        .unwrap_or_else(|| panic!("{}: not in the standalone SAT", m.describe(core)));
    Some(match sides_differ(&moved.apply(&sat.verilog), sat, dir) {
        Some(e) => Verdict::Killed(format!("the SAT alone: {e}")),
        None => Verdict::Survived,
    })
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
            if let Err(e) = compare(got, &Expected::of(want), taken) {
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

    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let suite = runs(&cfg);
    let sat = standalone_sat();
    if let Some(e) = sides_differ(&sat.verilog, &sat, &root.join("cosim-cache").join("sat")) {
        panic!("the unmutated SAT fails: {e}");
    }
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
        let verdict = match judge(&m.apply(&verilog), &cfg, &suite, &dir) {
            Verdict::Survived => {
                judge_sides(m, &verilog, &sat, &dir.join("sat")).unwrap_or(Verdict::Survived)
            }
            v => v,
        };
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
