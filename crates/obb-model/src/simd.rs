//! Vectors of f64 lanes for the SAT, the preparation and the cell scan, on two instruction sets:
//! AVX-512 (eight lanes) and AVX2 (four). Each of those three parts is written once, generic
//! over `Isa`, and compiled for each instruction set inside a function that enables it
//! (`#[target_feature]`). Every method here is `#[inline(always)]`, so that it is inlined into
//! that function and its intrinsics with it; a method left as a call would cost more than the
//! vector it computes. Every lane computes exactly what the scalar operation does (no fused
//! multiply-add), so the vector forms round as the scalar code they follow.
//!
//! A value of an `Isa` type is the proof that the CPU has its instructions: its only
//! constructor, `detect`, checks. Vectors are made only through it, so their methods are safe.

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(target_arch = "x86_64")]
mod isa;
#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) use avx512::Avx512;
#[cfg(target_arch = "x86_64")]
pub(crate) use isa::*;

/// The instruction sets the engines' vector code runs on. Every form gives the same answers
/// bit for bit; they differ only in speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vectors {
    /// AVX-512F with AVX2 and POPCNT: eight f64 lanes.
    Avx512,
    /// AVX2 with POPCNT: four f64 lanes.
    Avx2,
    /// No vector intrinsics: the portable code, which the compiler vectorises as it can.
    Portable,
}

impl Vectors {
    /// The best instruction set this CPU has.
    pub fn detected() -> Vectors {
        Vectors::available()[0]
    }

    /// Every form this CPU can run, the best first. The tests run each of them.
    pub fn available() -> &'static [Vectors] {
        #[cfg(target_arch = "x86_64")]
        {
            if Avx512::detect().is_some() {
                return &[Vectors::Avx512, Vectors::Avx2, Vectors::Portable];
            }
            if Avx2::detect().is_some() {
                return &[Vectors::Avx2, Vectors::Portable];
            }
        }
        &[Vectors::Portable]
    }
}
