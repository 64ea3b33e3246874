//! The instruction-set trait the vector code is written over, its vector and mask traits, and
//! the helpers every instruction set shares (`super` says how they are compiled).

use crate::scene::Obb;
use std::mem::{offset_of, size_of};
use std::ops::{Add, BitAnd, BitOr, Mul, Not, Sub};

/// Compiles the generic vector function `$f(isa, args...)` for each instruction set, as
/// `with_avx512` and `with_avx2`: each enables its instructions (`#[target_feature]`), so that
/// the `#[inline(always)]` vector code and its intrinsics are inlined into it. Defines `on`,
/// which runs `$f` on the form `vectors` (one this CPU has) and returns `None` for the portable
/// form, which each caller provides itself.
macro_rules! compile_for_each_isa {
    ($f:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        #[target_feature(enable = "avx512f,avx2,popcnt")]
        fn with_avx512(isa: $crate::simd::Avx512, $($arg: $ty),*) -> $ret {
            $f(isa, $($arg),*)
        }

        #[target_feature(enable = "avx2,popcnt")]
        fn with_avx2(isa: $crate::simd::Avx2, $($arg: $ty),*) -> $ret {
            $f(isa, $($arg),*)
        }

        /// `$f` on the instruction set `vectors`; `None` for the portable form.
        pub(super) fn on(vectors: $crate::simd::Vectors, $($arg: $ty),*) -> Option<$ret> {
            use $crate::simd::{Avx2, Avx512, Vectors};
            // SAFETY (both calls): the token `detect` returns proves that this CPU has the
            // features the function enables.
            match (vectors, Avx512::detect(), Avx2::detect()) {
                (Vectors::Avx512, Some(isa), _) => Some(unsafe { with_avx512(isa, $($arg),*) }),
                (Vectors::Avx2, _, Some(isa)) => Some(unsafe { with_avx2(isa, $($arg),*) }),
                _ => None,
            }
        }
    };
}
pub(crate) use compile_for_each_isa;

/// Implements the operator trait `$op` (method `$method`) on the vector type `$t` by the
/// intrinsic `$f`.
macro_rules! operator {
    ($t:ident, $op:ident, $method:ident, $f:ident) => {
        impl std::ops::$op for $t {
            type Output = $t;
            #[inline(always)]
            fn $method(self, other: $t) -> $t {
                // SAFETY: a value of `$t` exists only on a CPU with its instructions.
                $t(unsafe { $f(self.0, other.0) })
            }
        }
    };
}
pub(crate) use operator;

/// Boxes as arrays of f64: a box's stride and its fields' offsets.
pub(crate) const OBB_STRIDE: usize = size_of::<Obb>() / 8;
pub(crate) const CENTER: usize = offset_of!(Obb, center) / 8;
pub(crate) const AXES: usize = offset_of!(Obb, axes) / 8;
pub(crate) const HALF: usize = offset_of!(Obb, half) / 8;
// `Isa::boxes` reads a box as sixteen f64.
const _: () = assert!(OBB_STRIDE == 16);

/// The most lanes of any [`Isa`]: buffers that every width writes into are sized for it.
pub(crate) const MAX_WIDTH: usize = 8;

/// An instruction set with vectors of `W` f64 lanes ([`Isa::F`]) and of `W` u64 lanes
/// ([`Isa::U`]).
pub(crate) trait Isa<const W: usize>: Copy {
    type F: Lanes;
    type U: Copy + BitOr<Output = Self::U>;

    /// Every lane `x`.
    fn splat(self, x: f64) -> Self::F;
    /// Every lane `x`.
    fn splat_u64(self, x: u64) -> Self::U;
    /// Lane `l` holds `l`.
    fn lane_numbers(self) -> Self::U;
    /// The lanes below `n` (all of them when `n >= W`).
    fn first(self, n: usize) -> Mask<Self, W>;
    /// The `W` values at `p`. SAFETY: they must be readable.
    unsafe fn load(self, p: *const f64) -> Self::F;
    /// The `W` values at `p`. SAFETY: they must be readable.
    unsafe fn load_u64(self, p: *const u64) -> Self::U;
    /// Lane `l` holds `base[at[l]]`. SAFETY: every `base[at[l]]` must be readable.
    unsafe fn gather(self, base: *const f64, at: [u32; W]) -> Self::F;
    /// The boxes `at` of `obbs` read whole, as [`OBB_STRIDE`] vectors: lane `l` of vector `f`
    /// is the f64 at `f` in box `at[l]` (so `boxes[CENTER + k]` holds the centers' `k`).
    /// SAFETY: every index of `at` must be below `obbs.len()`.
    unsafe fn boxes(self, obbs: &[Obb], at: [usize; W]) -> [Self::F; OBB_STRIDE];
    /// The lanes as an array.
    fn lanes(self, v: Self::F) -> [f64; W];
    /// The lanes where bit `shift` of `row` is set.
    fn bit(self, row: Self::U, shift: Self::U) -> Mask<Self, W>;
    /// Stores the lanes of `v` whose bit is set in `keep`, in lane order, at `out`. It writes
    /// `W` values: those past the kept ones are left unspecified.
    /// SAFETY: `W` u64 from `out` must be writable.
    unsafe fn compress_store(self, keep: u8, v: Self::U, out: *mut u64);
}

/// The comparison mask of an [`Isa`]'s f64 vectors.
pub(crate) type Mask<I, const W: usize> = <<I as Isa<W>>::F as Lanes>::Mask;

/// A vector of f64 lanes. Each operation is the scalar one on each lane, rounded as it is.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
{
    type Mask: LaneMask;
    fn abs(self) -> Self;
    /// `if self < other { self } else { other }` on each lane (so `other` when either is NaN),
    /// as x86's `minpd` computes it.
    fn min(self, other: Self) -> Self;
    /// `if self > other { self } else { other }` on each lane, as x86's `maxpd` computes it.
    fn max(self, other: Self) -> Self;
    /// The lanes where `self <= other` (false on NaN).
    fn le(self, other: Self) -> Self::Mask;
    /// The lanes where `self > other` (false on NaN).
    fn gt(self, other: Self) -> Self::Mask;
    /// An approximation of `1 / self`, to about 12 bits or better (or exact).
    fn recip(self) -> Self;
}

/// A mask of lanes.
pub(crate) trait LaneMask:
    Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self>
{
    /// Bit `l` set for lane `l`; the bits past the last lane clear.
    fn bits(self) -> u8;
}

/// The scalar code's minimum, `if y < x { y } else { x }` on each lane (it keeps `x` when
/// either is NaN).
#[inline(always)]
pub(crate) fn lower<F: Lanes>(x: F, y: F) -> F {
    y.min(x)
}

/// The scalar code's maximum, `if y > x { y } else { x }` on each lane (it keeps `x` when
/// either is NaN).
#[inline(always)]
pub(crate) fn higher<F: Lanes>(x: F, y: F) -> F {
    y.max(x)
}

/// `(p0·q0 + p1·q1) + p2·q2`, the order of every three-term dot product of the scalar code.
#[inline(always)]
pub(crate) fn dot<F: Lanes>(p: &[F; 3], q: &[F; 3]) -> F {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// Three consecutive fields of [`Isa::boxes`]' vectors, from `field`.
#[inline(always)]
pub(crate) fn field3<F: Copy>(boxes: &[F; OBB_STRIDE], field: usize) -> [F; 3] {
    [boxes[field], boxes[field + 1], boxes[field + 2]]
}

/// The three axes of [`Isa::boxes`]' vectors: `axes(b)[k][x]` is entry `x` of axis `k`.
#[inline(always)]
pub(crate) fn axes<F: Copy>(boxes: &[F; OBB_STRIDE]) -> [[F; 3]; 3] {
    [
        field3(boxes, AXES),
        field3(boxes, AXES + 3),
        field3(boxes, AXES + 6),
    ]
}

/// The bits of the lanes below `W`.
#[inline(always)]
pub(crate) const fn all_lanes<const W: usize>() -> u8 {
    (u16::MAX >> (16 - W)) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::{Avx2, Avx512};

    /// `first(n)` holds exactly the lanes below `n`, for every `n` from 0 past `W`.
    fn first_is_the_lanes_below<I: Isa<W>, const W: usize>(isa: I) {
        for n in 0..=2 * W {
            let want = (0..n.min(W)).fold(0u8, |bits, l| bits | 1 << l);
            assert_eq!(isa.first(n).bits(), want, "first({n}) with {W} lanes");
        }
    }

    #[test]
    fn first_holds_the_lanes_below_n() {
        if let Some(isa) = Avx512::detect() {
            first_is_the_lanes_below(isa);
        }
        if let Some(isa) = Avx2::detect() {
            first_is_the_lanes_below(isa);
        }
    }
}
