//! The separating-axis test in integer arithmetic, bit-exact with the hardware: 15 axes, every
//! product one DSP48E1 (at most 25 x 18 bits), every radius term rounded up and |T·L| down, and
//! the margins of `Margins`. Separated only if separated for certain (docs/numerics.md).

use super::margins::Margins;
use super::quantize::{Projected, QObb};
use super::rounding::ceil_shift;

#[inline]
fn dot(p: &[i64; 3], q: &[i64; 3]) -> i64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// The SAT's first stage, exact: `t_i = T·a_i`, `u_j = T·b_j` (LSB · 2^-f) and `R_ij = a_i·b_j`
/// (2^-2f), with `T = c_B - c_A`. The hardware's `sat_front` computes exactly these.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SatProducts {
    pub t: [i64; 3],
    pub u: [i64; 3],
    pub r: [[i64; 3]; 3],
}

pub fn sat_products(a: &QObb, b: &QObb) -> SatProducts {
    let t_world: [i64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    SatProducts {
        t: std::array::from_fn(|i| dot(&a.axes[i], &t_world)),
        u: std::array::from_fn(|j| dot(&b.axes[j], &t_world)),
        r: std::array::from_fn(|i| std::array::from_fn(|j| dot(&a.axes[i], &b.axes[j]))),
    }
}

/// The SAT's second stage: the products rounded for the next multiplies. `r_up = ceil(|R| /
/// 2^f)` (face radii), `rt = round(R / 2^f)` (cross axes), `th = floor(t / 2^f)`, and |t|, |u|.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SatRounded {
    pub abs_t: [i64; 3],
    pub abs_u: [i64; 3],
    pub r_up: [[i64; 3]; 3],
    pub rt: [[i64; 3]; 3],
    pub th: [i64; 3],
}

pub fn sat_round(p: &SatProducts, f: u32) -> SatRounded {
    SatRounded {
        abs_t: p.t.map(i64::abs),
        abs_u: p.u.map(i64::abs),
        r_up: p.r.map(|row| row.map(|v| ceil_shift(v.abs(), f))),
        rt: p.r.map(|row| row.map(|v| (v + (1 << (f - 1))) >> f)),
        th: p.t.map(|v| v >> f),
    }
}

/// The unordered pairs {j, l}, j != l, in the order the minors are kept.
pub const MINOR_PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// The minor pair holding {j, l}.
fn minor_index(j: usize, l: usize) -> usize {
    match (j.min(l), j.max(l)) {
        (0, 1) => 0,
        (0, 2) => 1,
        _ => 2,
    }
}

/// The SAT's third stage, one product pair each: the face radii `Σ_j h^B_j r_up_ij` (A's axes)
/// and `Σ_i h^A_i r_up_ij` (B's), and per cross axis (i, j) with (i, i1, i2) cyclic:
/// `P = rt_i1j th_i2 - rt_i2j th_i1`, `r_A = h^A_i1 |rt_i2j| + h^A_i2 |rt_i1j|`, and the minors
/// `ceil(|rt_i1j rt_i2l - rt_i2j rt_i1l| / 2^f)` for each pair {j, l} (`MINOR_PAIRS`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SatTerms {
    pub face_a: [i64; 3],
    pub face_b: [i64; 3],
    pub p: [[i64; 3]; 3],
    pub r_a: [[i64; 3]; 3],
    pub minors: [[i64; 3]; 3],
}

pub fn sat_terms(a: &QObb, b: &QObb, r: &SatRounded, f: u32) -> SatTerms {
    let cyc = |i: usize| ((i + 1) % 3, (i + 2) % 3);
    SatTerms {
        face_a: std::array::from_fn(|i| dot(&b.half, &r.r_up[i])),
        face_b: std::array::from_fn(|j| dot(&a.half, &[r.r_up[0][j], r.r_up[1][j], r.r_up[2][j]])),
        p: std::array::from_fn(|i| {
            let (i1, i2) = cyc(i);
            std::array::from_fn(|j| r.rt[i1][j] * r.th[i2] - r.rt[i2][j] * r.th[i1])
        }),
        r_a: std::array::from_fn(|i| {
            let (i1, i2) = cyc(i);
            std::array::from_fn(|j| a.half[i1] * r.rt[i2][j].abs() + a.half[i2] * r.rt[i1][j].abs())
        }),
        minors: std::array::from_fn(|i| {
            let (i1, i2) = cyc(i);
            MINOR_PAIRS.map(|(j, l)| {
                let m = r.rt[i1][j] * r.rt[i2][l] - r.rt[i2][j] * r.rt[i1][l];
                ceil_shift(m.abs(), f)
            })
        }),
    }
}

/// The SAT's fourth stage: `r_B` of each cross axis (i, j), `Σ_(l != j) h^B_l minor(i, {j, l})`.
pub fn sat_r_b(b: &QObb, t: &SatTerms) -> [[i64; 3]; 3] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..3)
                .filter(|&l| l != j)
                .map(|l| b.half[l] * t.minors[i][minor_index(j, l)])
                .sum()
        })
    })
}

/// The SAT's last stage: the 15 comparisons, each side cut by `compare_shift` bits (docs/
/// numerics.md, "Comparison width"). True unless an axis separates the boxes for certain.
/// `half_a`, `half_b` are the boxes' half-lengths; of `r` only |t| and |u| are read.
pub fn sat_decide(
    half_a: &[i64; 3],
    half_b: &[i64; 3],
    pair_margin: i64,
    r: &SatRounded,
    t: &SatTerms,
    r_b: &[[i64; 3]; 3],
    m: &Margins,
) -> bool {
    let (f, k) = (m.frac_bits, m.compare_shift);
    let apart = |lhs: i64, radius: i64| lhs >> k > radius >> k;
    let face = m.face + pair_margin;
    let cross = m.cross + pair_margin;
    !((0..3).any(|i| apart(r.abs_t[i], (half_a[i] << f) + t.face_a[i] + face))
        || (0..3).any(|j| apart(r.abs_u[j], (half_b[j] << f) + t.face_b[j] + face))
        || (0..3).any(|i| (0..3).any(|j| apart(t.p[i][j].abs(), t.r_a[i][j] + r_b[i][j] + cross))))
}

/// The 15-axis test on quantized boxes `a` and `b` with their projections: the stages above in
/// order. True unless an axis separates them for certain.
pub fn collide(a: &QObb, pa: &Projected, b: &QObb, pb: &Projected, m: &Margins, f: u32) -> bool {
    let rounded = sat_round(&sat_products(a, b), f);
    let terms = sat_terms(a, b, &rounded, f);
    let r_b = sat_r_b(b, &terms);
    sat_decide(
        &a.half,
        &b.half,
        pa.margin + pb.margin,
        &rounded,
        &terms,
        &r_b,
        m,
    )
}
