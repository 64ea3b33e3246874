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
        ((1u16 << n.min(8)) - 1) as u8
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

    /// Each box is read a quarter (four fields) at a time, and box `l` and box `l + 4` share a
    /// register, one in each 256-bit half (a load and an insert from memory, which Intel's CPUs
    /// run on either of two ports); a 4x4 transpose in each half (eight shuffles) then gives
    /// four fields of the eight boxes. That is 32 shuffles for the eight boxes, where a
    /// transpose of their 64-byte halves took 48, all on the one port that shuffles 512-bit
    /// registers. Gathering the fifteen fields would take fifteen gathers of eight loads each:
    /// on AMD's Zen 4 the gathers bounded both the SAT and the preparation (docs/engines.md).
    #[inline(always)]
    unsafe fn boxes(self, obbs: &[Obb], at: [usize; 8]) -> [F64x8; OBB_STRIDE] {
        let base = obbs.as_ptr().cast::<f64>();
        // SAFETY (all intrinsics): this CPU has AVX-512F (`self`); each load reads a quarter of
        // box `i`, which is inside `obbs` (the caller's promise) and is OBB_STRIDE f64.
        unsafe {
            let mut out = [F64x8(_mm512_setzero_pd()); OBB_STRIDE];
            // Lanes 0, 1 of the first source, 0, 1 of the second, then 4, 5 of each: the
            // even 128-bit lanes of both, in each 256-bit half; `odd` the odd ones.
            let even = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
            let odd = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
            for (quarter, fields) in out.chunks_exact_mut(4).enumerate() {
                // row[k]: fields 4q to 4q + 3 of box at[k] in the low half, of box at[k + 4]
                // in the high half.
                let mut row = [_mm512_setzero_pd(); 4];
                for (k, r) in row.iter_mut().enumerate() {
                    let low = _mm256_loadu_pd(base.add(at[k] * OBB_STRIDE + 4 * quarter));
                    let high = _mm256_loadu_pd(base.add(at[k + 4] * OBB_STRIDE + 4 * quarter));
                    *r = _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(low), high);
                }
                // Fields f and f + 2 of rows 0, 1 (and of 2, 3) interleaved, f = 0 in `lo`
                // and f = 1 in `hi`.
                let (lo01, hi01) = (
                    _mm512_unpacklo_pd(row[0], row[1]),
                    _mm512_unpackhi_pd(row[0], row[1]),
                );
                let (lo23, hi23) = (
                    _mm512_unpacklo_pd(row[2], row[3]),
                    _mm512_unpackhi_pd(row[2], row[3]),
                );
                fields[0] = F64x8(_mm512_permutex2var_pd(lo01, even, lo23));
                fields[1] = F64x8(_mm512_permutex2var_pd(hi01, even, hi23));
                fields[2] = F64x8(_mm512_permutex2var_pd(lo01, odd, lo23));
                fields[3] = F64x8(_mm512_permutex2var_pd(hi01, odd, hi23));
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
