//! The fixed-point model: configuration and quantization errors, projection outward rounding,
//! and the central claim: never a false negative against the f64 reference, for every
//! supported configuration (docs/numerics.md).

use crate::common;

use obb_model::aabb::Aabb;
use obb_model::fixed::broad::{self, BroadWork};
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame, QuantizeError};
use obb_model::sat::obbs_collide;
use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared, Scene};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

/// Any supported configuration: every width in its range, the LSB then fitted to the scene.
fn config() -> impl Strategy<Value = HwConfig> {
    (
        8u32..=23,
        4u32..=18,
        0u32..=100,
        0u32..=100,
        prop_oneof![Just(1e-6), Just(1e-5), Just(1e-3)],
        16u32..=48,
        -4i32..=4,
        1u32..=10,
    )
        .prop_map(
            |(
                center_bits,
                rot_bits,
                key_pick,
                half_pick,
                ortho_tol,
                sat_bits,
                cell_exp,
                grid_hash_bits,
            )| {
                let key_bits = 4 + key_pick % (center_bits - 3);
                let half_max = 17.min(center_bits - 1);
                let half_bits = half_max - half_pick % half_max.min(8);
                HwConfig {
                    center_bits,
                    rot_bits,
                    key_bits,
                    half_bits,
                    ortho_tol,
                    sat_bits,
                    radix_digit_bits: key_bits.min(8),
                    // Grid cells from 1/16 mm (most boxes large) to 16 mm; from 2 buckets
                    // per bank (every list mixed) to 1,024.
                    grid_cell_mm: 2f64.powi(cell_exp),
                    grid_hash_bits,
                    // Every group, and the sweep, which takes boxes of any size: the grid's
                    // windows are widened where a test runs it (`whole_grid`).
                    grid_groups: 8,
                    broad_phase: BroadPhase::Sweep,
                    ..HwConfig::default()
                }
            },
        )
        .prop_filter("a supported configuration", |c| c.validate().is_ok())
}

/// The f64 reference: AABB overlap and the conservative f64 SAT.
fn reference(a: &Obb, b: &Obb) -> bool {
    Aabb::of(a).overlaps(&Aabb::of(b)) && obbs_collide(a, b)
}

/// What the core reports for the pair, with the LSB fitted to the two boxes.
fn model(a: &Obb, b: &Obb, cfg: &HwConfig) -> bool {
    let scene = Scene {
        obbs: vec![a.clone(), b.clone()],
    };
    let cfg = cfg.fitted(&scene);
    let m = ModelFrame::new(&scene, &cfg).expect("a fitted configuration holds the scene");
    m.keys_overlap(0, 1) && m.sat(0, 1)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Boxes sharing a boundary point (faces, edges, corners; near-parallel, single-precision
    /// and zero-thickness boxes) are reported by every configuration, in both orders.
    #[test]
    fn touching_pairs_are_never_missed((a, b) in common::touching_pair(), cfg in config()) {
        prop_assert!(model(&a, &b, &cfg), "missed: {a:?} {b:?} with {cfg:?}");
        prop_assert!(model(&b, &a, &cfg), "missed (swapped): {a:?} {b:?} with {cfg:?}");
    }

    /// Random boxes close together: whatever the f64 reference reports, the model reports.
    #[test]
    fn random_pairs_are_never_missed(
        a in common::obb(3.0, 2.0, 1),
        b in common::obb(3.0, 2.0, 1),
        cfg in config(),
    ) {
        if reference(&a, &b) {
            prop_assert!(model(&a, &b, &cfg), "missed: {a:?} {b:?} with {cfg:?}");
        }
    }

    /// The projection's AABB contains the original box's, and the keys contain the AABB.
    #[test]
    fn projection_rounds_outward(a in common::obb(50.0, 20.0, 1), cfg in config()) {
        let scene = Scene { obbs: vec![a.clone()] };
        let cfg = cfg.fitted(&scene);
        let m = ModelFrame::new(&scene, &cfg).unwrap();
        let (p, (k0, k1)) = (&m.projected[0], &m.keys[0]);
        let exact = Aabb::of(&a);
        let (q, s, offset) = (cfg.lsb_mm, cfg.key_shift(), 1i64 << (cfg.center_bits - 1));
        for x in 0..3 {
            prop_assert!(p.min[x] as f64 * q <= exact.min[x] && exact.max[x] <= p.max[x] as f64 * q);
            prop_assert!(((k0[x] << s) as i64) - offset <= p.min[x]);
            prop_assert!(p.max[x] <= ((k1[x] << s) as i64) - offset);
            prop_assert!(k1[x] < 1 << cfg.key_bits);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Whole scenes (degenerate ones included): the model's pairs contain the f64 engines'.
    #[test]
    fn scenes_are_never_missed(scene in common::core_scene(24), cfg in config(), mask in common::mask()) {
        let cfg = cfg.fitted(&scene);
        let m = ModelFrame::new(&scene, &cfg).unwrap();
        let run = m.detect(cfg.broad_phase, &mask);
        let (pairs, c) = (&run.pairs, run.counters());
        let mut prepared = Prepared::default();
        let (truth, _) = detect(EngineKind::Brute, &prepared.update(&scene.obbs), &mask);
        for p in &truth {
            prop_assert!(pairs.binary_search(p).is_ok(), "missed {p:?} with {cfg:?}");
        }
        prop_assert_eq!(c.pairs as usize, pairs.len());
    }
}

/// `m` with its grid cells coarsened four times over until no large box's window is too wide
/// for the grid's slow path (at the key range's cell none is). Each incomplete frame on the way
/// sent only pairs whose keys overlap and the mask allows (`wanted`, sorted), each once.
fn whole_grid(m: &ModelFrame, mask: &GroupMask, wanted: &[[u32; 2]]) -> ModelFrame {
    let mut m = m.clone();
    loop {
        let mut sent = Vec::new();
        let work = broad::run(&m, BroadPhase::Grid, mask, |i, j| {
            sent.push([i.min(j) as u32, i.max(j) as u32]);
        });
        if !work.incomplete {
            return m;
        }
        sent.sort_unstable();
        let n = sent.len();
        sent.dedup();
        assert_eq!(sent.len(), n, "an incomplete grid frame sent a pair twice");
        assert!(sent.iter().all(|p| wanted.binary_search(p).is_ok()));
        m.cfg.grid_cell_mm *= 4.0;
    }
}

const MODES: [BroadPhase; 4] = [
    BroadPhase::Brute,
    BroadPhase::Sweep,
    BroadPhase::ImprovedSap,
    BroadPhase::Grid,
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Every broad phase emits every pair whose keys overlap and the mask allows (so all report
    /// the same pairs); `brute`, `sweep` and `grid` emit exactly those, each once.
    #[test]
    fn broad_phases_emit_every_overlapping_pair(
        scene in common::core_scene(40), cfg in config(), mask in common::mask(),
    ) {
        let cfg = cfg.fitted(&scene);
        let m = ModelFrame::new(&scene, &cfg).unwrap();
        let n = scene.obbs.len();
        let wanted: Vec<[u32; 2]> = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| [i as u32, j as u32]))
            .filter(|&[i, j]| {
                let (i, j) = (i as usize, j as usize);
                mask.allows(scene.obbs[i].group, scene.obbs[j].group) && m.keys_overlap(i, j)
            })
            .collect();
        let reference = m.detect(BroadPhase::Brute, &mask).pairs;
        let grid = whole_grid(&m, &mask, &wanted);
        for mode in MODES {
            let m = if mode == BroadPhase::Grid { &grid } else { &m };
            let mut emitted = Vec::new();
            let work: BroadWork = broad::run(m, mode, &mask, |i, j| {
                emitted.push([i.min(j) as u32, i.max(j) as u32]);
            });
            prop_assert_eq!(work.sat_tests as usize, emitted.len());
            prop_assert!(work.visits >= work.sat_tests);
            let mut distinct = emitted.clone();
            distinct.sort_unstable();
            distinct.dedup();
            for p in &wanted {
                prop_assert!(distinct.binary_search(p).is_ok(), "{mode:?} dropped {p:?}");
            }
            // Directly: no pair whose original (f64) AABBs overlap is dropped.
            for [i, j] in (0..n).flat_map(|i| (i + 1..n).map(move |j| [i, j])) {
                let (a, b) = (&scene.obbs[i], &scene.obbs[j]);
                if mask.allows(a.group, b.group) && Aabb::of(a).overlaps(&Aabb::of(b)) {
                    let p = [i as u32, j as u32];
                    prop_assert!(distinct.binary_search(&p).is_ok(), "{mode:?} dropped {p:?}");
                }
            }
            if mode != BroadPhase::ImprovedSap {
                // Exactly the wanted pairs, each once (the AABB table check filters the rest).
                let mut once = emitted.clone();
                once.sort_unstable();
                prop_assert_eq!(&once, &wanted, "{:?}", mode);
            }
            prop_assert_eq!(&m.detect(mode, &mask).pairs, &reference, "{:?}", mode);
        }
    }
}

#[test]
fn every_width_combination_on_touching_pairs() {
    // The full grid of widths (not a random sample) on a fixed set of touching pairs.
    let mut runner = common::runner();
    let pairs: Vec<(Obb, Obb)> = (0..40)
        .map(|_| {
            common::touching_pair()
                .new_tree(&mut runner)
                .unwrap()
                .current()
        })
        .collect();
    let mut configs = 0;
    for center_bits in 8..=23 {
        for rot_bits in 4..=18 {
            for key_bits in [4, (4 + center_bits) / 2, center_bits] {
                let cfg = HwConfig {
                    center_bits,
                    rot_bits,
                    key_bits,
                    half_bits: 17.min(center_bits - 1),
                    radix_digit_bits: 4,
                    ..HwConfig::default()
                };
                if cfg.validate().is_err() {
                    // Only 23-bit centers with rot_bits 4 (docs/numerics.md, "Widths").
                    assert_eq!((center_bits, rot_bits), (23, 4));
                    continue;
                }
                configs += 1;
                for (a, b) in &pairs {
                    assert!(model(a, b, &cfg), "missed {a:?} {b:?} with {cfg:?}");
                }
            }
        }
    }
    assert_eq!(configs, 16 * 15 * 3 - 3);
}

#[test]
fn separated_boxes_beyond_the_margin_are_separated() {
    // The price side: axis-aligned boxes further apart than the derived worst case (docs/
    // numerics.md, "What a false positive can cost") are reported separated.
    for center_bits in [12, 16, 20, 23] {
        for rot_bits in [6, 12, 18] {
            let cfg = HwConfig {
                center_bits,
                rot_bits,
                key_bits: center_bits,
                half_bits: 17.min(center_bits - 1),
                ..HwConfig::default()
            };
            cfg.validate().unwrap();
            let a = Obb::aligned([0.0; 3], [1.0, 1.0, 1.0], 0);
            let fit = cfg.fitted(&Scene {
                obbs: vec![a.clone(), Obb::aligned([8.0, 0.0, 0.0], [1.0; 3], 0)],
            });
            let sum_half = 3 * (1.0 / fit.lsb_mm).ceil() as i64;
            let bound = obb_model::fixed::Margins::new(&fit).face_gap_lsb([sum_half; 2]);
            let gap = (bound + 1.0) * fit.lsb_mm;
            let b = Obb::aligned([2.0 + gap, 0.0, 0.0], [1.0; 3], 0);
            let scene = Scene {
                obbs: vec![a.clone(), b.clone()],
            };
            let m = ModelFrame::new(&scene, &fit).unwrap();
            assert!(!m.sat(0, 1), "gap {gap} mm reported colliding with {fit:?}");
            // And at a gap below one LSB the pair is reported (a false positive, never a miss).
            let c = Obb::aligned([2.0 + 0.4 * fit.lsb_mm, 0.0, 0.0], [1.0; 3], 0);
            let near = ModelFrame::new(&Scene { obbs: vec![a, c] }, &fit).unwrap();
            assert!(near.keys_overlap(0, 1) && near.sat(0, 1));
        }
    }
}

#[test]
fn configuration_round_trips_and_defaults_are_valid() {
    let cfg = HwConfig::default();
    cfg.validate().unwrap();
    let text = cfg.to_toml();
    assert_eq!(HwConfig::parse(&text, "round trip").unwrap(), cfg);
    let partial = HwConfig::parse(
        "key_bits = 12\ngroups = \"0-1,0-2\"\nbroad_phase = \"sweep\"\n",
        "t",
    )
    .unwrap();
    assert_eq!(partial.key_bits, 12);
    assert_eq!(partial.groups, GroupMask::Pairs(vec![(0, 1), (0, 2)]));
    assert_eq!(partial.center_bits, cfg.center_bits);
}

#[test]
fn bad_configurations_name_the_key() {
    let cases = [
        ("lsb_mm = 0.001", "lsb_mm"),
        ("lsb_mm = -0.5", "lsb_mm"),
        ("center_bits = 24", "center_bits"),
        ("rot_bits = 19", "rot_bits"),
        ("rot_bits = 3", "rot_bits"),
        ("half_bits = 18", "half_bits"),
        ("key_bits = 21", "key_bits"),
        ("ortho_tol = 0.1", "ortho_tol"),
        ("capacity = 0", "capacity"),
        ("lanes = 0", "lanes"),
        ("lanes = 3", "lanes"),
        ("lanes = 16", "lanes"),
        ("lanes = 2\nbroad_phase = \"sweep\"", "lanes"),
        ("radix_digit_bits = 17", "radix_digit_bits"),
        ("groups = \"0-x\"", "groups"),
        ("broad_phase = \"octree\"", "broad_phase"),
        ("center_bit = 20", "center_bit"),
        ("center_bits = \"wide\"", "center_bits"),
        ("groups = \"0-8\"", "groups"),
        ("clock_ns = 0.5", "clock_ns"),
        ("speed_grade = 4", "speed_grade"),
    ];
    for (text, key) in cases {
        let e = HwConfig::parse(text, "test.toml").unwrap_err().to_string();
        assert!(e.contains(key), "`{text}`: {e}");
    }
}

#[test]
fn scenes_that_do_not_fit_are_rejected_naming_the_obb() {
    let cfg = HwConfig::default(); // ±512 mm at 2^-10 mm, half-lengths below 128 mm
    let ok = Obb::aligned([0.0; 3], [1.0; 3], 0);
    let check = |bad: Obb, what: &str| {
        let scene = Scene {
            obbs: vec![ok.clone(), bad],
        };
        let e = ModelFrame::new(&scene, &cfg).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("obb 1") && text.contains(what), "{text}");
    };
    check(Obb::aligned([600.0, 0.0, 0.0], [1.0; 3], 0), "center[0]");
    check(Obb::aligned([0.0, 510.0, 0.0], [5.0; 3], 0), "axis 1");
    check(Obb::aligned([0.0; 3], [1.0, 1.0, 200.0], 0), "half[2]");
    let mut skew = ok.clone();
    skew.axes[0] = [1.0, 1e-4, 0.0];
    check(skew, "ortho");
    check(Obb::aligned([f64::NAN, 0.0, 0.0], [1.0; 3], 0), "center");
    check(Obb::aligned([0.0; 3], [1.0, -1.0, 1.0], 0), "half");
    let small = HwConfig {
        capacity: 1,
        ..cfg.clone()
    };
    let two = Scene {
        obbs: vec![ok.clone(), ok.clone()],
    };
    assert!(matches!(
        ModelFrame::new(&two, &small),
        Err(QuantizeError::Capacity {
            count: 2,
            capacity: 1
        })
    ));
}

#[test]
fn cycle_model_by_hand() {
    // Two touching boxes, brute force: load 2 + LAT_PROJECT + LAT_KEY_WRITE, no entries, no
    // sort, one visit (one clock), then LAT_BROAD + LAT_SAT.
    use obb_model::fixed::cycles::{
        LAT_BROAD, LAT_KEY_WRITE, LAT_PROJECT, LAT_SAT, LAT_SORT_PASS, LAT_SORT_START,
    };
    let scene = Scene {
        obbs: vec![
            Obb::aligned([0.0; 3], [1.0; 3], 0),
            Obb::aligned([2.0, 0.0, 0.0], [1.0; 3], 1),
            Obb::aligned([9.0, 0.0, 0.0], [1.0; 3], 1),
        ],
    };
    let cfg = HwConfig::default();
    let m = ModelFrame::new(&scene, &cfg).unwrap();
    let run = m.detect(BroadPhase::Brute, &GroupMask::All);
    assert_eq!(run.pairs, vec![[0, 1]]);
    let c = run.cycles;
    assert_eq!(
        (c.load, c.sort, c.walk, c.drain),
        (3 + LAT_PROJECT + LAT_KEY_WRITE, 0, 3, LAT_BROAD + LAT_SAT)
    );
    assert_eq!(c.total, c.load + 3 + LAT_BROAD + LAT_SAT);
    // The sweep sorts three keys on 20 bits in 3 passes of 7-bit digits (128 bins each), as
    // RadixSorter splits 20 bits into digits of at most 8. Box 0 visits box 1 and reads box 2
    // beyond its max; box 1 reads box 2 beyond its max: 1 visit; 4 clocks per box and 1 per
    // visit.
    let sweep = m.detect(BroadPhase::Sweep, &GroupMask::All);
    assert_eq!(
        sweep.cycles.sort,
        3 * (128 + 3 + LAT_SORT_PASS) + LAT_SORT_START
    );
    assert_eq!(sweep.work.visits, 1);
    assert_eq!(sweep.cycles.walk, 4 * 3 + 1);
    // Improved-sap: on x, box 0 meets box 1's min and box 1 meets box 0's max (2 visits); on y
    // and z the three boxes share their keys, so each min meets the two other mins or maxes
    // (6 visits each). Per axis 2n loading clocks, one reading, one per max and two per min,
    // one starting each of the later axes.
    let sap = m.detect(BroadPhase::ImprovedSap, &GroupMask::All);
    assert_eq!(sap.work.visits, 14);
    assert_eq!(sap.cycles.walk, 3 * (2 * 3 + 1 + 3 + 2 * 3) + 2 + 14);
    assert_eq!(sap.reported(), 6, "pair (0, 1) is met twice on each axis");
    // An empty frame: its end marker, the key write, the drain.
    let empty = ModelFrame::new(&Scene { obbs: vec![] }, &cfg).unwrap();
    let e = empty.detect(BroadPhase::Sweep, &GroupMask::All).cycles;
    assert_eq!((e.load, e.walk), (1 + LAT_KEY_WRITE, 0));
}
