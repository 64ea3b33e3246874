//! The f64 separating-axis test on 15 axes, conservative by construction.
//!
//! Semantics (derived in docs/sat.md): a box is the closed set `c + Σ t_k h_k a_k`, |t_k| ≤ 1.
//! The test answers "separated" only when one of its 15 axes separates the two boxes with a
//! margin that covers every floating-point rounding and the measured non-orthonormality of both
//! boxes' axes. So it never reports a pair of intersecting (or touching) boxes as separated, for
//! any input that passes validation. It may report "colliding" for boxes apart by less than that
//! margin: about 1e-14 of the scene's scale for exactly orthonormal axes, and about
//! 2·η·Σh for axes orthonormal only to η (1e-7 for single-precision rotations).

use crate::aabb::{TINY, U};
use crate::prepared::Frame;
use crate::scene::Obb;
use crate::simd::Vectors;

/// Added to every axis test's margin: the absolute error of the products that underflow (at
/// most 2^-1075 each, some 40 in one axis test, carried by factors near 1), which the relative
/// margin does not cover when the boxes and their distance are subnormal (docs/sat.md,
/// "Underflow"). 2^14 times the smallest subnormal: 400 times the bound, and still about 1e-319
/// mm, so it adds no false positive at any scale a scene can have.
const MARGIN_FLOOR: f64 = 16384.0 * TINY;

/// Two per-box constants of the SAT margin, computed once per frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct Slack {
    /// h0 + h1 + h2.
    pub hsum: f64,
    /// Slack for this box's non-orthonormality: 2.01 · η · Σh, η bounding |A Aᵀ - I|.
    pub kappa: f64,
}

impl Slack {
    pub fn of(obb: &Obb) -> Slack {
        Slack::with_skew(obb).0
    }

    /// The slack and the box's skew `q = fl(2.01 η)`, of which `kappa` is `fl(q · hsum)`. For
    /// any `r >= q`, `fl(r · hsum) >= kappa` (rounding is monotone): the largest skew of a
    /// frame ([`crate::Frame::skew`]) bounds every box's `kappa` from its `hsum` alone.
    pub fn with_skew(obb: &Obb) -> (Slack, f64) {
        // The Gram matrix is computed with error < 4u per entry; 8u covers it with room.
        let eta = obb.ortho_error() + 8.0 * U;
        let hsum = obb.half[0] + obb.half[1] + obb.half[2];
        let skew = 2.01 * eta;
        let slack = Slack {
            hsum,
            kappa: skew * hsum,
        };
        (slack, skew)
    }
}

#[cfg(target_arch = "x86_64")]
mod vector;

/// Pairs [`retain_colliding_with`] tests side by side in the portable form.
pub const LANES: usize = 4;

#[inline(always)]
fn dot(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// The SAT on two boxes, computing their slack: the convenience form for tests and tools.
pub fn obbs_collide(a: &Obb, b: &Obb) -> bool {
    boxes_collide(a, &Slack::of(a), b, &Slack::of(b))
}

/// True unless one of the 15 axes separates `a` and `b` for certain. Touching counts as colliding.
/// `sa` and `sb` are the boxes' [`Slack`].
#[inline]
pub fn boxes_collide(a: &Obb, sa: &Slack, b: &Obb, sb: &Slack) -> bool {
    sat_lanes([a], [sa], [b], [sb])[0]
}

/// Keeps the pairs of `pairs` that collide (by [`boxes_collide`]), in their order, on the best
/// vector instructions this CPU has ([`retain_colliding_with`]). The pairs name boxes of
/// `frame`.
pub fn retain_colliding(frame: &Frame, pairs: &mut Vec<[u32; 2]>) {
    retain_colliding_with(Vectors::detected(), frame, pairs);
}

/// [`retain_colliding`] on the instruction set `vectors`, which this CPU must have (it panics
/// otherwise); public so that the tests can run every form. With AVX-512 it tests eight pairs
/// at a time, with AVX2 four, each box read whole into its lane, after a first pass that
/// accepts the pairs whose boxes share a point between their centres (`vector`). The portable
/// form is the generic `sat_lanes` on [`LANES`] pairs, compiled for AVX2 or SSE4.1 and chosen
/// at run time (no fused multiply-add), with no first pass. Every lane rounds exactly as
/// [`boxes_collide`] does, and the first pass accepts only boxes that intersect, so for boxes
/// that pass validation the answer is the same on every CPU and in every form.
pub fn retain_colliding_with(vectors: Vectors, frame: &Frame, pairs: &mut Vec<[u32; 2]>) {
    assert!(
        Vectors::available().contains(&vectors),
        "this CPU cannot run the SAT's {vectors:?} form"
    );
    let (obbs, slack) = (frame.obbs, frame.slack);
    #[cfg(target_arch = "x86_64")]
    if vector::fits(obbs.len()) && vector::on(vectors, obbs, slack, frame.skew, pairs).is_some() {
        return;
    }
    retain_colliding_lanes(obbs, slack, pairs);
}

/// The portable form of [`retain_colliding_with`]: [`LANES`] pairs at a time with the widest
/// vector instructions the CPU has (chosen at run time; no fused multiply-add, so every lane
/// rounds exactly as [`boxes_collide`] does).
#[multiversion::multiversion(targets("x86_64+avx2", "x86_64+sse4.1"))]
fn retain_colliding_lanes(obbs: &[Obb], slack: &[Slack], pairs: &mut Vec<[u32; 2]>) {
    let n = pairs.len();
    let mut kept = 0;
    for start in (0..n).step_by(LANES) {
        // The last group repeats its final pair to fill the lanes.
        let mut p = [pairs[n - 1]; LANES];
        let take = LANES.min(n - start);
        p[..take].copy_from_slice(&pairs[start..start + take]);
        let (mut a, mut b) = ([&obbs[0]; LANES], [&obbs[0]; LANES]);
        let (mut sa, mut sb) = ([&slack[0]; LANES], [&slack[0]; LANES]);
        for l in 0..LANES {
            let [i, j] = p[l].map(|x| x as usize);
            (a[l], sa[l], b[l], sb[l]) = (&obbs[i], &slack[i], &obbs[j], &slack[j]);
        }
        let hit = sat_lanes(a, sa, b, sb);
        for (l, &q) in p.iter().enumerate().take(take) {
            pairs[kept] = q;
            kept += usize::from(hit[l]);
        }
    }
    pairs.truncate(kept);
}

/// One value per lane.
type V<const L: usize> = [f64; L];

#[inline(always)]
fn lanes<const L: usize>(mut f: impl FnMut(usize) -> f64) -> V<L> {
    // A plain loop: `array::from_fn` is not always inlined, and a call per value costs more
    // than the value.
    let mut v = [0.0; L];
    for (l, x) in v.iter_mut().enumerate() {
        *x = f(l);
    }
    v
}

/// Three lane values, `f(k, l)`.
#[inline(always)]
fn lanes3<const L: usize>(mut f: impl FnMut(usize, usize) -> f64) -> [V<L>; 3] {
    let mut v = [[0.0; L]; 3];
    for (k, row) in v.iter_mut().enumerate() {
        *row = lanes(|l| f(k, l));
    }
    v
}

/// A 3x3 matrix of lane values, `f(i, j, l)`.
#[inline(always)]
fn lanes33<const L: usize>(mut f: impl FnMut(usize, usize, usize) -> f64) -> [[V<L>; 3]; 3] {
    let mut v = [[[0.0; L]; 3]; 3];
    for (i, row) in v.iter_mut().enumerate() {
        *row = lanes3(|j, l| f(i, j, l));
    }
    v
}

/// The SAT on `L` pairs (`a[l]`, `b[l]`) at once: every value is an array over the lanes, so the
/// compiler can keep a lane per vector element. A lane is separated when any axis separates it;
/// the work stops early only when every lane is separated.
#[inline(always)]
fn sat_lanes<const L: usize>(
    a: [&Obb; L],
    sa: [&Slack; L],
    b: [&Obb; L],
    sb: [&Slack; L],
) -> [bool; L] {
    let tw: [V<L>; 3] = lanes3(|k, l| b[l].center[k] - a[l].center[k]);
    let tnorm: V<L> = lanes(|l| tw[0][l].abs() + tw[1][l].abs() + tw[2][l].abs());
    // The margin every axis test gets: the rounding bound 64u·(|T|₁ + Σa + Σb) (docs/sat.md
    // derives 23u) plus both boxes' orthonormality slack, plus the underflow floor.
    let s: V<L> = lanes(|l| {
        sa[l].kappa + sb[l].kappa + 64.0 * U * (tnorm[l] + sa[l].hsum + sb[l].hsum) + MARGIN_FLOOR
    });
    let ah: [V<L>; 3] = lanes3(|k, l| a[l].half[k]);
    let bh: [V<L>; 3] = lanes3(|k, l| b[l].half[k]);

    let r: [[V<L>; 3]; 3] = lanes33(|i, j, l| dot(&a[l].axes[i], &b[l].axes[j]));
    let ar: [[V<L>; 3]; 3] = lanes33(|i, j, l| r[i][j][l].abs());
    // T in each box's own axes: computed directly, so no orthonormality is assumed.
    let tl = |l: usize| [tw[0][l], tw[1][l], tw[2][l]];
    let t: [V<L>; 3] = lanes3(|i, l| dot(&tl(l), &a[l].axes[i]));
    let u: [V<L>; 3] = lanes3(|j, l| dot(&tl(l), &b[l].axes[j]));

    let mut sep = [false; L];
    // Axes a_i.
    for i in 0..3 {
        for l in 0..L {
            let rb = bh[0][l] * ar[i][0][l] + bh[1][l] * ar[i][1][l] + bh[2][l] * ar[i][2][l];
            sep[l] |= t[i][l].abs() > ah[i][l] + rb + s[l];
        }
    }
    // Axes b_j.
    for j in 0..3 {
        for l in 0..L {
            let ra = ah[0][l] * ar[0][j][l] + ah[1][l] * ar[1][j][l] + ah[2][l] * ar[2][j][l];
            sep[l] |= u[j][l].abs() > ra + bh[j][l] + s[l];
        }
    }
    if sep.iter().all(|&x| x) {
        return [false; L];
    }
    // Axes L = R[i1][j]·a_{i2} - R[i2][j]·a_{i1} (= a_i × b_j for orthonormal A). Its projections
    // are computed from R and t exactly as written; B's radius uses the 2x2 minors of R directly
    // rather than the cofactor identity, which holds only for orthonormal B. Each minor
    // m[i][k] = |R[i1][k1]·R[i2][k2] - R[i2][k1]·R[i1][k2]| serves two axes; computed once, it
    // rounds exactly as when written out for each (a product commutes, and fl(x - y) = -fl(y - x)).
    let m: [[V<L>; 3]; 3] = lanes33(|i, k, l| {
        let (i1, i2, k1, k2) = ((i + 1) % 3, (i + 2) % 3, (k + 1) % 3, (k + 2) % 3);
        (r[i1][k1][l] * r[i2][k2][l] - r[i2][k1][l] * r[i1][k2][l]).abs()
    });
    for (i, mi) in m.iter().enumerate() {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            for (l, sep) in sep.iter_mut().enumerate() {
                let lhs = (t[i2][l] * r[i1][j][l] - t[i1][l] * r[i2][j][l]).abs();
                let ra = ah[i1][l] * ar[i2][j][l] + ah[i2][l] * ar[i1][j][l];
                let rb = bh[j1][l] * mi[j2][l] + bh[j2][l] * mi[j1][l];
                *sep |= lhs > ra + rb + s[l];
            }
        }
    }
    sep.map(|x| !x)
}
