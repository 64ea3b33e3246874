//! [`Isa`] on AVX2: four f64 lanes, masks as vectors of all-ones or all-zeros lanes.

use super::{operator, Isa, LaneMask, Lanes, OBB_STRIDE};
use crate::scene::Obb;
use std::arch::x86_64::*;
use std::ops::Not;

/// The proof that this CPU has AVX2 and POPCNT.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(());

impl Avx2 {
    pub(crate) fn detect() -> Option<Avx2> {
        let has = is_x86_feature_detected!("avx2") && is_x86_feature_detected!("popcnt");
        has.then_some(Avx2(()))
    }
}

/// Four f64 lanes. Made only through [`Avx2`], so every value exists on a CPU with AVX2: that
/// is the SAFETY of each intrinsic called here.
#[derive(Clone, Copy, Debug)]
pub(crate) struct F64x4(__m256d);

/// Four u64 lanes, made only through [`Avx2`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct U64x4(__m256i);

/// A mask of four lanes, each all ones or all zeros, made only through [`Avx2`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mask4(__m256d);

operator!(F64x4, Add, add, _mm256_add_pd);
operator!(F64x4, Sub, sub, _mm256_sub_pd);
operator!(F64x4, Mul, mul, _mm256_mul_pd);
operator!(U64x4, BitOr, bitor, _mm256_or_si256);
operator!(Mask4, BitAnd, bitand, _mm256_and_pd);
operator!(Mask4, BitOr, bitor, _mm256_or_pd);

impl Not for Mask4 {
    type Output = Mask4;
    #[inline(always)]
    fn not(self) -> Mask4 {
        Mask4(unsafe { _mm256_xor_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))) })
    }
}

impl LaneMask for Mask4 {
    #[inline(always)]
    fn bits(self) -> u8 {
        (unsafe { _mm256_movemask_pd(self.0) }) as u8
    }
}

impl Lanes for F64x4 {
    type Mask = Mask4;

    #[inline(always)]
    fn abs(self) -> F64x4 {
        // The sign bit cleared, as `f64::abs` does.
        F64x4(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }

    #[inline(always)]
    fn min(self, other: F64x4) -> F64x4 {
        F64x4(unsafe { _mm256_min_pd(self.0, other.0) })
    }

    #[inline(always)]
    fn max(self, other: F64x4) -> F64x4 {
        F64x4(unsafe { _mm256_max_pd(self.0, other.0) })
    }

    #[inline(always)]
    fn le(self, other: F64x4) -> Mask4 {
        Mask4(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, other.0) })
    }

    #[inline(always)]
    fn gt(self, other: F64x4) -> Mask4 {
        Mask4(unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, other.0) })
    }

    /// `1 / self`, correctly rounded. AVX2 has no approximate reciprocal of doubles: `rcpps` on
    /// the value rounded to f32 and a Newton step in f64 were seven instructions where
    /// `vdivpd` is one, in a step of the SAT's first pass that fills the reorder buffer (0.06
    /// to 0.1 ms less a frame of the surgical scene on AMD's Zen 3). The division's latency
    /// stays off the longest chain: the offsets it divides are known before the room that
    /// multiplies them (a division of the room by the offset was 0.09 ms slower).
    #[inline(always)]
    fn recip(self) -> F64x4 {
        F64x4(unsafe { _mm256_div_pd(_mm256_set1_pd(1.0), self.0) })
    }
}

/// For each 4-bit mask, the 32-bit lanes that move the mask's 64-bit lanes to the front, in
/// order (the rest from lane 0).
const COMPRESS: [[i32; 8]; 16] = {
    let mut table = [[0; 8]; 16];
    let mut keep = 0;
    while keep < 16 {
        let mut to = 0;
        let mut lane = 0;
        while lane < 4 {
            if keep >> lane & 1 == 1 {
                table[keep][2 * to] = 2 * lane;
                table[keep][2 * to + 1] = 2 * lane + 1;
                to += 1;
            }
            lane += 1;
        }
        keep += 1;
    }
    table
};

impl Isa<4> for Avx2 {
    type F = F64x4;
    type U = U64x4;

    #[inline(always)]
    fn splat(self, x: f64) -> F64x4 {
        F64x4(unsafe { _mm256_set1_pd(x) })
    }

    #[inline(always)]
    fn splat_u64(self, x: u64) -> U64x4 {
        U64x4(unsafe { _mm256_set1_epi64x(x as i64) })
    }

    #[inline(always)]
    fn lane_numbers(self) -> U64x4 {
        U64x4(unsafe { _mm256_setr_epi64x(0, 1, 2, 3) })
    }

    #[inline(always)]
    fn first(self, n: usize) -> Mask4 {
        // Lane `l` is kept where `min(n, 4) > l`.
        let n = unsafe { _mm256_set1_epi64x(n.min(4) as i64) };
        Mask4(unsafe { _mm256_castsi256_pd(_mm256_cmpgt_epi64(n, self.lane_numbers().0)) })
    }

    #[inline(always)]
    unsafe fn load(self, p: *const f64) -> F64x4 {
        // SAFETY: the caller's promise.
        F64x4(unsafe { _mm256_loadu_pd(p) })
    }

    #[inline(always)]
    unsafe fn load_u64(self, p: *const u64) -> U64x4 {
        // SAFETY: the caller's promise.
        U64x4(unsafe { _mm256_loadu_si256(p.cast()) })
    }

    /// Four scalar loads: AVX2's gather is slower than them on AMD's Zen 3.
    #[inline(always)]
    unsafe fn gather(self, base: *const f64, at: [u32; 4]) -> F64x4 {
        // SAFETY: the caller's promise.
        unsafe {
            let (x0, x1) = (*base.add(at[0] as usize), *base.add(at[1] as usize));
            let (x2, x3) = (*base.add(at[2] as usize), *base.add(at[3] as usize));
            F64x4(_mm256_setr_pd(x0, x1, x2, x3))
        }
    }

    /// Each quarter of a box (four fields) is two 16-byte loads; boxes 0 and 2, and 1 and 3,
    /// share a register (one load inserted into the high half), so that one unpack of the two
    /// registers gives a field of all four boxes. Eight inserts and eight unpacks per four
    /// fields, where a gather would take four loads for each field.
    #[inline(always)]
    unsafe fn boxes(self, obbs: &[Obb], at: [usize; 4]) -> [F64x4; OBB_STRIDE] {
        let base = obbs.as_ptr().cast::<f64>();
        // SAFETY (all intrinsics): this CPU has AVX2 (`self`); each load reads two f64 of box
        // `at[l]`, which is inside `obbs` (the caller's promise) and is OBB_STRIDE f64.
        unsafe {
            let mut boxes = [base; 4];
            for (b, &i) in boxes.iter_mut().zip(&at) {
                *b = base.add(i * OBB_STRIDE);
            }
            let mut out = [F64x4(_mm256_setzero_pd()); OBB_STRIDE];
            for field in (0..OBB_STRIDE).step_by(2) {
                // Fields `field` and `field + 1` of boxes 0 | 2, and of boxes 1 | 3.
                let even = _mm256_loadu2_m128d(boxes[2].add(field), boxes[0].add(field));
                let odd = _mm256_loadu2_m128d(boxes[3].add(field), boxes[1].add(field));
                out[field] = F64x4(_mm256_unpacklo_pd(even, odd));
                out[field + 1] = F64x4(_mm256_unpackhi_pd(even, odd));
            }
            out
        }
    }

    #[inline(always)]
    fn lanes(self, v: F64x4) -> [f64; 4] {
        let mut lanes = [0.0; 4];
        // SAFETY: `lanes` is four f64.
        unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), v.0) };
        lanes
    }

    #[inline(always)]
    fn bit(self, row: U64x4, shift: U64x4) -> Mask4 {
        unsafe {
            let one = _mm256_set1_epi64x(1);
            let set = _mm256_and_si256(_mm256_srlv_epi64(row.0, shift.0), one);
            Mask4(_mm256_castsi256_pd(_mm256_cmpeq_epi64(set, one)))
        }
    }

    /// A permutation from a table of the sixteen masks, then one store of the four lanes.
    #[inline(always)]
    unsafe fn compress_store(self, keep: u8, v: U64x4, out: *mut u64) {
        // SAFETY: the caller's promise; the table's row is 32 bytes.
        unsafe {
            let order = _mm256_loadu_si256(COMPRESS[usize::from(keep & 15)].as_ptr().cast());
            _mm256_storeu_si256(out.cast(), _mm256_permutevar8x32_epi32(v.0, order));
        }
    }
}
