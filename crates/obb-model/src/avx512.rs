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
const _: () = assert!(size_of::<Obb>().is_multiple_of(8));

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

/// Three values of the eight records: fields `field`, `field + 1`, `field + 2`.
///
/// SAFETY: as [`gather`].
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn gather3(base: *const f64, at: __m256i, field: usize) -> [__m512d; 3] {
    unsafe {
        [
            gather(base, at, field),
            gather(base, at, field + 1),
            gather(base, at, field + 2),
        ]
    }
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
