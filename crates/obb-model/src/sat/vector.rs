//! The SAT of [`super::retain_colliding`] on several pairs at a time, written once over the
//! vector instruction set ([`Isa`]): eight pairs with AVX-512, four with AVX2.
//!
//! The compiler's own vectorisation of `sat_lanes` spends most of its time putting each box's
//! values into their lanes: the two boxes of a pair lie anywhere in the scene, so every value
//! is a load, a shuffle or a spill. Here the boxes of a step are read whole and transposed in
//! registers ([`Isa::boxes`]), so that each vector holds one value of the step's boxes. Every
//! product, sum and comparison is the one `sat_lanes` writes, in the same order and without
//! fused multiply-add, so each lane rounds exactly as [`super::boxes_collide`] does. A pair is
//! accepted without the SAT only when its boxes share a point for certain (a point between the
//! centres, proved in docs/sat.md), which `boxes_collide` never calls separated: the two give
//! the same answer on every pair of valid boxes, which the tests check on random and touching
//! pairs.

use super::{Slack, MARGIN_FLOOR};
use crate::aabb::U;
use crate::scene::Obb;
use crate::simd::{
    all_lanes, axes, compile_for_each_isa, dot, field3, Isa, LaneMask, Lanes, Mask, CENTER, HALF,
    MAX_WIDTH,
};
use std::mem::{offset_of, size_of};

/// Slacks as arrays of f64, for the gathers' indices.
const SLACK_STRIDE: usize = size_of::<Slack>() / 8;
const KAPPA: usize = offset_of!(Slack, kappa) / 8;
const _: () = assert!(size_of::<Slack>().is_multiple_of(8));

/// Whether every box's slack offset fits the gathers' 32-bit indices.
pub(super) fn fits(n: usize) -> bool {
    n.checked_mul(SLACK_STRIDE)
        .is_some_and(|x| x <= i32::MAX as usize)
}

/// Pairs taken at a time through the three passes of [`retain_colliding`]: small enough that
/// their boxes are still in the caches when the second pass reads them again.
const BLOCK: usize = 1024;
/// The first pass prefetches the boxes of the step this many steps ahead. A step's work (two
/// boxes of `W` pairs read and transposed, and the segment test: about 330 instructions with
/// AVX2) is more than the CPU's reorder buffer holds, so without it a step's box reads, mostly
/// from L3, hardly overlap any other step's work: on AMD's Zen 3, 2 to 8 steps ahead took 0.1
/// ms off the surgical scene's all-pairs frame (3 %), alike.
const PREFETCH_STEPS: usize = 4;

compile_for_each_isa!(retain_colliding(
    obbs: &[Obb],
    slack: &[Slack],
    skew: f64,
    pairs: &mut Vec<[u32; 2]>,
) -> ());

/// [`super::retain_colliding`], `W` pairs per step, for boxes that [`fits`] accepts; `skew` is
/// their frame's ([`crate::Frame::skew`]). A pair naming a box past `obbs` or `slack` panics,
/// as indexing does.
///
/// Nine in ten of the pairs the grid hands over collide, so most steps need all 15 axes. In a
/// block of pairs, a first pass looks for a point between the two centres inside both boxes
/// ([`Front::shares_a_point`]: a sufficient test for colliding, which needs 6 of the SAT's 15
/// dot products, and decides five in six of the surgical scene's pairs); the second pass runs
/// the whole SAT on the pairs the first could not decide, packed `W` to a step; the third
/// keeps the colliding pairs, in their order.
#[inline(always)]
fn retain_colliding<I: Isa<W>, const W: usize>(
    isa: I,
    obbs: &[Obb],
    slack: &[Slack],
    skew: f64,
    pairs: &mut Vec<[u32; 2]>,
) {
    debug_assert!(fits(obbs.len()));
    let n = pairs.len();
    let boxes = obbs.len().min(slack.len());
    // The loads and gathers do not check their indices: this does, through the largest index
    // (a plain loop, compiled with the instruction set: in vectors; through `find`, the check
    // took 0.67 million instructions a frame more on the surgical scene).
    let mut largest = 0;
    for q in pairs.iter() {
        largest = largest.max(q[0]).max(q[1]);
    }
    // (With no pairs the largest is 0, and no pair is past the boxes.)
    if largest as usize >= boxes {
        let past = |q: &&[u32; 2]| q.iter().any(|&i| i as usize >= boxes);
        if let Some(q) = pairs.iter().find(past) {
            panic!("pair {q:?} names a box past the {boxes} boxes");
        }
    }
    // The third pass stores `W` pairs whole at each step, the kept ones first: room for the
    // last step's.
    pairs.reserve(W);
    let mut kept = 0;
    // Bit `l` of `colliding[s]`: the pair at lane `l` of step `s` collides.
    let mut colliding = [0u8; BLOCK];
    // The block's pairs that the first pass left undecided, as offsets into the block, with
    // room for the lanes that each store writes past them.
    let mut undecided = [0u64; BLOCK + MAX_WIDTH];
    let base = pairs.as_mut_ptr();
    for block in (0..n).step_by(BLOCK) {
        let len = BLOCK.min(n - block);
        // SAFETY: the block is inside `pairs`, and nothing writes to it while `at` is read
        // (the third pass, which writes, reads through `base`).
        let at = unsafe { std::slice::from_raw_parts(base.add(block), len) };
        let steps = len.div_ceil(W);
        let mut open = 0;
        for (s, hit) in colliding.iter_mut().enumerate().take(steps) {
            // SAFETY: the pairs below `n` are inside `pairs`, not yet written by any third
            // pass (which writes at most up to the current block).
            unsafe { prefetch_boxes(obbs, base, n, block + (s + PREFETCH_STEPS) * W, W) };
            let live = isa.first(len - s * W);
            // SAFETY: every pair's boxes are inside both slices, checked above.
            let front = unsafe { Front::of(isa, obbs, Kappa::Bounded(skew), &step(at, s)) };
            let shares = front.shares_a_point(isa);
            let shares = shares & live;
            let rest = (!shares & live).bits();
            *hit = shares.bits();
            let offsets = isa.lane_numbers() | isa.splat_u64((s * W) as u64);
            // SAFETY: `undecided` has room for the block's pairs and `MAX_WIDTH` more.
            unsafe { isa.compress_store(rest, offsets, undecided.as_mut_ptr().add(open)) };
            open += rest.count_ones() as usize;
        }
        for chunk in undecided[..open].chunks(W) {
            let p = lanes(at, |l| chunk[l.min(chunk.len() - 1)] as usize);
            // SAFETY: as above.
            let separated = unsafe { Front::of(isa, obbs, Kappa::Read(slack), &p) }.separated(isa);
            let separated = separated.bits();
            for (l, &q) in chunk.iter().enumerate() {
                let q = q as usize;
                colliding[q / W] |= u8::from(separated >> l & 1 == 0) << (q % W);
            }
        }
        for (s, &hit) in colliding.iter().enumerate().take(steps) {
            let from = block + s * W;
            // SAFETY: the load reads the step's pairs, from `pairs` when the step is whole,
            // else from a copy of its pairs; the store writes `W` pairs at `kept`, at most
            // `from`: below every pair not yet read, and inside `pairs` and the room reserved.
            unsafe {
                let v = if s < len / W {
                    isa.load_u64(base.add(from).cast())
                } else {
                    let mut tail = [0u64; W];
                    let rest = len - s * W;
                    std::ptr::copy_nonoverlapping(base.add(from).cast(), tail.as_mut_ptr(), rest);
                    isa.load_u64(tail.as_ptr())
                };
                isa.compress_store(hit, v, base.add(kept).cast());
            }
            kept += hit.count_ones() as usize;
        }
    }
    pairs.truncate(kept);
}

/// Prefetches into the first-level cache both boxes of the `w` pairs from `at` (those below
/// `n`): each box is 128 bytes, and its bytes 0, 64 and 127 lie on every line it covers (two or
/// three, as it is aligned).
/// SAFETY: the pairs below `n` must be readable at `pairs`.
#[inline(always)]
unsafe fn prefetch_boxes(obbs: &[Obb], pairs: *const [u32; 2], n: usize, at: usize, w: usize) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    for k in at..(at + w).min(n) {
        // SAFETY: `k < n`, the caller's promise.
        for i in unsafe { *pairs.add(k) } {
            // A prefetch never faults; the address is only a hint (`wrapping_add`: not even an
            // index checked by the caller is needed).
            let b = obbs.as_ptr().wrapping_add(i as usize).cast::<i8>();
            // SAFETY: SSE, which every x86_64 CPU has.
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(b);
                _mm_prefetch::<_MM_HINT_T0>(b.wrapping_add(64));
                _mm_prefetch::<_MM_HINT_T0>(b.wrapping_add(size_of::<Obb>() - 1));
            }
        }
    }
}

/// The pairs of step `s` of `at`, the last pair repeated past the end of `at`.
#[inline(always)]
fn step<const W: usize>(at: &[[u32; 2]], s: usize) -> [[u32; 2]; W] {
    match at.get(s * W..(s + 1) * W) {
        Some(full) => full.try_into().expect("a step is W pairs"),
        None => lanes(at, |l| s * W + l),
    }
}

/// The pairs `at[index(l)]` for the `W` lanes, the last pair repeated past the end of `at`.
#[inline(always)]
fn lanes<const W: usize>(at: &[[u32; 2]], index: impl Fn(usize) -> usize) -> [[u32; 2]; W] {
    std::array::from_fn(|l| at[index(l).min(at.len() - 1)])
}

/// The `kappa` of the boxes `at`. SAFETY: every index must be below `slack.len()` and below
/// a length that [`fits`] accepts (the gather's offsets are 32-bit).
#[inline(always)]
unsafe fn gather_kappa<I: Isa<W>, const W: usize>(isa: I, slack: &[Slack], at: [usize; W]) -> I::F {
    let mut offsets = [0; W];
    for (o, &i) in offsets.iter_mut().zip(&at) {
        *o = (i * SLACK_STRIDE + KAPPA) as u32;
    }
    // SAFETY: the caller's promise.
    unsafe { isa.gather(slack.as_ptr().cast::<f64>(), offsets) }
}

/// Where [`Front::of`] takes the boxes' `kappa` from.
#[derive(Clone, Copy)]
enum Kappa<'a> {
    /// Each box's own, gathered from its slack: the whole SAT's margin, exactly as
    /// `sat_lanes` computes it.
    Read(&'a [Slack]),
    /// `fl(skew · hsum)` for the frame's skew, at least each box's own (`Slack::with_skew`),
    /// so the margin is at least the exact one: enough for the first pass, which only needs a
    /// margin that large, and with no gather.
    Bounded(f64),
}

/// What the SAT reads and computes first for the `W` pairs of a step, and what both passes
/// need: the boxes read whole ([`Isa::boxes`]), `kappa`, the margin, and the centres' offset's
/// projections on each box's axes. Every value is computed as `sat_lanes` computes it (the
/// margin with [`Kappa::Read`]; with [`Kappa::Bounded`] it is the same or larger).
struct Front<F> {
    ah: [F; 3],
    bh: [F; 3],
    a_axes: [[F; 3]; 3],
    b_axes: [[F; 3]; 3],
    /// The margin `s` of every axis test.
    s: F,
    /// `tw · a_k` and `tw · b_k`.
    t: [F; 3],
    u: [F; 3],
}

impl<F: Lanes> Front<F> {
    /// SAFETY: every index of `p` must be below `obbs.len()`, and below the slack's length
    /// with [`Kappa::Read`].
    #[inline(always)]
    unsafe fn of<I: Isa<W, F = F>, const W: usize>(
        isa: I,
        obbs: &[Obb],
        kappa: Kappa,
        p: &[[u32; 2]; W],
    ) -> Front<F> {
        // Plain loops here and below, no `map` or `from_fn`: their closures are compiled
        // outside the function that enables the instruction set, so vector work in them would
        // be a call each.
        let (mut a_at, mut b_at) = ([0; W], [0; W]);
        for (l, &[i, j]) in p.iter().enumerate() {
            (a_at[l], b_at[l]) = (i as usize, j as usize);
        }
        // SAFETY: the caller's indices are inside `obbs`.
        let (a_boxes, b_boxes) = unsafe { (isa.boxes(obbs, a_at), isa.boxes(obbs, b_at)) };
        let (ah, bh) = (field3(&a_boxes, HALF), field3(&b_boxes, HALF));
        // `Slack::hsum`, summed here from the halves just read, in its order: two gathers
        // fewer.
        let (a_hsum, b_hsum) = (ah[0] + ah[1] + ah[2], bh[0] + bh[1] + bh[2]);
        let (a_kappa, b_kappa) = match kappa {
            // SAFETY: the caller's indices are inside `slack`, and `fits` keeps their
            // offsets below 2^31.
            Kappa::Read(slack) => unsafe {
                (
                    gather_kappa(isa, slack, a_at),
                    gather_kappa(isa, slack, b_at),
                )
            },
            Kappa::Bounded(skew) => (isa.splat(skew) * a_hsum, isa.splat(skew) * b_hsum),
        };
        let (a_center, b_center) = (field3(&a_boxes, CENTER), field3(&b_boxes, CENTER));
        let a_axes = axes(&a_boxes);
        let b_axes = axes(&b_boxes);
        let mut tw = [a_hsum; 3];
        for k in 0..3 {
            tw[k] = b_center[k] - a_center[k];
        }
        let tnorm = tw[0].abs() + tw[1].abs() + tw[2].abs();
        let hsums = tnorm + a_hsum + b_hsum;
        let s = a_kappa + b_kappa + isa.splat(64.0 * U) * hsums + isa.splat(MARGIN_FLOOR);
        let (mut t, mut u) = ([s; 3], [s; 3]);
        for k in 0..3 {
            t[k] = dot(&tw, &a_axes[k]);
            u[k] = dot(&tw, &b_axes[k]);
        }
        Front {
            ah,
            bh,
            a_axes,
            b_axes,
            s,
            t,
            u,
        }
    }

    /// The lanes whose two boxes share a point of the segment between their centres, for
    /// certain: then the boxes intersect, and the SAT, which never calls intersecting boxes
    /// separated, finds them colliding. The point `c_A + αT` lies in the first box when
    /// `α |t_k| <= h_k - 2s` for each of its axes, and in the second when `(1 - α) |u_k| <=
    /// h_k - 2s` for each of its; `2s` covers the rounding and the boxes' skew (the proof is in
    /// docs/sat.md, "A sufficient test: a point between the centres"). `α` is the middle of the
    /// range that the two conditions leave, found with approximate reciprocals: any `α` in
    /// `[0, 1]` would do, since the conditions are then checked as computed. False on NaN.
    #[inline(always)]
    fn shares_a_point<I: Isa<W, F = F>, const W: usize>(&self, isa: I) -> F::Mask {
        let (zero, one) = (isa.splat(0.0), isa.splat(1.0));
        let m = self.s + self.s;
        let (mut room_a, mut room_b, mut t, mut u) = ([m; 3], [m; 3], [m; 3], [m; 3]);
        for k in 0..3 {
            (room_a[k], room_b[k]) = (self.ah[k] - m, self.bh[k] - m);
            (t[k], u[k]) = (self.t[k].abs(), self.u[k].abs());
        }
        // The largest α the first box allows, and the largest 1 - α the second allows (a zero
        // offset's ratio, infinite or NaN, leaves them as they are).
        let (mut hi, mut lo) = (one, one);
        for k in 0..3 {
            hi = (room_a[k] * t[k].recip()).min(hi);
            lo = (room_b[k] * u[k].recip()).min(lo);
        }
        let mid = isa.splat(0.5) * (hi + (one - lo));
        // In [0, 1] (a NaN becomes 1: `min` returns its second operand then).
        let alpha = mid.min(one).max(zero);
        let beta = one - alpha;
        let mut holds = isa.first(W);
        for k in 0..3 {
            holds = holds & (alpha * t[k]).le(room_a[k]) & (beta * u[k]).le(room_b[k]);
        }
        holds
    }

    /// The lanes that one of the 15 axes separates: `sat_lanes` step by step. Plain loops, not
    /// closures: a closure here is not always inlined, and a call per vector costs more than
    /// the vector.
    #[inline(always)]
    fn separated<I: Isa<W, F = F>, const W: usize>(&self, isa: I) -> Mask<I, W> {
        let Front {
            ah,
            bh,
            a_axes,
            b_axes,
            s,
            t,
            u,
        } = *self;
        let zero = isa.splat(0.0);
        let (mut r, mut ar) = ([[zero; 3]; 3], [[zero; 3]; 3]);
        for a in 0..3 {
            for b in 0..3 {
                r[a][b] = dot(&a_axes[a], &b_axes[b]);
                ar[a][b] = r[a][b].abs();
            }
        }
        let mut sep = !isa.first(W);
        for a in 0..3 {
            let rb = bh[0] * ar[a][0] + bh[1] * ar[a][1] + bh[2] * ar[a][2];
            sep = sep | t[a].abs().gt(ah[a] + rb + s);
        }
        for b in 0..3 {
            let ra = ah[0] * ar[0][b] + ah[1] * ar[1][b] + ah[2] * ar[2][b];
            sep = sep | u[b].abs().gt(ra + bh[b] + s);
        }
        if sep.bits() == all_lanes::<W>() {
            return sep;
        }
        for a in 0..3 {
            let (a1, a2) = ((a + 1) % 3, (a + 2) % 3);
            let mut m = [zero; 3];
            for (k, mk) in m.iter_mut().enumerate() {
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                *mk = (r[a1][k1] * r[a2][k2] - r[a2][k1] * r[a1][k2]).abs();
            }
            for b in 0..3 {
                let (b1, b2) = ((b + 1) % 3, (b + 2) % 3);
                let lhs = (t[a2] * r[a1][b] - t[a1] * r[a2][b]).abs();
                let ra = ah[a1] * ar[a2][b] + ah[a2] * ar[a1][b];
                let rb = bh[b1] * m[b2] + bh[b2] * m[b1];
                sep = sep | lhs.gt(ra + rb + s);
            }
        }
        sep
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sat::boxes_collide;
    use crate::scene::ORTHO_TOL;
    use crate::simd::{Avx2, Avx512};
    use nalgebra::{Matrix3, Rotation3, Vector3};
    use proptest::prelude::*;

    /// Axes of a random rotation, each entry then moved by up to `skew`: orthonormal only to
    /// about `2 * skew`, as single-precision axes are (and up to the validation's limit).
    fn axes(angles: [f64; 3], skew: [f64; 9]) -> [[f64; 3]; 3] {
        let r = Rotation3::from_euler_angles(angles[0], angles[1], angles[2]);
        std::array::from_fn(|k| std::array::from_fn(|x| r[(k, x)] + skew[3 * k + x]))
    }

    /// `v` in `b`'s frame, in units of its half-lengths: the 3x3 system solved by LU, an
    /// independent route to the test's answer. Its own error is a few ulps.
    fn coordinates(b: &Obb, v: Vector3<f64>) -> Option<[f64; 3]> {
        let m = Matrix3::from_fn(|x, k| b.axes[k][x]);
        let x = m.lu().solve(&v)?;
        Some(std::array::from_fn(|k| x[k] / b.half[k]))
    }

    /// Box coordinates near the faces, or anywhere inside and a little beyond.
    fn near_faces() -> impl Strategy<Value = [f64; 3]> {
        proptest::array::uniform3(prop_oneof![
            -1.0001..1.0001f64,
            0.9999..1.0001f64,
            -1.0001..-0.9999f64
        ])
    }

    /// Two boxes at a scale of `10^scale`, and a point `p` at `alpha` of the way from the first
    /// centre to the second, with `p` near faces of both boxes (`inner_a`, `inner_b`: its box
    /// coordinates, before rounding).
    fn pair_strategy() -> impl Strategy<Value = (Obb, Obb)> {
        let box_axes = (
            proptest::array::uniform3(-3.2..3.2f64),
            proptest::array::uniform9(-2.4e-6..2.4e-6f64),
        );
        (
            (box_axes.clone(), box_axes),
            proptest::array::uniform3(0.05..4.0f64),
            (near_faces(), near_faces()),
            0.05..0.95f64,
            -300i32..7,
        )
            .prop_map(|((aa, ab), ha, (inner_a, inner_b), alpha, scale)| {
                let s = 10f64.powi(scale);
                let a = Obb {
                    center: [s, -2.0 * s, 0.5 * s],
                    axes: axes(aa.0, aa.1),
                    half: ha.map(|h| h * s),
                    group: 0,
                };
                // p - c_A, then the second centre: p - c_B = (alpha - 1) T.
                let d: [f64; 3] = std::array::from_fn(|x| {
                    (0..3).map(|k| inner_a[k] * a.half[k] * a.axes[k][x]).sum()
                });
                let t = d.map(|dx| dx / alpha);
                let b_axes = axes(ab.0, ab.1);
                let from_b = t.map(|tx| (alpha - 1.0) * tx);
                let half = std::array::from_fn(|k| {
                    let y: f64 = (0..3).map(|x| b_axes[k][x] * from_b[x]).sum();
                    (y / inner_b[k]).abs()
                });
                let b = Obb {
                    center: std::array::from_fn(|x| a.center[x] + t[x]),
                    axes: b_axes,
                    half,
                    group: 0,
                };
                (a, b)
            })
    }

    /// The pairs `[2l, 2l + 1]` of `obbs` that the first pass accepts, by `l`, with `kappa`.
    fn first_pass<I: Isa<W>, const W: usize>(isa: I, obbs: &[Obb], kappa: Kappa) -> Vec<usize> {
        let mut accepted = Vec::new();
        for first in (0..obbs.len() / 2).step_by(W) {
            let p: [[u32; 2]; W] =
                std::array::from_fn(|l| [2 * (first + l) as u32, 2 * (first + l) as u32 + 1]);
            // SAFETY: every index is in range (the callers pass a multiple of `2 W` boxes).
            let front = unsafe { Front::of(isa, obbs, kappa, &p) };
            let shares = front.shares_a_point(isa);
            accepted.extend(
                (0..W)
                    .filter(|l| shares.bits() >> l & 1 == 1)
                    .map(|l| first + l),
            );
        }
        accepted
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Whenever the first pass accepts a pair, some point between the centres lies in both
        /// boxes (by an independent solve), so the boxes intersect, and the SAT agrees. The
        /// points lie near faces of both boxes, whose axes are skewed up to the validation's
        /// limit: without its margin the test accepts pairs whose segment misses a box.
        #[test]
        fn an_accepted_pair_shares_a_point_between_the_centres(
            pairs in proptest::collection::vec(pair_strategy(), MAX_WIDTH)
        ) {
            let obbs: Vec<Obb> = pairs.iter().flat_map(|(a, b)| [a.clone(), b.clone()]).collect();
            prop_assume!(obbs.iter().all(|b| b.ortho_error() <= ORTHO_TOL));
            prop_assume!(obbs.iter().all(|b| b.half.iter().all(|h| h.is_finite())));
            let (slack, skews): (Vec<Slack>, Vec<f64>) = obbs.iter().map(Slack::with_skew).unzip();
            // Each box's own slack (the least margin, the proof's case) and the bound from the
            // largest skew, as `retain_colliding` runs the pass.
            let skew = skews.into_iter().fold(0.0, f64::max);
            let mut accepted = Vec::new();
            for kappa in [Kappa::Read(&slack), Kappa::Bounded(skew)] {
                if let Some(isa) = Avx512::detect() {
                    accepted.extend(first_pass(isa, &obbs, kappa));
                }
                if let Some(isa) = Avx2::detect() {
                    accepted.extend(first_pass(isa, &obbs, kappa));
                }
            }
            for (l, (a, b)) in accepted.into_iter().map(|l| (l, &pairs[l])) {
                // The point c_A + αT is at αv from c_A and at (α - 1)w from c_B, v and w the
                // centres' offset in each box's coordinates: the α that both boxes allow.
                let t = Vector3::from(b.center) - Vector3::from(a.center);
                let v = coordinates(a, t).expect("skewed axes are still independent");
                let w = coordinates(b, t).expect("skewed axes are still independent");
                let hi = v.iter().map(|v| 1.0 / v.abs()).fold(1.0, f64::min);
                let lo = w.iter().map(|w| 1.0 - 1.0 / w.abs()).fold(0.0, f64::max);
                // The solve's own error, a few ulps, and no more.
                prop_assert!(lo <= hi + 1e-12, "no common point: α in [{lo}, {hi}], {a:?} {b:?}");
                prop_assert!(boxes_collide(a, &slack[2 * l], b, &slack[2 * l + 1]));
            }
        }
    }
}
