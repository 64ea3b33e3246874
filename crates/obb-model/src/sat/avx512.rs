//! The SAT of [`super::retain_colliding`] on eight pairs at a time, written with AVX-512
//! intrinsics.
//!
//! The compiler's own vectorisation of `sat_lanes` spends most of its time putting each box's
//! values into their lanes: the two boxes of a pair lie anywhere in the scene, so every value
//! is a load, a shuffle or a spill. Here eight boxes are read whole and transposed in registers
//! (`crate::avx512::boxes`), so that each vector holds one value of the eight boxes. Every
//! product, sum and comparison is the one `sat_lanes` writes, in the same order and without
//! fused multiply-add, so each lane rounds exactly as [`super::boxes_collide`] does: the two
//! give the same answer on every pair, which the tests check on random and touching pairs.

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

/// [`super::retain_colliding`], eight pairs per step. Only for a CPU and box count that
/// [`usable`] accepts. A pair naming a box past `obbs` or `slack` panics, as indexing does.
#[target_feature(enable = "avx512f,avx2,popcnt")]
pub(super) fn retain_colliding(obbs: &[Obb], slack: &[Slack], pairs: &mut Vec<[u32; 2]>) {
    debug_assert!(usable(obbs.len()));
    let n = pairs.len();
    let boxes = obbs.len().min(slack.len());
    let mut kept = 0;
    for start in (0..n).step_by(WIDTH) {
        // The last step repeats its final pair to fill the lanes.
        let take = WIDTH.min(n - start);
        let mut p = [pairs[n - 1]; WIDTH];
        p[..take].copy_from_slice(&pairs[start..start + take]);
        // The loads and gathers do not check their indices: this does.
        if let Some(q) = p
            .iter()
            .find(|q| q[0] as usize >= boxes || q[1] as usize >= boxes)
        {
            panic!("pair {q:?} names a box past the {boxes} boxes");
        }
        // SAFETY: `p` is 64 bytes; every index is below `boxes`, checked above, so each load
        // and gather reads inside `obbs` or `slack`; the masked store writes `keep`'s count of
        // pairs at `kept`, which is at most `start + take - count`, inside `pairs`.
        unsafe {
            // Each pair as one 64-bit lane, its first index in the low half.
            let v = _mm512_loadu_si512(p.as_ptr().cast());
            let i = _mm512_cvtepi64_epi32(v);
            let j = _mm512_cvtepi64_epi32(_mm512_srli_epi64::<32>(v));
            let separated = separated(obbs, slack, &p, i, j);
            let keep = !separated & (u16::MAX >> (16 - take)) as u8;
            // Compressed in a register, then stored under a mask of the kept count: a
            // compress straight to memory is microcoded on AMD's Zen 4 (about 7 % of the SAT's
            // time there, sampled on the instruction after it), a masked store is not.
            let count = keep.count_ones();
            let low = ((1u16 << count) - 1) as u8;
            let packed = _mm512_maskz_compress_epi64(keep, v);
            _mm512_mask_storeu_epi64(pairs.as_mut_ptr().add(kept).cast(), low, packed);
            kept += count as usize;
        }
    }
    pairs.truncate(kept);
}

/// The lanes where `lhs > rhs` (false on NaN, as in Rust).
#[inline]
#[target_feature(enable = "avx512f")]
fn greater(lhs: __m512d, rhs: __m512d) -> u8 {
    _mm512_cmp_pd_mask::<_CMP_GT_OQ>(lhs, rhs)
}

/// The lanes that one of the 15 axes separates, for the pairs `p` (box indices also as `i` and
/// `j`): `sat_lanes` step by step, the boxes read whole ([`boxes`]), `kappa` gathered.
/// Plain loops, not closures: a closure here is not always inlined, and a call per vector costs
/// more than the vector.
///
/// SAFETY: every index of `p` (and so of `i` and `j`) must be below `obbs.len()` and
/// `slack.len()`.
#[target_feature(enable = "avx512f,avx2")]
unsafe fn separated(
    obbs: &[Obb],
    slack: &[Slack],
    p: &[[u32; 2]; WIDTH],
    i: __m256i,
    j: __m256i,
) -> u8 {
    let sb = slack.as_ptr().cast::<f64>();
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
    // `Slack::hsum`, summed here from the halves just read, in its order: two gathers fewer.
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

    let (mut r, mut ar) = ([[zero; 3]; 3], [[zero; 3]; 3]);
    let (mut t, mut u) = ([zero; 3], [zero; 3]);
    for a in 0..3 {
        for b in 0..3 {
            r[a][b] = dot(&a_axes[a], &b_axes[b]);
            ar[a][b] = abs(r[a][b]);
        }
        t[a] = dot(&tw, &a_axes[a]);
        u[a] = dot(&tw, &b_axes[a]);
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
