//! AVX-512 helpers shared by the vector SAT (`sat/avx512.rs`) and the vector preparation
//! (`prepared/avx512.rs`): each lane of these computes exactly what the scalar operation does
//! (no fused multiply-add), so the vector forms round as the scalar code they follow.

use crate::scene::Obb;
use std::arch::x86_64::*;
use std::mem::{offset_of, size_of};

/// Boxes as arrays of f64, for the gathers' indices: a box's stride and its fields' offsets.
pub(crate) const OBB_STRIDE: usize = size_of::<Obb>() / 8;
pub(crate) const CENTER: usize = offset_of!(Obb, center) / 8;
pub(crate) const AXES: usize = offset_of!(Obb, axes) / 8;
pub(crate) const HALF: usize = offset_of!(Obb, half) / 8;
// `boxes` reads a box as two 8-f64 halves.
const _: () = assert!(OBB_STRIDE == 16);

/// The values at `field` of the eight records at `at` from `base`, both in f64.
///
/// SAFETY: every record read must lie inside the allocation at `base`.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn gather(base: *const f64, at: __m256i, field: usize) -> __m512d {
    unsafe { _mm512_i32gather_pd::<8>(at, base.add(field).cast()) }
}

/// The eight indices `index` in f64 from the start of an array of records of `stride` f64.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) fn scaled(index: __m256i, stride: usize) -> __m256i {
    _mm256_mullo_epi32(index, _mm256_set1_epi32(stride as i32))
}

/// The boxes `at` of `obbs` read whole, as [`OBB_STRIDE`] vectors: lane `l` of vector `f` is
/// the f64 at `f` in box `at[l]` (so `boxes[CENTER + k]` holds the eight centers' `k`).
///
/// Each box is two 64-byte loads, and the two 8x8 blocks are transposed in registers (24
/// shuffles each), where gathering the fifteen fields would take fifteen gathers of eight loads
/// each. On AMD's Zen 4 the gathers bounded both the SAT and the preparation; on the Intel CPU
/// where they were first measured, the two forms were equally fast (docs/engines.md).
///
/// SAFETY: every index of `at` must be below `obbs.len()`.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn boxes(obbs: &[Obb], at: [usize; 8]) -> [__m512d; OBB_STRIDE] {
    let base = obbs.as_ptr().cast::<f64>();
    let mut out = [_mm512_setzero_pd(); OBB_STRIDE];
    // The 8x8 transpose: pairs of rows interleaved, then 128-bit lanes from two pairs, then
    // 256-bit halves from the two groups of four rows.
    let from_pairs_lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
    let from_pairs_hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    for (half, fields) in out.chunks_exact_mut(8).enumerate() {
        let mut row = [_mm512_setzero_pd(); 8];
        for (r, &i) in row.iter_mut().zip(&at) {
            // SAFETY: box `i` is inside `obbs` (the caller's promise) and is OBB_STRIDE f64.
            *r = unsafe { _mm512_loadu_pd(base.add(i * OBB_STRIDE + 8 * half)) };
        }
        let mut pairs = [_mm512_setzero_pd(); 8];
        for (k, p) in pairs.iter_mut().enumerate() {
            let (x, y) = (row[k & !1], row[k | 1]);
            *p = if k % 2 == 0 {
                _mm512_unpacklo_pd(x, y)
            } else {
                _mm512_unpackhi_pd(x, y)
            };
        }
        // quads[4q + m], for the rows 4q to 4q + 3: their field f in the low 256 bits and their
        // field f + 4 in the high, f = [0, 2, 1, 3][m].
        let mut quads = [_mm512_setzero_pd(); 8];
        for q in 0..2 {
            let (even, odd) = (4 * q, 4 * q + 1);
            quads[4 * q] = _mm512_permutex2var_pd(pairs[even], from_pairs_lo, pairs[even + 2]);
            quads[4 * q + 1] = _mm512_permutex2var_pd(pairs[even], from_pairs_hi, pairs[even + 2]);
            quads[4 * q + 2] = _mm512_permutex2var_pd(pairs[odd], from_pairs_lo, pairs[odd + 2]);
            quads[4 * q + 3] = _mm512_permutex2var_pd(pairs[odd], from_pairs_hi, pairs[odd + 2]);
        }
        for (m, field) in [0, 2, 1, 3].into_iter().enumerate() {
            fields[field] = _mm512_shuffle_f64x2::<0x44>(quads[m], quads[4 + m]);
            fields[field + 4] = _mm512_shuffle_f64x2::<0xEE>(quads[m], quads[4 + m]);
        }
    }
    out
}

/// Three consecutive fields of [`boxes`]' vectors, from `field`.
#[inline(always)]
pub(crate) fn field3(boxes: &[__m512d; OBB_STRIDE], field: usize) -> [__m512d; 3] {
    [boxes[field], boxes[field + 1], boxes[field + 2]]
}

#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn add(x: __m512d, y: __m512d) -> __m512d {
    _mm512_add_pd(x, y)
}

#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn sub(x: __m512d, y: __m512d) -> __m512d {
    _mm512_sub_pd(x, y)
}

#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn mul(x: __m512d, y: __m512d) -> __m512d {
    _mm512_mul_pd(x, y)
}

#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn abs(x: __m512d) -> __m512d {
    _mm512_abs_pd(x)
}

/// The lanes of `if y < x { y } else { x }`, the scalar code's minimum (it keeps `x` when
/// either is NaN).
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn lower(x: __m512d, y: __m512d) -> __m512d {
    _mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_LT_OQ>(y, x), x, y)
}

/// The lanes of `if y > x { y } else { x }`, the scalar code's maximum (it keeps `x` when
/// either is NaN).
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn higher(x: __m512d, y: __m512d) -> __m512d {
    _mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_GT_OQ>(y, x), x, y)
}

/// `(p0·q0 + p1·q1) + p2·q2`, the order of every three-term dot product of the scalar code.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn dot(p: &[__m512d; 3], q: &[__m512d; 3]) -> __m512d {
    add(add(mul(p[0], q[0]), mul(p[1], q[1])), mul(p[2], q[2]))
}
