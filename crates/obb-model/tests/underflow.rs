//! Scenes at the bottom of f64's range: lengths, distances and axis entries near and below
//! 2^-1022, where products underflow (subnormal numbers) and lose absolute, not relative,
//! precision. Every engine, and the SAT in both argument orders, must report every pair whose
//! boxes share a point. Whether they do is decided here in exact rational arithmetic, written
//! independently of the engines: the shared point's box coordinates are solved for by Cramer's
//! rule (docs/sat.md, "Underflow").

use crate::common;

use common::{axes_of, f32_axes, point, runner, touching};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::sat::obbs_collide;
use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared, Scene};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// 2^e exactly, for e down to -1074 (as a product of two normal powers, so nothing rounds).
fn pow2(e: i32) -> f64 {
    2f64.powi(e / 2) * 2f64.powi(e - e / 2)
}

/// The determinant of three rows.
fn det(r: [&[BigRational; 3]; 3]) -> BigRational {
    let [a, b, c] = r;
    &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
        + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0])
}

/// Whether the closed box `o` holds the point `p`, exactly: `p - c = Σ_k s_k a_k` with
/// `|s_k| <= h_k`. By Cramer's rule `s_k = det(A with row k replaced by p - c) / det(A)`.
fn contains(o: &Obb, p: &[BigRational; 3]) -> bool {
    let a = o.axes.map(|row| row.map(exact));
    let d: [BigRational; 3] = std::array::from_fn(|x| &p[x] - exact(o.center[x]));
    let whole = det([&a[0], &a[1], &a[2]]);
    assert!(!whole.is_zero(), "axes span space");
    (0..3).all(|k| {
        let mut rows = [&a[0], &a[1], &a[2]];
        rows[k] = &d;
        det(rows).abs() <= exact(o.half[k]) * whole.abs()
    })
}

/// Every engine, the SAT both ways round and the fixed-point model (the default configuration,
/// all pairs) report the pair (0, 1) of a two-box scene.
fn every_engine_reports(a: &Obb, b: &Obb, what: &str) {
    let scene = Scene {
        obbs: vec![a.clone(), b.clone()],
    };
    scene.validate().expect("a valid scene");
    assert!(obbs_collide(a, b) && obbs_collide(b, a), "{what}: the SAT");
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&scene.obbs);
    for kind in EngineKind::ALL {
        let (pairs, _) = detect(kind, &boxes, &GroupMask::All);
        assert_eq!(pairs, vec![[0, 1]], "{what}: {kind}");
    }
    let cfg = HwConfig {
        groups: GroupMask::All,
        ..HwConfig::default()
    };
    let model = ModelFrame::new(&scene, &cfg).expect("fits the default range");
    assert_eq!(
        model.run().pairs,
        vec![[0, 1]],
        "{what}: the fixed-point model"
    );
}

/// The two crossing plates of zero thickness whose x extents' products underflow: they share
/// the point (-6.5 · 2^-1074, -0.65, -0.65), which no f64 can hold.
#[test]
fn crossing_plates_with_subnormal_axis_entries() {
    let plate = |center: f64, tilt: f64| Obb {
        center: [center, 0.0, 0.0],
        axes: [[1.0, 0.0, 0.0], [tilt, 1.0, 0.0], [tilt, 0.0, 1.0]],
        half: [0.0, 0.7, 0.7],
        group: 0,
    };
    let (a, b) = (plate(0.0, 2.5e-323), plate(-6.4e-323, -2.5e-323));
    let tiny = exact(pow2(-1074));
    let p = [
        tiny * BigRational::new(BigInt::from(-13), BigInt::from(2)),
        BigRational::new(BigInt::from(-65), BigInt::from(100)),
        BigRational::new(BigInt::from(-65), BigInt::from(100)),
    ];
    assert!(contains(&a, &p) && contains(&b, &p), "the plates share p");
    every_engine_reports(&a, &b, "crossing plates");
}

/// Two cubes of subnormal size, the second's center on the first's face: every length of the
/// SAT underflows, and the grid's cells would be smaller than 1 / f64::MAX.
#[test]
fn cubes_of_subnormal_size() {
    let cube = |x: f64| Obb::aligned([x, 0.0, 0.0], [1e-310; 3], 0);
    let (a, b) = (cube(0.0), cube(1e-310));
    assert!(contains(&a, &[exact(1e-310), exact(0.0), exact(0.0)]));
    assert!(contains(&b, &[exact(1e-310), exact(0.0), exact(0.0)]));
    every_engine_reports(&a, &b, "subnormal cubes");
}

/// Axes: aligned, random, rounded to single precision, or aligned with subnormal entries off
/// the diagonal (as the plates).
fn axes() -> impl Strategy<Value = [[f64; 3]; 3]> {
    (prop::array::uniform4(-1.0f64..1.0), 0..4, -8i64..8).prop_map(|(q, kind, tilt)| match kind {
        0 => axes_of([1.0, 0.0, 0.0, 0.0]),
        1 => axes_of(q),
        2 => f32_axes(axes_of(q)),
        _ => {
            let t = tilt as f64 * pow2(-1074);
            [[1.0, t, -t], [t, 1.0, t], [-t, t, 1.0]]
        }
    })
}

/// A box of the unit scale: center in [-4, 4]^3, half-lengths up to 2 (zeros included).
fn unit_box() -> impl Strategy<Value = Obb> {
    (
        prop::array::uniform3(-4.0f64..4.0),
        axes(),
        prop::array::uniform3(prop_oneof![1 => Just(0.0), 4 => 0.0f64..2.0]),
    )
        .prop_map(|(center, axes, half)| Obb {
            center,
            axes,
            half,
            group: 0,
        })
}

/// Box coordinates with one pinned to ±1: a point on the boundary.
fn on_boundary() -> impl Strategy<Value = [f64; 3]> {
    (
        prop::array::uniform3(-1.0f64..=1.0),
        0..3usize,
        any::<bool>(),
    )
        .prop_map(|(mut s, face, sign)| {
            s[face] = if sign { 1.0 } else { -1.0 };
            s
        })
}

/// Pairs of boxes that touch (a point of each one's boundary in common), drawn at the unit
/// scale and scaled by 2^e for e from 0 down to -1074: half the pairs near and below the
/// smallest normal length. The touching point is computed in f64, so it may miss either box by
/// a rounding; only pairs whose point lies in both boxes exactly are kept, and at every scale
/// enough must be.
#[test]
fn touching_pairs_at_every_scale_are_reported() {
    const SCALES: [i32; 9] = [0, -900, -1000, -1022, -1030, -1040, -1055, -1066, -1074];
    const DRAWS: usize = 400;
    let strategy = (unit_box(), unit_box(), on_boundary(), on_boundary());
    let mut rng = runner();
    for e in SCALES {
        let scale = pow2(e);
        let shrink = |o: Obb| Obb {
            center: o.center.map(|v| v * scale),
            half: o.half.map(|v| v * scale),
            ..o
        };
        let mut kept = 0;
        for _ in 0..DRAWS {
            let (a, b, sa, sb) = strategy.new_tree(&mut rng).unwrap().current();
            let a = shrink(a);
            let b = touching(&a, sa, shrink(b), sb);
            let p = point(&a, sa).map(exact);
            if !(contains(&a, &p) && contains(&b, &p)) {
                continue;
            }
            kept += 1;
            every_engine_reports(&a, &b, &format!("scale 2^{e}: {a:?} and {b:?}"));
        }
        assert!(
            kept >= DRAWS / 20,
            "scale 2^{e}: only {kept} pairs share a point"
        );
    }
}
