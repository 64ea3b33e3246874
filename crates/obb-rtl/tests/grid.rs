//! The grid block (`GridPhase`) against the model's walk and clocks
//! (`obb_model::fixed::grid`, `grid_clocks::grid_schedule`): driven clock by clock with the
//! inputs the core gives it on the model's schedule (accepts, keys out of the projection, the
//! test queue drained on clocks with no accept), in rust-hdl and as Verilog in Verilator,
//! with one walker lane and with several. Both must agree on every output on every clock, and
//! equal the model: the credits, every visit (clock, lane's walking box, visited box), the
//! visits counted, every SAT test issued (clock, pair, margins) and the clock the frame is
//! over.

use crate::common;

use obb_model::fixed::cycles::LAT_PROJECT;
use obb_model::fixed::grid_clocks::grid_schedule;
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame};
use obb_model::generate::{slabs, surgical, uniform};
use obb_model::{GroupMask, Obb, Scene};
use obb_rtl::flow::verilator::Port;
use obb_rtl::grid::GridPhase;
use obb_rtl::projection::{CENTER, MARGIN};
use rust_hdl::prelude::*;

const A: usize = 10;
const C: usize = 11;

/// The block's inputs, in port order.
fn input_ports() -> Vec<Port> {
    let mut p = vec![
        Port::new("start", 1),
        Port::new("accept", 1),
        Port::new("loaded", 1),
        Port::new("key_valid", 1),
        Port::new("key_index", A),
    ];
    for name in ["key_min", "key_max"] {
        p.extend(axes(name));
    }
    p.push(Port::new("key_margin", MARGIN));
    p.push(Port::new("key_group", 3));
    p.push(Port::new("test_ready", 1));
    p
}

/// A key per axis: `name_x`, `name_y`, `name_z`.
fn axes(name: &str) -> Vec<Port> {
    ["x", "y", "z"]
        .map(|a| Port::new(format!("{name}_{a}"), CENTER))
        .to_vec()
}

/// The outputs compared: all of them follow from registers only.
fn output_ports() -> Vec<Port> {
    vec![
        Port::new("credit", 1),
        Port::new("visit", 8),
        Port::new("visit_i0", 64),
        Port::new("visit_i1", 64),
        Port::new("visit_i2", 64),
        Port::new("visit_i3", 64),
        Port::new("visit_j0", 64),
        Port::new("visit_j1", 64),
        Port::new("visit_j2", 64),
        Port::new("visit_j3", 64),
        Port::new("visits", 4),
        Port::new("test_valid", 1),
        Port::new("test_a", A),
        Port::new("test_b", A),
        Port::new("test_ma", MARGIN),
        Port::new("test_mb", MARGIN),
        Port::new("finished", 1),
        Port::new("too_wide", 1),
    ]
}

/// What the model says, and the vectors that drive the block on its schedule: vector t is
/// clock t (vector 0 the frame's start pulse); the outputs read after its edge are clock t+1's.
struct Case {
    frame: ModelFrame,
    vectors: Vec<Vec<u64>>,
    /// Clock by clock: a box accepted.
    accept: Vec<bool>,
    /// Per visit: clock, i, j (in that order: with several lanes, a clock makes several).
    visits: Vec<(u64, u64, u64)>,
    /// Per SAT test: clock, a, b (in clock order).
    issues: Vec<(u64, u64, u64)>,
    finished: u64,
    /// The clock from which `too_wide` is high (the slow path planned a window too wide).
    too_wide: Option<u64>,
}

fn case(scene: &Scene, cfg: &HwConfig, mask: &GroupMask) -> Case {
    let frame = ModelFrame::new(scene, cfg).unwrap();
    let walk = frame.grid_walk(mask);
    let s = grid_schedule(&walk);
    // Addressed at F, the box's keys are registered at F + 1, its window's limit at F + 2 and
    // its window planned at F + 3.
    let too_wide = walk
        .too_wide
        .map(|l| s.fetches.iter().find(|f| f.1 == l).unwrap().0 + 4);
    // Over when the list heads are clear (from the clock after the walk, one bucket a clock)
    // and the last SAT test has left the queue.
    let cleared = s.walked + (1 << cfg.grid_hash_bits) + 1;
    let finished = cleared.max(s.issues.last().map_or(0, |&t| t + 1));
    let clocks = finished + 5;
    let n = frame.obbs.len();
    let mut visits: Vec<(u64, u64, u64)> = s
        .visits
        .iter()
        .zip(&walk.pairs)
        .map(|(&t, &(i, j))| (t, u64::from(i), u64::from(j)))
        .collect();
    visits.sort_unstable();
    let passed: Vec<(u64, u64)> = walk
        .pairs
        .iter()
        .zip(&walk.passes)
        .filter(|(_, &p)| p)
        .map(|(&(i, j), _)| (u64::from(i.min(j)), u64::from(i.max(j))))
        .collect();
    assert_eq!(passed.len(), s.issues.len());
    let mut issues: Vec<(u64, u64, u64)> = s
        .issues
        .iter()
        .zip(&passed)
        .map(|(&t, &(a, b))| (t, a, b))
        .collect();
    issues.sort_unstable();
    let mut accept = vec![false; clocks as usize];
    for &t in &s.accepts {
        accept[t as usize] = true;
    }
    let margin = |k: usize| frame.projected[k].margin as u64;
    let mut vectors = Vec::with_capacity(clocks as usize);
    for t in 0..clocks {
        let mut v = vec![
            u64::from(t == 0),
            u64::from(accept[t as usize]),
            u64::from(s.accepts.iter().filter(|&&a| a < t).count() == n),
        ];
        let keyed = s.accepts.iter().position(|&a| a + LAT_PROJECT == t);
        match keyed {
            Some(k) => {
                let (lo, hi) = &frame.keys[k];
                v.push(1);
                v.push(k as u64);
                v.extend(lo);
                v.extend(hi);
                v.push(margin(k));
                v.push(u64::from(frame.obbs[k].group));
            }
            None => v.extend([0; 10]),
        }
        v.push(u64::from(!accept[t as usize]));
        vectors.push(v);
    }
    Case {
        frame,
        vectors,
        accept,
        visits,
        issues,
        finished,
        too_wide,
    }
}

/// The outputs against the model: row t is clock t + 1.
fn check_against_model(c: &Case, rows: &[Vec<u64>], what: &str) {
    let n = c.frame.obbs.len();
    let mut accepted = 0;
    let (mut visits, mut issues) = (Vec::new(), Vec::new());
    let mut finished = None;
    // The visits made one and two clocks before.
    let mut previous = [0; 2];
    for (t, row) in rows.iter().enumerate() {
        let t = t as u64 + 1;
        if (t as usize) < c.accept.len() && accepted < n {
            assert_eq!(
                row[0] == 1,
                c.accept[t as usize],
                "{what}: credit at clock {t}"
            );
        }
        if (t as usize) < c.accept.len() && c.accept[t as usize] {
            accepted += 1;
        }
        // Lane k's visit: bit k of `visit`, its boxes in 32-bit fields of the packed ports.
        let lanes = c.frame.cfg.lanes as usize;
        assert_eq!(
            row[1] >> lanes,
            0,
            "{what}: a visit on a lane that does not exist"
        );
        let mut made = 0;
        for k in (0..lanes).filter(|&k| row[1] >> k & 1 == 1) {
            let field = |port: usize| row[port + k / 2] >> (32 * (k % 2)) & 0xffff_ffff;
            visits.push((t, field(2), field(6)));
            made += 1;
        }
        // `visits` counts the visits of two clocks before.
        assert_eq!(row[10], previous[1], "{what}: visits counted at clock {t}");
        previous = [made, previous[0]];
        let ready = (t as usize) < c.accept.len() && !c.accept[t as usize];
        if row[11] == 1 && ready {
            issues.push((t, row[12], row[13]));
            let margin = |k: u64| c.frame.projected[k as usize].margin as u64;
            assert_eq!(
                (row[14], row[15]),
                (margin(row[12]), margin(row[13])),
                "{what}: margins"
            );
        }
        if row[16] == 1 && finished.is_none() {
            finished = Some(t);
        }
        assert_eq!(
            row[17] == 1,
            c.too_wide.is_some_and(|w| t >= w),
            "{what}: too_wide at clock {t}"
        );
    }
    visits.sort_unstable();
    same(&visits, &c.visits, &format!("{what}: visits (clock, i, j)"));
    same(
        &issues,
        &c.issues,
        &format!("{what}: SAT tests (clock, a, b)"),
    );
    assert_eq!(finished, Some(c.finished), "{what}: the end");
}

/// Two event lists are equal; else the first difference.
fn same(got: &[(u64, u64, u64)], want: &[(u64, u64, u64)], what: &str) {
    if let Some(k) = (0..got.len().max(want.len())).find(|&k| got.get(k) != want.get(k)) {
        panic!(
            "{what}: event {k} of {} (the model's {}): the block's {:?}, the model's {:?}",
            got.len(),
            want.len(),
            got.get(k),
            want.get(k)
        );
    }
}

fn rust_hdl_rows(cfg: &HwConfig, c: &Case) -> Vec<Vec<u64>> {
    let mut uut = GridPhase::<A, C>::new(cfg);
    common::run_rust_hdl(
        &mut uut,
        &c.vectors,
        |u, v| {
            u.start.next = v[0] == 1;
            u.accept.next = v[1] == 1;
            u.loaded.next = v[2] == 1;
            u.key_valid.next = v[3] == 1;
            u.key_index.next = v[4].into();
            u.key_min_x.next = v[5].into();
            u.key_min_y.next = v[6].into();
            u.key_min_z.next = v[7].into();
            u.key_max_x.next = v[8].into();
            u.key_max_y.next = v[9].into();
            u.key_max_z.next = v[10].into();
            u.key_margin.next = v[11].into();
            u.key_group.next = v[12].into();
            u.test_ready.next = v[13] == 1;
        },
        |u, level| u.clock.next = Clock::from(level),
        |u| {
            vec![
                u64::from(u.credit.val()),
                u.visit.val().to_u64(),
                u.visit_i0.val().to_u64(),
                u.visit_i1.val().to_u64(),
                u.visit_i2.val().to_u64(),
                u.visit_i3.val().to_u64(),
                u.visit_j0.val().to_u64(),
                u.visit_j1.val().to_u64(),
                u.visit_j2.val().to_u64(),
                u.visit_j3.val().to_u64(),
                u.visits.val().to_u64(),
                u64::from(u.test_valid.val()),
                u.test_a.val().to_u64(),
                u.test_b.val().to_u64(),
                u.test_ma.val().to_u64(),
                u.test_mb.val().to_u64(),
                u64::from(u.finished.val()),
                u64::from(u.too_wide.val()),
            ]
        },
    )
}

fn grid_cfg(hash_bits: u32, cell_mm: f64, groups: GroupMask) -> HwConfig {
    HwConfig {
        broad_phase: BroadPhase::Grid,
        capacity: 1 << A,
        grid_hash_bits: hash_bits,
        grid_cell_mm: cell_mm,
        groups,
        ..HwConfig::default()
    }
}

/// Uniform boxes, all pairs, 8 buckets a bank: lists shared by many cells (mixed) and long
/// walks, on one lane and on two; coincident boxes, every visit a SAT test.
fn uniform_cases() -> Vec<(&'static str, HwConfig, Scene)> {
    vec![
        (
            "uniform 120, all pairs, 2^3 buckets",
            grid_cfg(3, 16.0, GroupMask::All),
            uniform(120, 5, 0.4).unwrap(),
        ),
        (
            "24 coincident boxes, then 120 apart: the SAT tests wait while the load holds \
             the geometry port, the queue fills, the walker stalls",
            grid_cfg(4, 2.0, GroupMask::All),
            Scene {
                obbs: (0..144)
                    .map(|k| match k {
                        0..24 => Obb::aligned([1.0; 3], [0.25; 3], k % 3),
                        _ => Obb::aligned([f64::from(k) * 3.0, 50.0, -20.0], [0.25; 3], 0),
                    })
                    .collect(),
            },
        ),
        (
            "48 coincident boxes, all pairs: the credits hold the load back",
            grid_cfg(4, 2.0, GroupMask::All),
            Scene {
                obbs: (0..48)
                    .map(|k| Obb::aligned([1.0; 3], [0.25; 3], k % 3))
                    .collect(),
            },
        ),
        (
            "uniform 120, all pairs, 2^3 buckets, 2 lanes",
            lanes(grid_cfg(3, 16.0, GroupMask::All), 2, 1),
            uniform(120, 5, 0.4).unwrap(),
        ),
    ]
}

/// The surgical surfaces, all pairs with most lists mixed, and cross-group, where the
/// instruments' boxes skip the tissue's pure lists.
fn surgical_cases() -> Vec<(&'static str, HwConfig, Scene)> {
    vec![
        (
            "surgical 300, all pairs, 2 buckets a bank: most lists mixed",
            grid_cfg(1, 16.0, GroupMask::All),
            surgical(300, 2).unwrap(),
        ),
        (
            "surgical 300, cross-group, 2^5 buckets",
            grid_cfg(5, 16.0, GroupMask::Cross),
            surgical(300, 2).unwrap(),
        ),
    ]
}

/// Boxes larger than a cell: the slow path's rounds and chain.
fn large_cases() -> Vec<(&'static str, HwConfig, Scene)> {
    vec![
        (
            "slabs over small boxes, 2 mm cells, groups 0-2 and 2-3: three large boxes, their \
             rounds and the chain",
            large_cfg(4, 2.0, "0-2,2-3".parse().unwrap()),
            slabs(),
        ),
        (
            "slabs over small boxes, 1 mm cells, all pairs, 2 buckets a bank: windows of \
             several rounds, every list mixed and read in several",
            large_cfg(1, 1.0, GroupMask::All),
            slabs(),
        ),
        (
            "slabs and a 1.5 mm box over small boxes, 1/8 mm cells: every box large, the 1.5 mm \
             box meets the others on the chain, then the far box's window is too wide",
            large_cfg(4, 1.0 / 8.0, GroupMask::All),
            Scene {
                obbs: [
                    slabs().obbs,
                    vec![Obb::aligned([1.0, 1.0, 0.0], [0.75; 3], 1)],
                ]
                .concat(),
            },
        ),
    ]
}

/// The lanes' larger cases: hundreds of lists, each Verilog of its own, so that Verilator takes
/// minutes over each. Long: run with
/// `cargo test --release -p obb-rtl --test rtl -- --ignored grid::`.
fn lanes_cases() -> Vec<(&'static str, HwConfig, Scene)> {
    vec![
        (
            "48 coincident boxes of one group, all pairs, 8 lanes: the credits of every lane, \
             the lanes' SAT tests issued lowest lane first",
            lanes(grid_cfg(4, 2.0, GroupMask::All), 8, 1),
            Scene {
                obbs: (0..48)
                    .map(|_| Obb::aligned([1.0; 3], [0.25; 3], 0))
                    .collect(),
            },
        ),
        (
            "surgical 300, cross-group, 2^5 buckets, 4 lanes",
            lanes(grid_cfg(5, 16.0, GroupMask::Cross), 4, 3),
            surgical(300, 2).unwrap(),
        ),
        (
            "slabs over small boxes, 1 mm cells, all pairs, 2 buckets a bank, 2 lanes: the \
             large boxes chained per lane, the rest of the chains a list on every lane",
            lanes(large_cfg(1, 1.0, GroupMask::All), 2, 4),
            slabs(),
        ),
        (
            "slabs over small boxes, 2 mm cells, groups 0-2 and 2-3, 2 lanes: the chains' \
             boxes meet across lanes where the mask pairs them",
            lanes(large_cfg(4, 2.0, "0-2,2-3".parse().unwrap()), 2, 4),
            slabs(),
        ),
    ]
}

/// `cfg` with walker lanes, and lists for fewer groups (each list is Verilog of its own).
fn lanes(cfg: HwConfig, lanes: u32, grid_groups: u32) -> HwConfig {
    HwConfig {
        lanes,
        grid_groups,
        ..cfg
    }
}

/// Four groups, for the slow path's masks.
fn large_cfg(hash_bits: u32, cell_mm: f64, groups: GroupMask) -> HwConfig {
    HwConfig {
        grid_groups: 4,
        ..grid_cfg(hash_bits, cell_mm, groups)
    }
}

// Each case in rust-hdl and, as emitted Verilog, in Verilator: both against the model, and
// equal clock for clock. (Three tests, so that their Verilator builds share the cores.)

#[test]
fn grid_block_on_uniform_boxes_matches_the_model() {
    block_matches_the_model(uniform_cases());
}

#[test]
fn grid_block_on_surgical_surfaces_matches_the_model() {
    block_matches_the_model(surgical_cases());
}

#[test]
fn grid_block_on_large_boxes_matches_the_model() {
    block_matches_the_model(large_cases());
}

#[test]
#[ignore = "long: the lanes' larger cases in rust-hdl and Verilator (run with --ignored)"]
fn grid_lanes_match_the_model_in_rust_hdl_and_verilog() {
    block_matches_the_model(lanes_cases());
}

fn block_matches_the_model(cases: Vec<(&'static str, HwConfig, Scene)>) {
    for (what, cfg, scene) in cases {
        let c = case(&scene, &cfg, &cfg.groups);
        assert!(!c.issues.is_empty(), "{what}: SAT tests to check");
        eprintln!(
            "{what}: {} visits, {} SAT tests, {} clocks",
            c.visits.len(),
            c.issues.len(),
            c.finished
        );
        let hdl = rust_hdl_rows(&cfg, &c);
        check_against_model(&c, &hdl, &format!("{what} (rust-hdl)"));
        let verilog =
            obb_rtl::flow::emit::verilog(&mut GridPhase::<A, C>::new(&cfg), "grid_phase").unwrap();
        let rows = common::run_verilator(
            &verilog,
            "grid_phase",
            &input_ports(),
            &output_ports(),
            &c.vectors,
        );
        check_against_model(&c, &rows, &format!("{what} (Verilator)"));
        assert_eq!(rows, hdl, "{what}: Verilator equals rust-hdl");
    }
}

/// Random keys over the whole key range, boxes up to a little more than a cell wide, and boxes
/// whose first cell has every base-4 digit 3 (the largest digit sums the residue mod 3 reduces),
/// for cells of one key unit, 2 mm and 16 mm: `GridCells`' banks, buckets, fingerprints and
/// home cell against `GridShape`, in rust-hdl and in Verilator.
#[test]
fn grid_cells_match_the_model() {
    use obb_model::fixed::grid::GridShape;
    use obb_rtl::grid_cells::{GridCells, BUCKET, FP, LATENCY};
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(15);
    for (cell_mm, hash_bits) in [(1.0 / 4096.0, 12), (2.0, 10), (16.0, 1)] {
        let cfg = grid_cfg(hash_bits, cell_mm, GroupMask::All);
        let shape = GridShape::new(&cfg);
        let top = (1u64 << cfg.key_bits) - 1;
        let cell = 1u64 << shape.cell_bits;
        let mut boxes: Vec<([u64; 3], [u64; 3])> = (0..400)
            .map(|_| {
                let ext = [0; 3].map(|_| rng.random_range(0..=cell + cell / 8));
                let lo = [0, 1, 2].map(|x| rng.random_range(0..=top - ext[x]));
                (lo, [0, 1, 2].map(|x| lo[x] + ext[x]))
            })
            .collect();
        let all_threes = (1..=cfg.key_bits / 2).map(|k| ((1u64 << (2 * k)) - 1) << shape.cell_bits);
        for (k, c) in all_threes.filter(|&c| c + cell <= top).enumerate() {
            let lo = [c, c - (k as u64 % 2) * cell, c >> 2];
            boxes.push((lo, lo.map(|v| v + cell)));
        }
        let mut vectors: Vec<Vec<u64>> = boxes
            .iter()
            .map(|(lo, hi)| [vec![1], lo.to_vec(), hi.to_vec()].concat())
            .collect();
        vectors.extend((0..LATENCY).map(|_| vec![0; 7]));
        // Row t (after edge t) shows the box of vector t + 1 - LATENCY.
        let want: Vec<Vec<u64>> = (0..vectors.len())
            .map(|t| {
                let Some((lo, hi)) = (t + 1)
                    .checked_sub(LATENCY as usize)
                    .and_then(|k| boxes.get(k))
                else {
                    return vec![0];
                };
                let small = shape.is_small(lo, hi);
                let mut row = vec![1, u64::from(small)];
                if small {
                    let (first, last) = shape.window(lo, hi);
                    let home = shape.home(lo);
                    for b in 0..27 {
                        match GridShape::cell_in_bank(b, &first, &last) {
                            Some(c) => row.extend([
                                1,
                                shape.bucket(&c) as u64,
                                shape.fingerprint(&c) as u64,
                                u64::from(GridShape::bank(&home) == b),
                            ]),
                            None => row.extend([0, 0, 0, 0]),
                        }
                    }
                    row.push(shape.fingerprint(&home) as u64);
                }
                row
            })
            .collect();
        // The block's rows in the same shape: a bank outside the window shows no values.
        let shaped = |rows: Vec<Vec<u64>>| -> Vec<Vec<u64>> {
            rows.into_iter()
                .map(|r| {
                    if r[0] == 0 {
                        return vec![0];
                    }
                    let mut row = vec![1, r[1]];
                    if r[1] == 1 {
                        for b in 0..27 {
                            let inside = r[2 + 27 * 2 + b];
                            let (bucket, fp, home) = (r[2 + b], r[2 + 27 + b], r[2 + 27 * 3 + b]);
                            row.extend(if inside == 1 {
                                [1, bucket, fp, home]
                            } else {
                                [0, 0, 0, 0]
                            });
                        }
                        row.push(r[2 + 27 * 4]);
                    }
                    row
                })
                .collect()
        };
        let mut uut = GridCells::new(&cfg);
        let rows = common::run_rust_hdl(
            &mut uut,
            &vectors,
            |u, v| {
                u.key_valid.next = v[0] == 1;
                for x in 0..3 {
                    u.key_min[x].next = v[1 + x].into();
                    u.key_max[x].next = v[4 + x].into();
                }
            },
            |u, level| u.clock.next = Clock::from(level),
            |u| {
                let mut r = vec![u64::from(u.valid.val()), u64::from(u.small_box.val())];
                r.extend(u.bucket.iter().map(|s| s.val().to_u64()));
                r.extend(u.fp.iter().map(|s| s.val().to_u64()));
                r.extend(u.inside.iter().map(|s| u64::from(s.val())));
                r.extend(u.home.iter().map(|s| u64::from(s.val())));
                r.push(u.home_fp.val().to_u64());
                r
            },
        );
        let what = format!("cells of {cell_mm} mm, 2^{hash_bits} buckets");
        let rust_rows = shaped(rows.clone());
        for (t, (g, w)) in rust_rows.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "{what}, rust-hdl, row {t}");
        }
        let verilog =
            obb_rtl::flow::emit::verilog(&mut GridCells::new(&cfg), "grid_cells").unwrap();
        let mut inputs = vec![Port::new("key_valid", 1)];
        inputs.extend(common::ports("key_min", 3, CENTER));
        inputs.extend(common::ports("key_max", 3, CENTER));
        let mut outputs = vec![Port::new("valid", 1), Port::new("small_box", 1)];
        outputs.extend(common::ports("bucket", 27, BUCKET));
        outputs.extend(common::ports("fp", 27, FP));
        outputs.extend(common::ports("inside", 27, 1));
        outputs.extend(common::ports("home", 27, 1));
        outputs.push(Port::new("home_fp", FP));
        let vrows = common::run_verilator(&verilog, "grid_cells", &inputs, &outputs, &vectors);
        assert_eq!(vrows, rows, "{what}: Verilator equals rust-hdl");
        assert!(
            want.iter().filter(|r| r.len() > 2).count() > 200,
            "{what}: small boxes"
        );
    }
}
