//! The SAT's margins: constants that bound, with the per-box margin, everything the integer test
//! does not compute exactly (input quantization, the axes' non-orthonormality, and the
//! truncations of the cross-axis operands). The derivation is in docs/numerics.md; each constant
//! here is named after its formula there.

use super::config::HwConfig;

/// The per-box margin is `ceil(Σh · beta_num / 2^BETA_SHIFT)`.
pub const BETA_SHIFT: u32 = 8;

/// Integer margins in SAT units (LSB · 2^-f).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Margins {
    /// Added to every face-axis radius sum.
    pub face: i64,
    /// Added to every cross-axis radius sum.
    pub cross: i64,
    /// β · 2^BETA_SHIFT, rounded up: the per-box margin's slope in Σh.
    pub beta_num: i64,
    /// Fraction bits f of the rotation entries: SAT units are LSB · 2^-f.
    pub frac_bits: u32,
    /// Bits dropped from both sides of each comparison (`HwConfig::sat_shift`).
    pub compare_shift: u32,
}

pub use super::config::eta;

/// A real bound made an integer bound: rounded up, with room for the f64 rounding of the
/// formula itself (a few ulps, far below the 1e-9 relative pad).
fn up(v: f64) -> i64 {
    (v * (1.0 + 1e-9)).ceil() as i64 + 1
}

impl Margins {
    pub fn new(cfg: &HwConfig) -> Margins {
        let two_f = f64::from(1u32 << cfg.frac_bits());
        let s3 = 3f64.sqrt();
        let eta = eta(cfg);
        // ρ̄: bound on |R̃_ij|, a rotation product rounded to 2^-f.
        let rho_bar = two_f * (1.0 + eta) + 0.5;
        let face = s3 * two_f * (1.0 + eta);
        let cross = 2.0 * rho_bar + 2.0 * s3 * rho_bar * (1.0 + eta);
        let beta_face = two_f * eta + s3 / 2.0 * (1.0 + eta);
        let beta_cross =
            (2.0 * eta * rho_bar).max(rho_bar / two_f) + s3 * rho_bar * (1.0 + eta) / two_f;
        Margins {
            face: up(face),
            cross: up(cross),
            beta_num: up(beta_face.max(beta_cross) * f64::from(1u32 << BETA_SHIFT)),
            frac_bits: cfg.frac_bits(),
            compare_shift: cfg.sat_shift(),
        }
    }

    /// The per-box margin of a box with these half-lengths, `ceil(β Σh)`.
    pub fn per_box(&self, half: [i64; 3]) -> i64 {
        self.per_box_sum(half[0] + half[1] + half[2])
    }

    fn per_box_sum(&self, sum: i64) -> i64 {
        super::rounding::ceil_shift(sum * self.beta_num, BETA_SHIFT)
    }

    /// The widest gap, in LSBs, at which the face-axis test can still report two boxes whose
    /// half-lengths sum to `sum_half` (LSBs) as colliding: the margins, plus 3 LSBs of rounding
    /// (two centers to nearest, two half-lengths up), and what cutting the comparison to
    /// `sat_bits` adds. The price of never missing.
    pub fn face_gap_lsb(&self, sum_half: [i64; 2]) -> f64 {
        let m = self.face + self.per_box_sum(sum_half[0]) + self.per_box_sum(sum_half[1]);
        // A cut comparison may call |T·L| < R + 2^shift not separated.
        let cut = 1i64 << self.compare_shift;
        (m + cut) as f64 / f64::from(1u32 << self.frac_bits) + 3.0
    }
}
