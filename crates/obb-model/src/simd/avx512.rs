//! [`Isa`] on AVX-512: eight f64 lanes, masks in `__mmask8`.

use super::{operator, Isa, LaneMask, Lanes, OBB_STRIDE};
use crate::scene::Obb;
use std::arch::x86_64::*;

/// The proof that this CPU has AVX-512F, AVX2 and POPCNT.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512(());

impl Avx512 {
    pub(crate) fn detect() -> Option<Avx512> {
        let has = is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("popcnt");
        has.then_some(Avx512(()))
    }
}

/// Eight f64 lanes. Made only through [`Avx512`], so every value exists on a CPU with AVX-512F:
/// that is the SAFETY of each intrinsic called here.
#[derive(Clone, Copy, Debug)]
pub(crate) struct F64x8(__m512d);

/// Eight u64 lanes, made only through [`Avx512`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct U64x8(__m512i);

operator!(F64x8, Add, add, _mm512_add_pd);
operator!(F64x8, Sub, sub, _mm512_sub_pd);
operator!(F64x8, Mul, mul, _mm512_mul_pd);
operator!(U64x8, BitOr, bitor, _mm512_or_si512);

impl Lanes for F64x8 {
    type Mask = u8;

    #[inline(always)]
    fn abs(self) -> F64x8 {
        F64x8(unsafe { _mm512_abs_pd(self.0) })
    }

    #[inline(always)]
    fn min(self, other: F64x8) -> F64x8 {
        F64x8(unsafe { _mm512_min_pd(self.0, other.0) })
    }

    #[inline(always)]
    fn max(self, other: F64x8) -> F64x8 {
        F64x8(unsafe { _mm512_max_pd(self.0, other.0) })
    }

    #[inline(always)]
    fn le(self, other: F64x8) -> u8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(self.0, other.0) }
    }

    #[inline(always)]
    fn gt(self, other: F64x8) -> u8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, other.0) }
    }

    /// `vrcp14pd`: relative error below 2^-14.
    #[inline(always)]
    fn recip(self) -> F64x8 {
        F64x8(unsafe { _mm512_rcp14_pd(self.0) })
    }
}

impl LaneMask for u8 {
    #[inline(always)]
    fn bits(self) -> u8 {
        self
    }
}

impl Isa<8> for Avx512 {
    type F = F64x8;
    type U = U64x8;

    #[inline(always)]
    fn splat(self, x: f64) -> F64x8 {
        F64x8(unsafe { _mm512_set1_pd(x) })
    }

    #[inline(always)]
    fn splat_u64(self, x: u64) -> U64x8 {
        U64x8(unsafe { _mm512_set1_epi64(x as i64) })
    }

    #[inline(always)]
    fn lane_numbers(self) -> U64x8 {
        U64x8(unsafe { _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7) })
    }

    #[inline(always)]
    fn first(self, n: usize) -> u8 {
        (u16::MAX >> (16 - n.min(8))) as u8
    }

    #[inline(always)]
    unsafe fn load(self, p: *const f64) -> F64x8 {
        // SAFETY: the caller's promise.
        F64x8(unsafe { _mm512_loadu_pd(p) })
    }

    #[inline(always)]
    unsafe fn load_u64(self, p: *const u64) -> U64x8 {
        // SAFETY: the caller's promise.
        U64x8(unsafe { _mm512_loadu_si512(p.cast()) })
    }

    #[inline(always)]
    unsafe fn gather(self, base: *const f64, at: [u32; 8]) -> F64x8 {
        // SAFETY: the caller's promise; `at` is 32 bytes.
        unsafe {
            let at = _mm256_loadu_si256(at.as_ptr().cast());
            F64x8(_mm512_i32gather_pd::<8>(at, base.cast()))
        }
    }

    /// Each box is two 64-byte loads, and the two 8x8 blocks are transposed in registers (24
    /// shuffles each), where gathering the fifteen fields would take fifteen gathers of eight
    /// loads each. On AMD's Zen 4 the gathers bounded both the SAT and the preparation; on the
    /// Intel CPU where they were first measured, the two forms were equally fast
    /// (docs/engines.md).
    #[inline(always)]
    unsafe fn boxes(self, obbs: &[Obb], at: [usize; 8]) -> [F64x8; OBB_STRIDE] {
        let base = obbs.as_ptr().cast::<f64>();
        // SAFETY (all intrinsics): this CPU has AVX-512F (`self`); each load reads half of box
        // `i`, which is inside `obbs` (the caller's promise) and is OBB_STRIDE f64.
        unsafe {
            let mut out = [F64x8(_mm512_setzero_pd()); OBB_STRIDE];
            // The 8x8 transpose: pairs of rows interleaved, then 128-bit lanes from two pairs,
            // then 256-bit halves from the two groups of four rows.
            let from_pairs_lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
            let from_pairs_hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
            for (half, fields) in out.chunks_exact_mut(8).enumerate() {
                let mut row = [_mm512_setzero_pd(); 8];
                for (r, &i) in row.iter_mut().zip(&at) {
                    *r = _mm512_loadu_pd(base.add(i * OBB_STRIDE + 8 * half));
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
                // quads[4q + m], for the rows 4q to 4q + 3: their field f in the low 256 bits
                // and their field f + 4 in the high, f = [0, 2, 1, 3][m].
                let mut quads = [_mm512_setzero_pd(); 8];
                for q in 0..2 {
                    let (even, odd) = (4 * q, 4 * q + 1);
                    let (e, e2, o, o2) = (pairs[even], pairs[even + 2], pairs[odd], pairs[odd + 2]);
                    quads[4 * q] = _mm512_permutex2var_pd(e, from_pairs_lo, e2);
                    quads[4 * q + 1] = _mm512_permutex2var_pd(e, from_pairs_hi, e2);
                    quads[4 * q + 2] = _mm512_permutex2var_pd(o, from_pairs_lo, o2);
                    quads[4 * q + 3] = _mm512_permutex2var_pd(o, from_pairs_hi, o2);
                }
                for (m, field) in [0, 2, 1, 3].into_iter().enumerate() {
                    fields[field] = F64x8(_mm512_shuffle_f64x2::<0x44>(quads[m], quads[4 + m]));
                    fields[field + 4] = F64x8(_mm512_shuffle_f64x2::<0xEE>(quads[m], quads[4 + m]));
                }
            }
            out
        }
    }

    #[inline(always)]
    fn lanes(self, v: F64x8) -> [f64; 8] {
        let mut lanes = [0.0; 8];
        // SAFETY: `lanes` is eight f64.
        unsafe { _mm512_storeu_pd(lanes.as_mut_ptr(), v.0) };
        lanes
    }

    #[inline(always)]
    fn bit(self, row: U64x8, shift: U64x8) -> u8 {
        unsafe { _mm512_test_epi64_mask(_mm512_srlv_epi64(row.0, shift.0), _mm512_set1_epi64(1)) }
    }

    /// Compressed in a register, then stored whole: a compress straight to memory is
    /// microcoded on AMD's Zen 4 (about 7 % of the SAT's time there, sampled on the instruction
    /// after it).
    #[inline(always)]
    unsafe fn compress_store(self, keep: u8, v: U64x8, out: *mut u64) {
        // SAFETY: the caller's promise.
        unsafe { _mm512_storeu_si512(out.cast(), _mm512_maskz_compress_epi64(keep, v.0)) }
    }
}
