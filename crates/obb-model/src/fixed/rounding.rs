//! Integer rounding shared by the stages (the quantization, the margins, the SAT).

/// `ceil(v / 2^s)` for `v >= 0`.
#[inline]
pub(crate) fn ceil_shift(v: i64, s: u32) -> i64 {
    (v + (1 << s) - 1) >> s
}
