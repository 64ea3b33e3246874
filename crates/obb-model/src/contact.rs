//! The contact of two colliding boxes, for a haptic loop: the unit normal of the axis of least
//! overlap, pointing from the first box to the second, and the penetration depth along it.
//!
//! For two boxes the least overlap over the 15 axes of the SAT (three face normals of each, nine
//! edge-edge cross products) is the exact penetration depth, the length of the shortest
//! translation that separates them: for convex polytopes that translation is along a face
//! normal or an edge-edge cross product (docs/sat.md, "Contacts", with the error of this f64
//! computation). A cross product of
//! edges closer to parallel than `MIN_CROSS_SINE` is not a candidate: its direction is mostly
//! rounding, and the face normals then give the depth (for parallel edges, exactly).

use crate::scene::Obb;
use serde::Serialize;

/// Edges whose directions' cross product is shorter than this (the sine of their angle) give no
/// candidate axis. Used, such an axis' direction has a relative error of about 2^-53 over the
/// sine, and so its depth about 1e-8 of the boxes' size at this sine; left out, the depth
/// exceeds the exact one by at most about the sine times twice that size (docs/sat.md). The two
/// are balanced here.
pub const MIN_CROSS_SINE: f64 = 1e-8;

/// A colliding pair's contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Contact {
    /// Unit normal of the axis of least overlap, from the first box towards the second (either
    /// way when their centers project to one point on it).
    pub normal: [f64; 3],
    /// Penetration depth along `normal`, in the scene's unit: 0 for boxes that touch, or that
    /// are apart by less than the SAT's margin and so reported.
    pub depth: f64,
}

fn dot(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

fn cross(p: &[f64; 3], q: &[f64; 3]) -> [f64; 3] {
    [
        p[1] * q[2] - p[2] * q[1],
        p[2] * q[0] - p[0] * q[2],
        p[0] * q[1] - p[1] * q[0],
    ]
}

/// `v` over its length, if it is longer than `least`.
fn unit(v: [f64; 3], least: f64) -> Option<[f64; 3]> {
    let len = dot(&v, &v).sqrt();
    (len > least).then(|| v.map(|x| x / len))
}

/// The contact of `a` and `b` (a pair the SAT reports).
pub fn contact(a: &Obb, b: &Obb) -> Contact {
    let t: [f64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    let radius = |o: &Obb, n: &[f64; 3]| -> f64 {
        (0..3).map(|k| o.half[k] * dot(&o.axes[k], n).abs()).sum()
    };
    let mut best = Contact {
        normal: [0.0, 0.0, 1.0],
        depth: f64::INFINITY,
    };
    let mut consider = |n: [f64; 3]| {
        let along = dot(&t, &n);
        let overlap = radius(a, &n) + radius(b, &n) - along.abs();
        if overlap < best.depth {
            let sign = if along < 0.0 { -1.0 } else { 1.0 };
            best = Contact {
                normal: n.map(|x| sign * x),
                depth: overlap,
            };
        }
    };
    // A face's normal is the cross product of the other two axes: exactly the box's (a
    // parallelepiped's) whatever the axes' orthonormality, which is only within `ORTHO_TOL`.
    for o in [a, b] {
        for k in 0..3 {
            if let Some(n) = unit(cross(&o.axes[(k + 1) % 3], &o.axes[(k + 2) % 3]), 0.0) {
                consider(n);
            }
        }
    }
    for p in &a.axes {
        for q in &b.axes {
            if let Some(n) = unit(cross(p, q), MIN_CROSS_SINE) {
                consider(n);
            }
        }
    }
    best.depth = best.depth.max(0.0);
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_contact_of_aligned_boxes() {
        let a = Obb::aligned([0.0; 3], [1.0; 3], 0);
        let b = Obb::aligned([1.5, 0.2, -0.1], [1.0; 3], 1);
        let c = contact(&a, &b);
        assert_eq!(c.normal, [1.0, 0.0, 0.0]);
        assert_eq!(c.depth, 0.5);
        let back = contact(&b, &a);
        assert_eq!(back.normal, [-1.0, 0.0, 0.0]);
        assert_eq!(back.depth, 0.5);
    }
}
