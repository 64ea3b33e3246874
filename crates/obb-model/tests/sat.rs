//! The f64 SAT never reports intersecting or touching boxes as separated, and agrees with an
//! independent implementation (parry3d-f64) except within a stated tolerance of touching.

use crate::common;

use common::{axes_of, boundary, f32_axes, obb_strategy, tilted, touching};
use obb_model::aabb::Aabb;
use obb_model::sat::{obbs_collide, retain_colliding_with};
use obb_model::simd::Vectors;
use obb_model::{Obb, Prepared};
use parry3d_f64::math::{Mat3, Pose, Rot3, Vector};
use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::Cuboid;
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn collide(a: &Obb, b: &Obb) -> bool {
    Aabb::of(a).overlaps(&Aabb::of(b)) && obbs_collide(a, b)
}

/// The classic SAT (Ericson, Real-Time Collision Detection, 4.4.1) with a fixed 1e-9 epsilon on
/// |R_ij|: it assumes exactly orthonormal axes. Here only to show the cases below are hard.
fn classic_sat(a: &Obb, b: &Obb) -> bool {
    let dot = |p: &[f64; 3], q: &[f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let (ea, eb) = (a.half, b.half);
    let r: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| dot(&a.axes[i], &b.axes[j])));
    let tw: [f64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    let t: [f64; 3] = std::array::from_fn(|i| dot(&tw, &a.axes[i]));
    let ar: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| r[i][j].abs() + 1e-9));
    for i in 0..3 {
        if t[i].abs() > ea[i] + eb[0] * ar[i][0] + eb[1] * ar[i][1] + eb[2] * ar[i][2] {
            return false;
        }
    }
    for j in 0..3 {
        let tb = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
        if tb.abs() > ea[0] * ar[0][j] + ea[1] * ar[1][j] + ea[2] * ar[2][j] + eb[j] {
            return false;
        }
    }
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let lhs = (t[i2] * r[i1][j] - t[i1] * r[i2][j]).abs();
            if lhs
                > ea[i1] * ar[i2][j] + ea[i2] * ar[i1][j] + eb[j1] * ar[i][j2] + eb[j2] * ar[i][j1]
            {
                return false;
            }
        }
    }
    true
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Boxes sharing a boundary point (`common::touching_pair`).
    #[test]
    fn touching_boxes_collide((a, b) in common::touching_pair()) {
        prop_assert!(collide(&a, &b), "missed: {a:?} {b:?}");
        prop_assert!(collide(&b, &a), "missed (swapped): {a:?} {b:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Every vector-lane form of the SAT this CPU has (AVX-512, AVX2, the portable lanes) keeps
    /// exactly the pairs the one-pair SAT accepts, in order, for any number of pairs (full
    /// groups of lanes and a partial last group).
    #[test]
    fn lanes_equal_one_pair_sat(scene in common::scene(24), take in 0usize..300) {
        let mut prepared = Prepared::default();
        let frame = prepared.update(&scene.obbs);
        let n = frame.len() as u32;
        let all: Vec<[u32; 2]> = (0..n).flat_map(|i| (i + 1..n).map(move |j| [i, j])).take(take).collect();
        let expect: Vec<[u32; 2]> = all.iter().copied().filter(|p| frame.sat(p[0] as usize, p[1] as usize)).collect();
        for &vectors in Vectors::available() {
            prop_assert_eq!(retained(&frame, &all, vectors), expect.clone(), "{:?}", vectors);
        }
    }

    /// The same on the stiff cases, at the very point where the answer flips: each touching pair
    /// is moved apart along the line of its centres to the last position the one-pair SAT calls
    /// colliding and the first it calls separated (found by bisection to adjacent floats). A
    /// lane that rounded any step differently would flip there.
    #[test]
    fn lanes_equal_one_pair_sat_where_it_flips(
        cases in prop::collection::vec(common::touching_pair(), 1..12)
    ) {
        let mut obbs = Vec::new();
        for (a, b) in cases {
            if let Some((inside, apart)) = flip_point(&a, &b) {
                obbs.extend([a.clone(), inside, a, apart]);
            }
        }
        let mut prepared = Prepared::default();
        let frame = prepared.update(&obbs);
        let all: Vec<[u32; 2]> = (0..obbs.len() as u32 / 2).map(|k| [2 * k, 2 * k + 1]).collect();
        let expect: Vec<[u32; 2]> = all.iter().copied().filter(|p| frame.sat(p[0] as usize, p[1] as usize)).collect();
        prop_assert_eq!(expect.len() * 2, all.len(), "half collide, half do not");
        for &vectors in Vectors::available() {
            prop_assert_eq!(retained(&frame, &all, vectors), expect.clone(), "{:?}", vectors);
        }
    }
}

/// `b` moved from `a` along the line of their centres to the last position where the one-pair
/// SAT says they collide and the first where it says they do not; `None` when the centres
/// coincide or no move of up to 2^60 times the scale separates them.
fn flip_point(a: &Obb, b: &Obb) -> Option<(Obb, Obb)> {
    let d: [f64; 3] = std::array::from_fn(|k| b.center[k] - a.center[k]);
    let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    let moved = |x: f64| {
        let mut m = b.clone();
        m.center = std::array::from_fn(|k| b.center[k] + x * d[k] / norm);
        m
    };
    let sat = |x: f64| obbs_collide(a, &moved(x));
    let (mut lo, mut hi) = (0.0, norm * f64::EPSILON);
    while sat(hi) {
        (lo, hi) = (hi, hi * 2.0);
        if hi > norm * 2f64.powi(60) {
            return None;
        }
    }
    // sat(lo) and not sat(hi): halve the gap until no float lies between.
    loop {
        let mid = lo + (hi - lo) / 2.0;
        if mid <= lo || mid >= hi {
            return Some((moved(lo), moved(hi)));
        }
        if sat(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

/// The pairs of `all` that the SAT's form on `vectors` keeps.
fn retained(frame: &obb_model::Frame, all: &[[u32; 2]], vectors: Vectors) -> Vec<[u32; 2]> {
    let mut kept = all.to_vec();
    retain_colliding_with(vectors, frame, &mut kept);
    kept
}

/// A pair naming a box past the scene is refused with a panic, by every form, never read.
#[test]
fn pair_past_the_boxes_panics() {
    let obbs = vec![Obb::aligned([0.0; 3], [1.0; 3], 0); 3];
    let mut prepared = Prepared::default();
    let frame = prepared.update(&obbs);
    for &vectors in Vectors::available() {
        let caught = std::panic::catch_unwind(|| retained(&frame, &[[0, 1], [1, 3]], vectors));
        assert!(caught.is_err(), "{vectors:?}: box 3 of 3 was accepted");
    }
}

/// The classic fixed-epsilon SAT misses some of those touching pairs (so the property above has
/// teeth); ours misses none. Counted over a fixed set of single-precision near-parallel cases.
#[test]
fn classic_epsilon_misses_what_ours_catches() {
    let mut runner = common::runner();
    let (mut classic_misses, mut ours_misses, mut total) = (0, 0, 0);
    let cases = (
        obb_strategy(true),
        obb_strategy(true),
        prop::array::uniform4(-1.0f64..1.0),
        -7i32..=-4,
        prop::array::uniform3(-1.0f64..=1.0),
        0usize..3,
    );
    for _ in 0..20_000 {
        let (a, b, q, e, s, f) = cases.new_tree(&mut runner).unwrap().current();
        let mut b = b;
        b.axes = f32_axes(tilted(a.axes, q, 10f64.powi(e)));
        let b = touching(&a, boundary(s, f, true), b, boundary(s, (f + 1) % 3, false));
        total += 1;
        classic_misses += usize::from(!classic_sat(&a, &b));
        ours_misses += usize::from(!collide(&a, &b));
    }
    println!(
        "touching pairs {total}: classic 1e-9 SAT missed {classic_misses}, ours {ours_misses}"
    );
    assert_eq!(ours_misses, 0);
    assert!(
        classic_misses > 0,
        "the cases should defeat a fixed 1e-9 epsilon"
    );
}

#[test]
fn exact_touching_faces_edges_corners_and_gaps() {
    let unit = Obb::aligned([0.0; 3], [1.0; 3], 0);
    let at = |c: [f64; 3]| Obb::aligned(c, [1.0; 3], 0);
    // Face, edge and corner contact at exactly representable coordinates.
    for c in [
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [2.0, 2.0, 2.0],
        [0.0, -2.0, 0.5],
    ] {
        assert!(collide(&unit, &at(c)), "touching at {c:?}");
    }
    // Gaps of 1e-9 and of one ulp beyond a face are separations the SAT must see.
    assert!(!collide(&unit, &at([2.0 + 1e-9, 0.0, 0.0])));
    assert!(!collide(&unit, &at([2.0, 2.0 + 1e-9, 2.0])));
    // A box rotated 45° about z whose edge touches the unit box's face at x = 1.
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let diamond = Obb {
        center: [1.0 + 2f64.sqrt(), 0.0, 0.0],
        axes: [[r, r, 0.0], [-r, r, 0.0], [0.0, 0.0, 1.0]],
        half: [1.0, 1.0, 1.0],
        group: 0,
    };
    assert!(collide(&unit, &diamond));
    let mut apart = diamond.clone();
    apart.center[0] += 1e-9;
    assert!(!collide(&unit, &apart));
    // Coincident and nested boxes, and a zero-size box inside another.
    assert!(collide(&unit, &unit));
    assert!(collide(&unit, &Obb::aligned([0.3, 0.2, 0.1], [0.1; 3], 0)));
    assert!(collide(&unit, &Obb::aligned([0.5; 3], [0.0; 3], 0)));
}

#[test]
fn shaft_against_tiny_boxes() {
    // A 150 mm x 2 mm shaft along a tilted direction, tiny boxes just touching its surface.
    let axes = f32_axes(axes_of([0.9, 0.1, -0.3, 0.2]));
    let shaft = Obb {
        center: [10.0, -5.0, 40.0],
        axes,
        half: [75.0, 1.0, 1.0],
        group: 1,
    };
    for k in 0..200 {
        let s = [-1.0 + k as f64 / 100.0, 1.0, (k as f64 * 0.37).sin()];
        let tiny = Obb {
            center: [0.0; 3],
            axes: axes_of([1.0, k as f64, 2.0, 0.5]),
            half: [0.01, 0.02, 0.0],
            group: 0,
        };
        let tiny = touching(&shaft, s, tiny, [1.0, -1.0, 0.3]);
        assert!(collide(&shaft, &tiny), "tiny box {k}");
    }
}

fn parry_collide(a: &Obb, b: &Obb, grow: f64) -> bool {
    let pose = |o: &Obb| {
        let v = |r: [f64; 3]| Vector::new(r[0], r[1], r[2]);
        let m = Mat3::from_cols(v(o.axes[0]), v(o.axes[1]), v(o.axes[2]));
        Pose::from_parts(v(o.center), Rot3::from_mat3(&m))
    };
    let cub = |o: &Obb| {
        Cuboid::new(
            Vector::new(o.half[0] + grow, o.half[1] + grow, o.half[2] + grow).max(Vector::ZERO),
        )
    };
    intersection_test(&pose(a), &cub(a), &pose(b), &cub(b))
        .expect("cuboids are supported")
        .intersecting
}

/// parry3d-f64 as an oracle on random pairs near contact. Disagreements are allowed only within
/// TOL of touching: growing (or shrinking) both boxes by TOL must make parry agree with us.
#[test]
fn agrees_with_parry_except_within_tolerance_of_touching() {
    const TOL: f64 = 1e-9;
    let mut runner = common::runner();
    let cases = (
        obb_strategy(false),
        obb_strategy(false),
        prop::array::uniform3(-1.5f64..1.5),
        prop_oneof![Just(0.0), -1e-6..1e-6f64],
    );
    let (mut we_collide_only, mut parry_collides_only, mut agree) = (0, 0, 0);
    for _ in 0..50_000 {
        let (a, b, dir, nudge) = cases.new_tree(&mut runner).unwrap().current();
        // Put b where a's point `dir` is, then nudge it: pairs straddle contact.
        let mut b = touching(&a, dir.map(|v| v.clamp(-1.0, 1.0)), b, [1.0, -1.0, 1.0]);
        b.center[0] += nudge;
        let ours = collide(&a, &b);
        let theirs = parry_collide(&a, &b, 0.0);
        match (ours, theirs) {
            (true, false) => {
                we_collide_only += 1;
                assert!(
                    parry_collide(&a, &b, TOL),
                    "we collide, parry is apart by more than {TOL}: {a:?} {b:?}"
                );
            }
            (false, true) => {
                parry_collides_only += 1;
                assert!(
                    !parry_collide(&a, &b, -TOL),
                    "parry collides deeper than {TOL} where we see a gap: {a:?} {b:?}"
                );
            }
            _ => agree += 1,
        }
    }
    println!("parry3d-f64 oracle: {agree} agree, {we_collide_only} only we call colliding, {parry_collides_only} only parry does (all within {TOL} of touching)");
    assert!(agree > 45_000);
}
