//! Contacts (`obb_model::contact`) against parry3d-f64's separating-axis search for cuboids (the
//! start of its cuboid contact), an independent implementation in f64: the same penetration depth, and the same normal or an axis of equal
//! overlap; zero depth on boxes that touch face to face; never a vanishing cross axis on
//! near-parallel edges.

use crate::common;

use common::{axes_of, obb_strategy, parry_contact, size, tilted, touching};
use obb_model::contact::{contact, Contact, MIN_CROSS_SINE};
use obb_model::Obb;
use proptest::prelude::*;

fn dot(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    (0..3).map(|x| p[x] * q[x]).sum()
}

/// The overlap of the two boxes' projections on the unit axis `n`, written here.
fn overlap(a: &Obb, b: &Obb, n: &[f64; 3]) -> f64 {
    let r = |o: &Obb| {
        (0..3)
            .map(|k| o.half[k] * dot(&o.axes[k], n).abs())
            .sum::<f64>()
    };
    let t: [f64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    r(a) + r(b) - dot(&t, n).abs()
}

/// `c` is a contact of `a` and `b` that agrees with parry's within `tol`: a unit normal from
/// `a` towards `b` along which the overlap is the depth, parry's depth, and parry's normal or
/// one of equal overlap.
fn agrees(a: &Obb, b: &Obb, c: &Contact, tol: f64) -> Result<(), TestCaseError> {
    let (n, depth) = parry_contact(a, b);
    prop_assert!((dot(&c.normal, &c.normal) - 1.0).abs() < 1e-12, "{c:?}");
    let t: [f64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    prop_assert!(dot(&t, &c.normal) >= 0.0, "{c:?} points from b to a");
    prop_assert!(
        (overlap(a, b, &c.normal).max(0.0) - c.depth).abs() <= tol,
        "{c:?}"
    );
    prop_assert!(
        (c.depth - depth).abs() <= tol,
        "depth {} against parry's {depth} ({a:?} {b:?})",
        c.depth
    );
    if dot(&c.normal, &n) < 1.0 - 1e-9 {
        prop_assert!(
            (overlap(a, b, &n) - c.depth).abs() <= tol,
            "normal {:?} against parry's {n:?}, not a tie",
            c.normal
        );
    }
    Ok(())
}

/// `b` moved so that its point at box coordinates `sb` lies on `a`'s point at `sa`, both
/// inside: the boxes intersect with volume (unless one is flat). With `tilt`, `b`'s axes are
/// `a`'s turned by 10^tilt rad about a random direction: every edge near-parallel to one of
/// `a`'s.
fn overlapping(tilt: Option<std::ops::RangeInclusive<i32>>) -> impl Strategy<Value = (Obb, Obb)> {
    (
        obb_strategy(false),
        obb_strategy(false),
        (
            prop::array::uniform3(-0.9f64..0.9),
            prop::array::uniform3(-0.9f64..0.9),
        ),
        prop::array::uniform3(-100.0f64..100.0),
        prop::array::uniform4(-1.0f64..1.0),
        tilt.unwrap_or(0..=0),
    )
        .prop_map(move |(mut a, mut b, (sa, sb), at, q, e)| {
            a.center = at;
            if e != 0 {
                b.axes = tilted(a.axes, q, 10f64.powi(e));
            }
            let b = touching(&a, sa, b, sb);
            (a, b)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Random intersecting boxes (half-lengths 0 to 75 mm, anywhere in a 200 mm cube): the
    /// depth to 1e-12 of their size, the normal parry's or of equal overlap.
    #[test]
    fn contacts_agree_with_parry((a, b) in overlapping(None)) {
        let tol = 1e-12 * size(&a, &b);
        agrees(&a, &b, &contact(&a, &b), tol)?;
        let back = contact(&b, &a);
        prop_assert!((back.depth - contact(&a, &b).depth).abs() <= tol);
    }

    /// Boxes whose edges are near-parallel (1e-6 to 1e-12 rad): no cross axis of two such
    /// edges is the normal, which is a face normal or the cross axis of edges at least
    /// `MIN_CROSS_SINE` apart; the depth agrees with parry's (which takes every cross axis
    /// longer than 2^-52) within twice the sine bound times the size.
    #[test]
    fn near_parallel_edges_give_no_vanishing_axis((a, b) in overlapping(Some(-12..=-6))) {
        let c = contact(&a, &b);
        let along = |v: [f64; 3]| {
            let len = dot(&v, &v).sqrt();
            len > 0.0 && (dot(&c.normal, &v).abs() / len - 1.0).abs() < 1e-9
        };
        let face = a.axes.iter().chain(&b.axes).any(|x| along(*x));
        let cross = a.axes.iter().any(|p| {
            b.axes.iter().any(|q| {
                let x = [
                    p[1] * q[2] - p[2] * q[1],
                    p[2] * q[0] - p[0] * q[2],
                    p[0] * q[1] - p[1] * q[0],
                ];
                dot(&x, &x).sqrt() >= MIN_CROSS_SINE && along(x)
            })
        });
        prop_assert!(face || cross, "{c:?} is no candidate axis");
        let (_, depth) = parry_contact(&a, &b);
        let tol = (1e-12 + 4.0 * MIN_CROSS_SINE) * size(&a, &b);
        prop_assert!((c.depth - depth).abs() <= tol, "depth {} against parry's {depth}", c.depth);
    }

    /// Boxes face to face (the second turned about the face normal, its face within the
    /// first's): depth 0 to rounding, the normal the first's face normal.
    #[test]
    fn face_to_face_boxes_touch_at_depth_zero(
        q in prop::array::uniform4(-1.0f64..1.0),
        half in prop::array::uniform3(0.1f64..50.0),
        other in prop::array::uniform3(0.1f64..50.0),
        face in 0usize..3,
        turn in -3.2f64..3.2,
        slide in prop::array::uniform2(-0.5f64..0.5),
    ) {
        let a = Obb { axes: axes_of(q), ..Obb::aligned([1.0, -2.0, 3.0], half, 0) };
        // b's axes: a's turned about a's `face` axis, the face axis itself kept third.
        let (u, w) = ((face + 1) % 3, (face + 2) % 3);
        let (s, c) = turn.sin_cos();
        let mix = |p: &[f64; 3], r: &[f64; 3], x: f64, y: f64| -> [f64; 3] {
            std::array::from_fn(|k| x * p[k] + y * r[k])
        };
        let axes = [
            mix(&a.axes[u], &a.axes[w], c, s),
            mix(&a.axes[u], &a.axes[w], -s, c),
            a.axes[face],
        ];
        // Its center on a's face normal, slid within a's face by at most half its halves.
        let center: [f64; 3] = std::array::from_fn(|x| {
            a.center[x]
                + (half[face] + other[2]) * a.axes[face][x]
                + slide[0] * half[u] * a.axes[u][x]
                + slide[1] * half[w] * a.axes[w][x]
        });
        let b = Obb { center, axes, half: other, group: 1 };
        let got = contact(&a, &b);
        let tol = 1e-13 * size(&a, &b);
        prop_assert!(got.depth <= tol, "{got:?}");
        prop_assert!(dot(&got.normal, &a.axes[face]) > 1.0 - 1e-12, "{got:?}");
    }
}
