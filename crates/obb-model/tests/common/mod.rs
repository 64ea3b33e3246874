//! Strategies shared by the integration tests: random and degenerate scenes.

use nalgebra::{Quaternion, UnitQuaternion};
use obb_model::{GroupMask, Obb, Scene};
use parry3d_f64::math::{Mat3, Pose, Rot3, Vector};
use parry3d_f64::query::sat;
use parry3d_f64::shape::Cuboid;
use proptest::prelude::*;

/// Axes of a rotation given by a (not necessarily unit) quaternion, as rows.
pub fn axes_of(q: [f64; 4]) -> [[f64; 3]; 3] {
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm < 1e-9 {
        return Obb::aligned([0.0; 3], [0.0; 3], 0).axes;
    }
    let r = UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
    let m = r.to_rotation_matrix();
    std::array::from_fn(|k| [m[(0, k)], m[(1, k)], m[(2, k)]])
}

/// The same axes rounded to single precision: orthonormal only to about 1e-7.
pub fn f32_axes(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    a.map(|row| row.map(|v| v as f32 as f64))
}

/// How a random box's axes are made.
#[derive(Clone, Copy, Debug)]
pub enum AxesKind {
    Aligned,
    Random,
    SinglePrecision,
}

pub fn axes_kind() -> impl Strategy<Value = AxesKind> {
    prop_oneof![
        Just(AxesKind::Aligned),
        Just(AxesKind::Random),
        Just(AxesKind::SinglePrecision)
    ]
}

/// One box in a cube of edge `side`, half-lengths in [0, max_half] (zero half-lengths included).
pub fn obb(side: f64, max_half: f64, groups: u32) -> impl Strategy<Value = Obb> {
    (
        prop::array::uniform3(0.0..=side),
        prop::array::uniform4(-1.0f64..1.0),
        axes_kind(),
        prop::array::uniform3(prop_oneof![1 => Just(0.0), 6 => 0.0..=max_half]),
        0..groups,
    )
        .prop_map(|(center, q, kind, half, group)| {
            let axes = match kind {
                AxesKind::Aligned => axes_of([1.0, 0.0, 0.0, 0.0]),
                AxesKind::Random => axes_of(q),
                AxesKind::SinglePrecision => f32_axes(axes_of(q)),
            };
            Obb {
                center,
                axes,
                half,
                group,
            }
        })
}

/// Scenes with the degenerate cases mixed in: identical boxes, coordinates snapped to a coarse
/// lattice (boxes sharing end points), everything in a tiny cube (all boxes overlapping), an
/// occasional huge box, and sometimes eleven groups instead of three.
pub fn scene(max_n: usize) -> impl Strategy<Value = Scene> {
    (
        prop_oneof![Just(1.0), Just(4.0), Just(12.0)],
        prop::collection::vec(obb(12.0, 2.0, 3), 0..max_n),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop::bool::weighted(0.2),
    )
        .prop_map(|(scale, mut obbs, duplicate, snap, huge, many_groups)| {
            for o in obbs.iter_mut() {
                o.center = o.center.map(|c| c * scale / 12.0);
            }
            if duplicate && obbs.len() > 2 {
                let copy = obbs[0].clone();
                obbs.push(copy.clone());
                obbs[1] = copy;
            }
            if snap {
                for o in obbs.iter_mut() {
                    o.center = o.center.map(|c| (c * 2.0).round() / 2.0);
                    o.half = o.half.map(|h| (h * 4.0).round() / 4.0);
                    o.axes = axes_of([1.0, 0.0, 0.0, 0.0]);
                }
            }
            if huge && !obbs.is_empty() {
                obbs[0].half = [40.0, 30.0, 0.5];
            }
            // More groups than the grid keeps ranks for (it then checks the mask pair by pair).
            if many_groups {
                for (i, o) in obbs.iter_mut().enumerate() {
                    o.group = (i % 11) as u32;
                }
            }
            Scene { obbs }
        })
}

/// `scene`, with the groups the core holds (`fixed::config::GROUP_BITS`): eleven become 0 to 7.
pub fn core_scene(max_n: usize) -> impl Strategy<Value = Scene> {
    let groups = 1 << obb_model::fixed::config::GROUP_BITS;
    scene(max_n).prop_map(move |mut s| {
        for o in s.obbs.iter_mut() {
            o.group %= groups;
        }
        s
    })
}

pub fn mask() -> impl Strategy<Value = GroupMask> {
    prop_oneof![
        Just(GroupMask::All),
        Just(GroupMask::Cross),
        Just(GroupMask::Pairs(vec![(0, 1)])),
        Just(GroupMask::Pairs(vec![(1, 1), (0, 2)])),
    ]
}

/// A deterministic runner for tests that draw a fixed number of cases themselves.
pub fn runner() -> proptest::test_runner::TestRunner {
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    TestRunner::new_with_rng(
        Config {
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    )
}

/// Point of `o` at box coordinates `s` (|s_k| <= 1).
pub fn point(o: &Obb, s: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|x| {
        o.center[x] + (0..3).map(|k| s[k] * o.half[k] * o.axes[k][x]).sum::<f64>()
    })
}

/// Places `b` so that its point at box coordinates `sb` is `a`'s point at `sa`: the two boxes
/// share that point, so they intersect (or touch, when both points are on the boundaries).
pub fn touching(a: &Obb, sa: [f64; 3], mut b: Obb, sb: [f64; 3]) -> Obb {
    let p = point(a, sa);
    b.center = [0.0; 3];
    let q = point(&b, sb);
    b.center = std::array::from_fn(|x| p[x] - q[x]);
    b
}

/// A point on the boundary of the unit cube: `face` picks the coordinate pinned to ±1.
pub fn boundary(s: [f64; 3], face: usize, sign: bool) -> [f64; 3] {
    let mut s = s;
    s[face] = if sign { 1.0 } else { -1.0 };
    s
}

/// Axes of `a` turned by `angle` about a random direction: edges near-parallel to a's.
pub fn tilted(a: [[f64; 3]; 3], q: [f64; 4], angle: f64) -> [[f64; 3]; 3] {
    let n = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt().max(1e-12);
    let (s, c) = (angle / 2.0).sin_cos();
    let turn = axes_of([c, s * q[1] / n, s * q[2] / n, s * q[3] / n]);
    // Row k of the result: turn applied to a_k.
    a.map(|row| std::array::from_fn(|x| (0..3).map(|y| turn[y][x] * row[y]).sum()))
}

/// A box at the origin with random axes (rounded to single precision when `single`) and
/// half-lengths from 0 to 75 mm.
pub fn obb_strategy(single: bool) -> impl Strategy<Value = Obb> {
    (
        prop::array::uniform4(-1.0f64..1.0),
        prop::array::uniform3(prop_oneof![1 => Just(0.0), 2 => 1e-3..0.5, 4 => 0.1..75.0f64]),
    )
        .prop_map(move |(q, half)| {
            let axes = axes_of(q);
            Obb {
                center: [0.0; 3],
                axes: if single { f32_axes(axes) } else { axes },
                half,
                group: 0,
            }
        })
}

/// Two boxes sharing a boundary point (a face, edge or corner point of each), with random,
/// near-parallel (1e-3 to 1e-9 rad) and single-precision axes, zero thicknesses and aspect
/// ratios up to 75 mm : 0 mm. They intersect or touch, so every test must report them.
pub fn touching_pair() -> impl Strategy<Value = (Obb, Obb)> {
    (
        prop_oneof![obb_strategy(false), obb_strategy(true)],
        prop_oneof![obb_strategy(false), obb_strategy(true)],
        prop_oneof![Just(None), (-9i32..=-3).prop_map(Some)],
        prop::array::uniform4(-1.0f64..1.0),
        (
            prop::array::uniform3(-1.0f64..=1.0),
            0usize..3,
            any::<bool>(),
        ),
        (
            prop::array::uniform3(-1.0f64..=1.0),
            0usize..3,
            any::<bool>(),
        ),
        any::<bool>(),
    )
        .prop_map(
            |(a, mut b, near_parallel, qt, (sa, fa, ga), (sb, fb, gb), corner)| {
                if let Some(e) = near_parallel {
                    b.axes = tilted(a.axes, qt, 10f64.powi(e));
                }
                let (sa, sb) = if corner {
                    (sa.map(|v| v.signum()), sb.map(|v| v.signum()))
                } else {
                    (boundary(sa, fa, ga), boundary(sb, fb, gb))
                };
                let b = touching(&a, sa, b, sb);
                (a, b)
            },
        )
}

/// parry's separating-axis search for two cuboids, the one its cuboid contact starts from: the
/// normal (from `a` towards `b`) and depth of the axis of least overlap. (`query::contact`
/// itself then measures a face contact's depth from one support point's projection on the
/// other box, which is not the least overlap when that point projects onto another face.)
pub fn parry_contact(a: &Obb, b: &Obb) -> ([f64; 3], f64) {
    let v = |r: [f64; 3]| Vector::new(r[0], r[1], r[2]);
    let pose = |o: &Obb| {
        let m = Mat3::from_cols(v(o.axes[0]), v(o.axes[1]), v(o.axes[2]));
        Pose::from_parts(v(o.center), Rot3::from_mat3(&m))
    };
    let (pa, pb) = (pose(a), pose(b));
    let (ca, cb) = (Cuboid::new(v(a.half)), Cuboid::new(v(b.half)));
    let (ab, ba) = (pa.inv_mul(&pb), pb.inv_mul(&pa));
    // Each in the first box's frame: a's faces, b's faces (normal from b to a), the edges.
    let faces_a = sat::cuboid_cuboid_find_local_separating_normal_oneway(&ca, &cb, &ab);
    let faces_b = sat::cuboid_cuboid_find_local_separating_normal_oneway(&cb, &ca, &ba);
    let edges = sat::cuboid_cuboid_find_local_separating_edge_twoway(&ca, &cb, &ab);
    let candidates = [
        (faces_a.0, pa.rotation * faces_a.1),
        (faces_b.0, pb.rotation * -faces_b.1),
        (edges.0, pa.rotation * edges.1),
    ];
    let (separation, n) =
        candidates
            .into_iter()
            .fold((f64::NEG_INFINITY, Vector::ZERO), |best, c| {
                if c.0 > best.0 {
                    c
                } else {
                    best
                }
            });
    ([n.x, n.y, n.z], -separation)
}

/// The boxes' size: their half-lengths and the distance of their centers, summed.
pub fn size(a: &Obb, b: &Obb) -> f64 {
    let t: [f64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    a.half.iter().chain(&b.half).sum::<f64>() + t.iter().map(|x| x * x).sum::<f64>().sqrt()
}
