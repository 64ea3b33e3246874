//! The f64 separating-axis test on 15 axes, conservative by construction.
//!
//! Semantics (derived in docs/sat.md): a box is the closed set `c + Σ t_k h_k a_k`, |t_k| ≤ 1.
//! The test answers "separated" only when one of its 15 axes separates the two boxes with a
//! margin that covers every floating-point rounding and the measured non-orthonormality of both
//! boxes' axes. So it never reports a pair of intersecting (or touching) boxes as separated, for
//! any input that passes validation. It may report "colliding" for boxes apart by less than that
//! margin: about 1e-14 of the scene's scale for exactly orthonormal axes, and about
//! 2·η·Σh for axes orthonormal only to η (1e-7 for single-precision rotations).

use crate::aabb::U;
use crate::scene::Obb;

/// A box ready for the SAT: the fields of the OBB plus two per-box constants.
#[derive(Clone, Copy, Debug, Default)]
pub struct SatBox {
    pub c: [f64; 3],
    pub a: [[f64; 3]; 3],
    pub h: [f64; 3],
    /// h0 + h1 + h2.
    pub hsum: f64,
    /// Slack for this box's non-orthonormality: 2.01 · η · Σh, η bounding |A Aᵀ - I|.
    pub kappa: f64,
}

impl SatBox {
    pub fn of(obb: &Obb) -> SatBox {
        // The Gram matrix is computed with error < 4u per entry; 8u covers it with room.
        let eta = obb.ortho_error() + 8.0 * U;
        let hsum = obb.half[0] + obb.half[1] + obb.half[2];
        SatBox {
            c: obb.center,
            a: obb.axes,
            h: obb.half,
            hsum,
            kappa: 2.01 * eta * hsum,
        }
    }
}

#[inline(always)]
fn dot(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// True unless one of the 15 axes separates `a` and `b` for certain. Touching counts as colliding.
#[inline]
pub fn boxes_collide(a: &SatBox, b: &SatBox) -> bool {
    let tw = [b.c[0] - a.c[0], b.c[1] - a.c[1], b.c[2] - a.c[2]];
    let tnorm = tw[0].abs() + tw[1].abs() + tw[2].abs();
    // The margin every axis test gets: the rounding bound 64u·(|T|₁ + Σa + Σb) (docs/sat.md
    // derives 23u) plus both boxes' orthonormality slack.
    let s = a.kappa + b.kappa + 64.0 * U * (tnorm + a.hsum + b.hsum);

    let mut r = [[0.0; 3]; 3];
    let mut ar = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = dot(&a.a[i], &b.a[j]);
            ar[i][j] = r[i][j].abs();
        }
    }
    // T in each box's own axes: computed directly, so no orthonormality is assumed.
    let t = [dot(&tw, &a.a[0]), dot(&tw, &a.a[1]), dot(&tw, &a.a[2])];
    let u = [dot(&tw, &b.a[0]), dot(&tw, &b.a[1]), dot(&tw, &b.a[2])];

    // Axes a_i.
    for i in 0..3 {
        let rb = b.h[0] * ar[i][0] + b.h[1] * ar[i][1] + b.h[2] * ar[i][2];
        if t[i].abs() > a.h[i] + rb + s {
            return false;
        }
    }
    // Axes b_j.
    for j in 0..3 {
        let ra = a.h[0] * ar[0][j] + a.h[1] * ar[1][j] + a.h[2] * ar[2][j];
        if u[j].abs() > ra + b.h[j] + s {
            return false;
        }
    }
    // Axes L = R[i1][j]·a_{i2} - R[i2][j]·a_{i1} (= a_i × b_j for orthonormal A). Its projections
    // are computed from R and t exactly as written; B's radius uses the products of R directly
    // rather than the cofactor identity, which holds only for orthonormal B.
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let lhs = (t[i2] * r[i1][j] - t[i1] * r[i2][j]).abs();
            let ra = a.h[i1] * ar[i2][j] + a.h[i2] * ar[i1][j];
            let rb = b.h[j1] * (r[i1][j] * r[i2][j1] - r[i2][j] * r[i1][j1]).abs()
                + b.h[j2] * (r[i1][j] * r[i2][j2] - r[i2][j] * r[i1][j2]).abs();
            if lhs > ra + rb + s {
                return false;
            }
        }
    }
    true
}
