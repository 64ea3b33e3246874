//! The stiff and extreme cases, each a test: the fixed-point model reports every pair the f64
//! reference reports, under a spread of configurations from the narrowest to the widest formats
//! (docs/numerics.md), with the sweep (which takes boxes of any size) and with the grid (cells
//! sized to the case's largest box). Each case also checks that the reference itself finds the
//! collisions the case is built to have, so that no case passes by being empty. The
//! configuration `obbcd plan` writes for each case takes it without a miss too.

use crate::common;

use common::{axes_of, f32_axes, parry_contact, size, tilted, touching};
use obb_model::aabb::Aabb;
use obb_model::contact::{contact, MIN_CROSS_SINE};
use obb_model::fixed::plan::{plan, Aims};
use obb_model::fixed::{BroadPhase, HwConfig, Margins, ModelFrame};
use obb_model::{detect, EngineKind, GroupMask, Obb, Pair, Prepared, Scene};

/// From the narrowest formats to the widest: (center_bits, rot_bits, key_bits, sat_bits).
const WIDTHS: [(u32, u32, u32, u32); 8] = [
    (8, 4, 4, 16),
    (10, 6, 10, 40),
    (12, 8, 8, 40),
    (16, 12, 16, 24),
    (20, 18, 20, 40),
    (20, 10, 12, 40),
    (23, 18, 23, 48),
    (23, 18, 23, 20),
];

fn configs() -> impl Iterator<Item = HwConfig> {
    WIDTHS
        .iter()
        .map(|&(center_bits, rot_bits, key_bits, sat_bits)| HwConfig {
            center_bits,
            rot_bits,
            key_bits,
            sat_bits,
            half_bits: 17.min(center_bits - 1),
            radix_digit_bits: 4,
            ortho_tol: 1e-5,
            broad_phase: BroadPhase::Sweep,
            grid_groups: 8,
            ..HwConfig::default()
        })
}

fn reference(scene: &Scene) -> Vec<Pair> {
    let mut prepared = Prepared::default();
    detect(
        EngineKind::Brute,
        &prepared.update(&scene.obbs),
        &GroupMask::All,
    )
    .0
}

/// Every configuration (with the LSB fitted to the scene) reports every reference pair, and the
/// reference reports at least `expected` pairs; and each reference pair's contact is finite,
/// its normal unit and its depth parry's (`contacts_agree`).
fn never_missed(scene: &Scene, expected: usize) {
    let truth = reference(scene);
    assert!(
        truth.len() >= expected,
        "reference found {} < {expected}",
        truth.len()
    );
    contacts_agree(scene, &truth);
    // The finest power-of-two cell no smaller than any box's AABB: no window is too wide.
    let extent = scene
        .obbs
        .iter()
        .map(|o| {
            let b = Aabb::of(o);
            (0..3).map(|x| b.max[x] - b.min[x]).fold(0.0, f64::max)
        })
        .fold(f64::MIN_POSITIVE, f64::max);
    let cell = 2f64.powi(extent.log2().ceil() as i32);
    for sweep in configs() {
        let grid = HwConfig {
            broad_phase: BroadPhase::Grid,
            grid_cell_mm: cell,
            ..sweep.clone()
        };
        for cfg in [sweep, grid] {
            let cfg = cfg.fitted(scene);
            let m = ModelFrame::new(scene, &cfg).expect("a fitted configuration holds the scene");
            let run = m.detect(cfg.broad_phase, &GroupMask::All);
            assert!(!run.work.incomplete, "a window too wide with {cfg:?}");
            for p in &truth {
                assert!(
                    run.pairs.binary_search(p).is_ok(),
                    "missed {p:?} with {cfg:?}"
                );
            }
        }
    }
    // The configuration `obbcd plan` writes for the scene, run as the core runs it.
    let planned = plan(std::slice::from_ref(scene), &Aims::default())
        .expect("every valid scene can be planned for")
        .cfg;
    let run = ModelFrame::new(scene, &planned)
        .expect("a plan holds its scene")
        .run();
    assert!(!run.work.incomplete, "a window too wide with {planned:?}");
    for p in &truth {
        assert!(
            run.pairs.binary_search(p).is_ok(),
            "missed {p:?} with the plan {planned:?}"
        );
    }
}

/// Each pair's contact against parry3d-f64's separating-axis search: a unit normal, a finite
/// depth of at least 0, equal to parry's within the rounding, the near-parallel edges' bound
/// and the axes' non-orthonormality (parry makes a rotation of them), all relative to the
/// boxes' size.
fn contacts_agree(scene: &Scene, pairs: &[Pair]) {
    for &[i, j] in pairs {
        let (a, b) = (&scene.obbs[i as usize], &scene.obbs[j as usize]);
        let c = contact(a, b);
        let norm: f64 = c.normal.iter().map(|x| x * x).sum();
        assert!((norm - 1.0).abs() < 1e-12, "{c:?} of {a:?} {b:?}");
        assert!(
            c.depth.is_finite() && c.depth >= 0.0,
            "{c:?} of {a:?} {b:?}"
        );
        let (_, depth) = parry_contact(a, b);
        let eta = a.ortho_error().max(b.ortho_error());
        let tol = (1e-12 + 4.0 * MIN_CROSS_SINE + 4.0 * eta) * size(a, b);
        assert!(
            (c.depth - depth.max(0.0)).abs() <= tol,
            "depth {} against parry's {depth} of {a:?} {b:?}",
            c.depth
        );
    }
}

fn scene(obbs: Vec<Obb>) -> Scene {
    Scene { obbs }
}

fn rotated(center: [f64; 3], half: [f64; 3], q: [f64; 4]) -> Obb {
    Obb {
        center,
        axes: axes_of(q),
        half,
        group: 0,
    }
}

#[test]
fn parallel_and_near_parallel_edges() {
    // Edge against edge, the second box turned by 1e-3 to 1e-9 rad: the cross-product axes all
    // but vanish.
    let a = rotated([0.0; 3], [2.0, 1.0, 0.5], [0.9, 0.2, -0.3, 0.1]);
    let mut obbs = vec![a.clone()];
    for e in 3..=9 {
        for (k, q) in [[0.3, 0.5, -0.2, 0.7], [0.1, -0.8, 0.4, 0.2]]
            .iter()
            .enumerate()
        {
            let mut b = a.clone();
            b.axes = tilted(a.axes, *q, 10f64.powi(-e));
            let sb = if k == 0 {
                [1.0, 1.0, -1.0]
            } else {
                [-1.0, 1.0, 0.3]
            };
            obbs.push(touching(&a, [1.0, -1.0, 0.2], b, sb));
        }
    }
    never_missed(&scene(obbs), 14);
}

#[test]
fn exactly_touching_faces_edges_and_corners() {
    let a = rotated([1.0, -2.0, 0.5], [1.5, 0.75, 0.25], [0.8, -0.1, 0.4, 0.3]);
    let b = rotated([0.0; 3], [0.5, 1.25, 2.0], [0.2, 0.7, -0.1, 0.6]);
    let mut obbs = vec![a.clone()];
    for (sa, sb) in [
        ([1.0, 0.2, -0.3], [-1.0, 0.1, 0.5]),  // face against face
        ([1.0, 1.0, 0.4], [-0.2, -1.0, -1.0]), // edge against edge
        ([1.0, 1.0, 1.0], [-1.0, -1.0, -1.0]), // corner against corner
        ([-1.0, 0.0, 0.0], [1.0, 1.0, 1.0]),   // corner against face
    ] {
        obbs.push(touching(&a, sa, b.clone(), sb));
    }
    // Axis-aligned faces sharing a plane exactly.
    obbs.push(Obb::aligned([10.0, 0.0, 0.0], [1.0; 3], 0));
    obbs.push(Obb::aligned([12.0, 0.5, -0.5], [1.0; 3], 0));
    never_missed(&scene(obbs), 5);
}

#[test]
fn gaps_of_one_lsb_and_of_half_an_lsb() {
    // Apart by 0, 1/2 and 1 LSB: the reference separates the last two, the core reports all
    // three (false positives inside the documented bound), and separates a gap beyond it.
    for cfg in configs() {
        // Room for the widest gap: with 2 fraction bits a rotation is known only to 1/8, and
        // the bound is then about 15 mm for these 2 mm boxes.
        let probe = scene(vec![
            Obb::aligned([0.0; 3], [1.0; 3], 0),
            Obb::aligned([100.0, 0.0, 0.0], [1.0; 3], 0),
        ]);
        let cfg = cfg.fitted(&probe);
        let q = cfg.lsb_mm;
        let bound = Margins::new(&cfg).face_gap_lsb([3 * (1.0 / q).ceil() as i64; 2]);
        assert!((bound + 1.0) * q < 90.0, "{bound} LSB with {cfg:?}");
        for (gap_lsb, reported) in [(0.0, true), (0.5, true), (1.0, true), (bound + 1.0, false)] {
            let s = scene(vec![
                Obb::aligned([0.0; 3], [1.0; 3], 0),
                Obb::aligned([2.0 + gap_lsb * q, 0.0, 0.0], [1.0; 3], 0),
            ]);
            let m = ModelFrame::new(&s, &cfg).unwrap();
            let got = m.keys_overlap(0, 1) && m.sat(0, 1);
            assert_eq!(got, reported, "gap {gap_lsb} LSB with {cfg:?}");
            assert_eq!(reference(&s).len(), usize::from(gap_lsb == 0.0));
        }
    }
}

#[test]
fn zero_thickness_boxes() {
    // Tissue quads: zero thickness, touching along edges, and a quad lying on a face.
    let quad = |x: f64, q: [f64; 4]| rotated([x, 0.0, 0.0], [0.5, 0.5, 0.0], q);
    let tilt = [1.0, 0.02, -0.01, 0.0];
    let mut obbs = vec![quad(0.0, tilt)];
    obbs.push(touching(
        &obbs[0],
        [1.0, 0.3, 0.0],
        quad(0.0, [1.0, -0.03, 0.02, 0.01]),
        [-1.0, 0.1, 0.0],
    ));
    obbs.push(Obb::aligned([5.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0));
    obbs.push(Obb::aligned([5.0, 0.2, 0.0], [0.5, 0.5, 0.0], 0));
    obbs.push(Obb::aligned([5.0, 0.2, 0.0], [0.0, 0.0, 0.0], 0)); // a point
    never_missed(&scene(obbs), 4);
}

#[test]
fn long_shaft_against_tiny_boxes() {
    // A 150 mm x 2 mm shaft and 0.05 mm boxes touching its surface all along.
    let shaft = rotated([0.0; 3], [75.0, 1.0, 1.0], [0.95, 0.1, 0.2, -0.2]);
    let mut obbs = vec![shaft.clone()];
    for k in 0..40 {
        let s = -1.0 + 2.0 * k as f64 / 39.0;
        let tiny = rotated([0.0; 3], [0.025; 3], [0.3, k as f64, 1.0, -0.5]);
        obbs.push(touching(&shaft, [s, 1.0, 0.3], tiny, [-1.0, -1.0, 1.0]));
    }
    never_missed(&scene(obbs), 40);
}

#[test]
fn boxes_at_the_edges_of_the_coordinate_range() {
    // Boxes whose AABBs reach exactly to the limit of the configured range, touching there.
    for cfg in configs() {
        let q = cfg.lsb_mm;
        let limit = (1i64 << (cfg.center_bits - 1)) - (1i64 << cfg.key_shift());
        let h = 16i64;
        // The projection's extent of an axis-aligned box with half-lengths h (docs/numerics.md).
        let f = cfg.frac_bits();
        let e = (h * ((2 << f) + 3) + (1 << f) + (2 << f) - 1) >> (f + 1);
        let edge = (limit - e) as f64 * q;
        let hq = h as f64 * q;
        let s = scene(vec![
            Obb::aligned([edge, -edge, edge], [hq; 3], 0),
            Obb::aligned([edge - 2.0 * hq, -edge, edge], [hq; 3], 0),
            Obb::aligned([-edge, edge, -edge], [hq; 3], 0),
            Obb::aligned([-edge, edge - 2.0 * hq, -edge], [hq; 3], 0),
        ]);
        let truth = reference(&s);
        assert_eq!(truth.len(), 2);
        let m = ModelFrame::new(&s, &cfg).expect("inside the range");
        assert_eq!(
            m.detect(cfg.broad_phase, &GroupMask::All).pairs,
            truth,
            "{cfg:?}"
        );
        // One LSB further and the box is rejected, never wrapped.
        let past = scene(vec![Obb::aligned([edge + q, 0.0, 0.0], [hq; 3], 0)]);
        let err = ModelFrame::new(&past, &cfg).unwrap_err().to_string();
        assert!(err.contains("obb 0") && err.contains("axis 0"), "{err}");
    }
}

#[test]
fn tiny_rotations() {
    let a = Obb::aligned([0.0; 3], [1.0, 2.0, 0.5], 0);
    let mut obbs = vec![a.clone()];
    for e in 6..=12 {
        let b = rotated([0.0; 3], [0.7, 0.3, 1.1], [1.0, 10f64.powi(-e), 0.0, 0.0]);
        obbs.push(touching(&a, [1.0, 0.9, -1.0], b, [-1.0, -1.0, 1.0]));
    }
    never_missed(&scene(obbs), 7);
}

#[test]
fn coincident_and_nested_boxes() {
    let a = rotated([1.0, 2.0, 3.0], [2.0, 1.0, 0.5], [0.5, 0.5, 0.5, 0.5]);
    let mut inner = a.clone();
    inner.half = [0.5, 0.25, 0.1];
    let mut deep = inner.clone();
    deep.half = [0.0; 3];
    never_missed(&scene(vec![a.clone(), a.clone(), inner, deep]), 6);
}

#[test]
fn many_equal_sort_keys() {
    // 64 boxes on a lattice with identical x extents: keys tie on x everywhere.
    let obbs: Vec<Obb> = (0..64)
        .map(|k| Obb::aligned([0.0, (k % 8) as f64, (k / 8) as f64], [0.5; 3], 0))
        .collect();
    // Lattice neighbours touch: 7*8 along y, 7*8 along z, and 2*7*7 diagonal (edge) contacts.
    never_missed(&scene(obbs), 7 * 8 * 2 + 2 * 7 * 7);
}

#[test]
fn axes_orthonormal_only_to_single_precision() {
    let mut obbs = Vec::new();
    for k in 0..24 {
        let q = [0.3 + k as f64, -0.2 * k as f64, 0.7, 0.1 * k as f64];
        let a = Obb {
            center: [0.0; 3],
            axes: f32_axes(axes_of(q)),
            half: [1.0, 0.5, 0.25],
            group: 0,
        };
        let mut b = a.clone();
        b.axes = f32_axes(tilted(a.axes, [0.1, 0.4, -0.3, 0.8], 1e-7));
        let b = touching(&a, [1.0, 1.0, -0.5], b, [-1.0, -1.0, 0.7]);
        let shift = [10.0 * k as f64, 0.0, 0.0];
        for mut o in [a, b] {
            o.center = std::array::from_fn(|x| o.center[x] + shift[x]);
            obbs.push(o);
        }
    }
    never_missed(&scene(obbs), 24);
}

#[test]
fn dense_scene_where_every_pair_collides() {
    let obbs: Vec<Obb> = (0..60)
        .map(|i| {
            rotated(
                [0.01 * i as f64, 0.0, -0.005 * i as f64],
                [1.0, 0.5, 0.25],
                [1.0, i as f64 * 0.1, 0.3, -0.2],
            )
        })
        .collect();
    never_missed(&scene(obbs), 60 * 59 / 2);
}
