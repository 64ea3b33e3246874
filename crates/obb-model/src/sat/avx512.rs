//! The SAT of [`super::retain_colliding`] on eight pairs at a time, written with AVX-512
//! intrinsics.
//!
//! The compiler's own vectorisation of `sat_lanes` spends most of its time putting each box's
//! values into their lanes: the two boxes of a pair lie anywhere in the scene, so every value
//! is a load, a shuffle or a spill. Here eight boxes are read whole and transposed in registers
//! (`crate::avx512::boxes`), so that each vector holds one value of the eight boxes. Every
//! product, sum and comparison is the one `sat_lanes` writes, in the same order and without
//! fused multiply-add, so each lane rounds exactly as [`super::boxes_collide`] does. A pair is
//! accepted without the SAT only when its boxes share a point for certain (a point between the
//! centres, proved in docs/sat.md), which `boxes_collide` never calls separated: the two give
//! the same answer on every pair of valid boxes, which the tests check on random and touching
//! pairs.

use super::{Slack, MARGIN_FLOOR};
use crate::aabb::U;
use crate::avx512::{abs, add, boxes, dot, field3, gather, mul, scaled, sub, AXES, CENTER, HALF};
use crate::scene::Obb;
use std::arch::x86_64::*;
use std::mem::{offset_of, size_of};

/// Pairs tested side by side: the f64 lanes of a 512-bit vector.
const WIDTH: usize = 8;
/// Slacks as arrays of f64, for the gathers' indices.
const SLACK_STRIDE: usize = size_of::<Slack>() / 8;
const KAPPA: usize = offset_of!(Slack, kappa) / 8;
const _: () = assert!(size_of::<Slack>().is_multiple_of(8));

/// Whether [`retain_colliding`] can run here on `n` boxes: the CPU has AVX-512F (and AVX2 and
/// POPCNT), and every box's slack offset fits the gathers' 32-bit indices.
pub(super) fn usable(n: usize) -> bool {
    n.checked_mul(SLACK_STRIDE)
        .is_some_and(|x| x <= i32::MAX as usize)
        && is_x86_feature_detected!("avx512f")
        && is_x86_feature_detected!("avx2")
        && is_x86_feature_detected!("popcnt")
}

/// Pairs taken at a time through the three passes of [`retain_colliding`]: small enough that
/// their boxes are still in the caches when the second pass reads them again.
const BLOCK: usize = 1024;

/// [`super::retain_colliding`], eight pairs per step. Only for a CPU and box count that
/// [`usable`] accepts. A pair naming a box past `obbs` or `slack` panics, as indexing does.
///
/// Nine in ten of the pairs the grid hands over collide, so most steps need all 15 axes. In a
/// block of pairs, a first pass looks for a point between the two centres inside both boxes
/// ([`Front::shares_a_point`]: a sufficient test for colliding, which needs 6 of the SAT's 15
/// dot products, and decides five in six of the surgical scene's pairs); the second pass runs
/// the whole SAT on the pairs the first could not decide, packed eight to a step; the third
/// keeps the colliding pairs, in their order.
#[target_feature(enable = "avx512f,avx2,popcnt")]
pub(super) fn retain_colliding(obbs: &[Obb], slack: &[Slack], pairs: &mut Vec<[u32; 2]>) {
    debug_assert!(usable(obbs.len()));
    let n = pairs.len();
    let boxes = obbs.len().min(slack.len());
    // The loads and gathers do not check their indices: this does.
    if let Some(q) = pairs
        .iter()
        .find(|q| q[0] as usize >= boxes || q[1] as usize >= boxes)
    {
        panic!("pair {q:?} names a box past the {boxes} boxes");
    }
    let mut kept = 0;
    // Bit `l` of `colliding[s]`: the pair at lane `l` of step `s` collides.
    let mut colliding = [0u8; BLOCK / WIDTH];
    // The block's pairs that the first pass left undecided, as offsets into the block, with
    // room for the sixteen lanes that each store writes.
    let mut undecided = [0u32; BLOCK + 2 * WIDTH];
    let lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    let base = pairs.as_mut_ptr();
    for block in (0..n).step_by(BLOCK) {
        let len = BLOCK.min(n - block);
        // SAFETY: the block is inside `pairs`, and nothing writes to it while `at` is read
        // (the third pass, which writes, reads through `base`).
        let at = unsafe { std::slice::from_raw_parts(base.add(block), len) };
        let steps = len.div_ceil(WIDTH);
        let mut open = 0;
        for (s, hit) in colliding.iter_mut().enumerate().take(steps) {
            let p = step(at, s);
            // SAFETY: every pair's boxes are inside both slices, checked above; `undecided`
            // has room for the block's pairs and sixteen more, which the store may write.
            unsafe {
                let live = in_range(len - s * WIDTH);
                *hit = Front::of(obbs, slack, &p).shares_a_point() & live;
                let rest = !*hit & live;
                // (Sixteen 32-bit lanes, of which eight are used: AVX-512F alone has no
                // compress of eight.)
                let offsets = _mm512_add_epi32(_mm512_set1_epi32((s * WIDTH) as i32), lane);
                let packed = _mm512_maskz_compress_epi32(u16::from(rest), offsets);
                _mm512_storeu_si512(undecided.as_mut_ptr().add(open).cast(), packed);
                open += rest.count_ones() as usize;
            }
        }
        for chunk in undecided[..open].chunks(WIDTH) {
            let p = lanes(at, |l| chunk[l.min(chunk.len() - 1)] as usize);
            // SAFETY: as above.
            let separated = unsafe { Front::of(obbs, slack, &p).separated() };
            for (l, &q) in chunk.iter().enumerate() {
                let q = q as usize;
                colliding[q / WIDTH] |= u8::from(separated >> l & 1 == 0) << (q % WIDTH);
            }
        }
        for (s, &hit) in colliding.iter().enumerate().take(steps) {
            // SAFETY: the load reads the step's pairs, those past the block's end masked off;
            // the masked store writes `hit`'s count of pairs at `kept`, at most `block + s *
            // WIDTH`: inside `pairs`, and below every pair not yet read.
            unsafe {
                let from = base.add(block + s * WIDTH).cast();
                let v = _mm512_maskz_loadu_epi64(in_range(len - s * WIDTH), from);
                // Compressed in a register, then stored under a mask of the kept count: a
                // compress straight to memory is microcoded on AMD's Zen 4 (about 7 % of the
                // SAT's time there, sampled on the instruction after it), a masked store is not.
                let count = hit.count_ones();
                let low = ((1u16 << count) - 1) as u8;
                let packed = _mm512_maskz_compress_epi64(hit, v);
                _mm512_mask_storeu_epi64(base.add(kept).cast(), low, packed);
                kept += count as usize;
            }
        }
    }
    pairs.truncate(kept);
}

/// The pairs of step `s` of `at`, the last pair repeated past the end of `at`.
#[inline(always)]
fn step(at: &[[u32; 2]], s: usize) -> [[u32; 2]; WIDTH] {
    match at.get(s * WIDTH..(s + 1) * WIDTH) {
        Some(full) => full.try_into().expect("a step is WIDTH pairs"),
        None => lanes(at, |l| s * WIDTH + l),
    }
}

/// The pairs `at[index(l)]` for the eight lanes, the last pair repeated past the end of `at`.
#[inline(always)]
fn lanes(at: &[[u32; 2]], index: impl Fn(usize) -> usize) -> [[u32; 2]; WIDTH] {
    std::array::from_fn(|l| at[index(l).min(at.len() - 1)])
}

/// The lanes below `n` (all eight when `n >= 8`).
#[inline(always)]
fn in_range(n: usize) -> u8 {
    (u16::MAX >> (16 - WIDTH.min(n))) as u8
}

/// The lanes where `lhs > rhs` (false on NaN, as in Rust).
#[inline]
#[target_feature(enable = "avx512f")]
fn greater(lhs: __m512d, rhs: __m512d) -> u8 {
    _mm512_cmp_pd_mask::<_CMP_GT_OQ>(lhs, rhs)
}

/// What the SAT reads and computes first for the eight pairs `p`, and what both passes need:
/// the boxes read whole ([`boxes`]), `kappa` gathered, the margin, and the centres' offset's
/// projections on each box's axes. Every value is computed as `sat_lanes` computes it.
struct Front {
    ah: [__m512d; 3],
    bh: [__m512d; 3],
    a_axes: [[__m512d; 3]; 3],
    b_axes: [[__m512d; 3]; 3],
    /// The margin `s` of every axis test.
    s: __m512d,
    /// `tw · a_k` and `tw · b_k`.
    t: [__m512d; 3],
    u: [__m512d; 3],
}

impl Front {
    /// SAFETY: every index of `p` must be below `obbs.len()` and `slack.len()`.
    #[inline]
    #[target_feature(enable = "avx512f,avx2")]
    unsafe fn of(obbs: &[Obb], slack: &[Slack], p: &[[u32; 2]; WIDTH]) -> Front {
        let sb = slack.as_ptr().cast::<f64>();
        // SAFETY: `p` is 64 bytes.
        let v = unsafe { _mm512_loadu_si512(p.as_ptr().cast()) };
        // Each pair is one 64-bit lane, its first index in the low half.
        let i = _mm512_cvtepi64_epi32(v);
        let j = _mm512_cvtepi64_epi32(_mm512_srli_epi64::<32>(v));
        let (a_slack, b_slack) = (scaled(i, SLACK_STRIDE), scaled(j, SLACK_STRIDE));
        // SAFETY: the caller's indices are inside both slices.
        let (a_boxes, b_boxes, a_kappa, b_kappa) = unsafe {
            (
                boxes(obbs, p.map(|q| q[0] as usize)),
                boxes(obbs, p.map(|q| q[1] as usize)),
                gather(sb, a_slack, KAPPA),
                gather(sb, b_slack, KAPPA),
            )
        };
        let (a_center, b_center) = (field3(&a_boxes, CENTER), field3(&b_boxes, CENTER));
        let (ah, bh) = (field3(&a_boxes, HALF), field3(&b_boxes, HALF));
        // `Slack::hsum`, summed here from the halves just read, in its order: two gathers
        // fewer.
        let (a_hsum, b_hsum) = (add(add(ah[0], ah[1]), ah[2]), add(add(bh[0], bh[1]), bh[2]));
        let a_axes = [0, 3, 6].map(|row| field3(&a_boxes, AXES + row));
        let b_axes = [0, 3, 6].map(|row| field3(&b_boxes, AXES + row));
        let zero = _mm512_setzero_pd();
        let mut tw = [zero; 3];
        for (k, w) in tw.iter_mut().enumerate() {
            *w = sub(b_center[k], a_center[k]);
        }
        let tnorm = add(add(abs(tw[0]), abs(tw[1])), abs(tw[2]));
        let hsums = add(add(tnorm, a_hsum), b_hsum);
        let s = add(
            add(add(a_kappa, b_kappa), mul(_mm512_set1_pd(64.0 * U), hsums)),
            _mm512_set1_pd(MARGIN_FLOOR),
        );
        let (mut t, mut u) = ([zero; 3], [zero; 3]);
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
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn shares_a_point(&self) -> u8 {
        let (zero, one) = (_mm512_setzero_pd(), _mm512_set1_pd(1.0));
        let m = add(self.s, self.s);
        let (mut room_a, mut room_b, mut t, mut u) = ([zero; 3], [zero; 3], [zero; 3], [zero; 3]);
        for k in 0..3 {
            (room_a[k], room_b[k]) = (sub(self.ah[k], m), sub(self.bh[k], m));
            (t[k], u[k]) = (abs(self.t[k]), abs(self.u[k]));
        }
        // The largest α the first box allows, and the largest 1 - α the second allows.
        let (mut hi, mut lo) = (one, one);
        for k in 0..3 {
            hi = _mm512_min_pd(mul(room_a[k], _mm512_rcp14_pd(t[k])), hi);
            lo = _mm512_min_pd(mul(room_b[k], _mm512_rcp14_pd(u[k])), lo);
        }
        let mid = mul(_mm512_set1_pd(0.5), add(hi, sub(one, lo)));
        // In [0, 1] (a NaN becomes 1: `min_pd` returns its second operand then).
        let alpha = _mm512_max_pd(_mm512_min_pd(mid, one), zero);
        let beta = sub(one, alpha);
        let mut holds = u8::MAX;
        for k in 0..3 {
            holds &= _mm512_cmp_pd_mask::<_CMP_LE_OQ>(mul(alpha, t[k]), room_a[k]);
            holds &= _mm512_cmp_pd_mask::<_CMP_LE_OQ>(mul(beta, u[k]), room_b[k]);
        }
        holds
    }

    /// The lanes that one of the 15 axes separates: `sat_lanes` step by step. Plain loops, not
    /// closures: a closure here is not always inlined, and a call per vector costs more than
    /// the vector.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn separated(&self) -> u8 {
        let Front {
            ah,
            bh,
            a_axes,
            b_axes,
            s,
            t,
            u,
        } = *self;
        let zero = _mm512_setzero_pd();
        let (mut r, mut ar) = ([[zero; 3]; 3], [[zero; 3]; 3]);
        for a in 0..3 {
            for b in 0..3 {
                r[a][b] = dot(&a_axes[a], &b_axes[b]);
                ar[a][b] = abs(r[a][b]);
            }
        }
        let mut sep = 0u8;
        for a in 0..3 {
            let rb = add(
                add(mul(bh[0], ar[a][0]), mul(bh[1], ar[a][1])),
                mul(bh[2], ar[a][2]),
            );
            sep |= greater(abs(t[a]), add(add(ah[a], rb), s));
        }
        for b in 0..3 {
            let ra = add(
                add(mul(ah[0], ar[0][b]), mul(ah[1], ar[1][b])),
                mul(ah[2], ar[2][b]),
            );
            sep |= greater(abs(u[b]), add(add(ra, bh[b]), s));
        }
        if sep == u8::MAX {
            return sep;
        }
        for a in 0..3 {
            let (a1, a2) = ((a + 1) % 3, (a + 2) % 3);
            let mut m = [zero; 3];
            for (k, mk) in m.iter_mut().enumerate() {
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                *mk = abs(sub(mul(r[a1][k1], r[a2][k2]), mul(r[a2][k1], r[a1][k2])));
            }
            for b in 0..3 {
                let (b1, b2) = ((b + 1) % 3, (b + 2) % 3);
                let lhs = abs(sub(mul(t[a2], r[a1][b]), mul(t[a1], r[a2][b])));
                let ra = add(mul(ah[a1], ar[a2][b]), mul(ah[a2], ar[a1][b]));
                let rb = add(mul(bh[b1], m[b2]), mul(bh[b2], m[b1]));
                sep |= greater(lhs, add(add(ra, rb), s));
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

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Whenever the first pass accepts a pair, some point between the centres lies in both
        /// boxes (by an independent solve), so the boxes intersect, and the SAT agrees. The
        /// points lie near faces of both boxes, whose axes are skewed up to the validation's
        /// limit: without its margin the test accepts pairs whose segment misses a box.
        #[test]
        fn an_accepted_pair_shares_a_point_between_the_centres(
            pairs in proptest::collection::vec(pair_strategy(), WIDTH)
        ) {
            let obbs: Vec<Obb> = pairs.iter().flat_map(|(a, b)| [a.clone(), b.clone()]).collect();
            prop_assume!(obbs.iter().all(|b| b.ortho_error() <= ORTHO_TOL));
            prop_assume!(obbs.iter().all(|b| b.half.iter().all(|h| h.is_finite())));
            if !usable(obbs.len()) {
                // `retain_colliding` then runs `retain_colliding_lanes`, which has no first pass.
                return Ok(());
            }
            let slack: Vec<Slack> = obbs.iter().map(Slack::of).collect();
            let p: [[u32; 2]; WIDTH] = std::array::from_fn(|l| [2 * l as u32, 2 * l as u32 + 1]);
            // SAFETY: checked above that this CPU has the features; every index is in range.
            let accepted = unsafe { Front::of(&obbs, &slack, &p).shares_a_point() };
            for (l, (a, b)) in pairs.iter().enumerate() {
                if accepted >> l & 1 == 0 {
                    continue;
                }
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
