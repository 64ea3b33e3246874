//! The separating-axis test in integer arithmetic, bit-exact with the hardware: 15 axes, every
//! product one DSP48E1 (at most 25 x 18 bits), every radius term rounded up and |T·L| down, and
//! the margins of `Margins`. Separated only if separated for certain (docs/numerics.md).

use super::margins::Margins;
use super::quantize::{ceil_shift, Projected, QObb};

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

/// The 15-axis test on quantized boxes `a` and `b` with their projections; `f` is the rotation
/// entries' fraction bits. True unless an axis separates them for certain.
pub fn collide(a: &QObb, pa: &Projected, b: &QObb, pb: &Projected, m: &Margins, f: u32) -> bool {
    let SatProducts { t, u, r } = sat_products(a, b);
    // |R_ij| / 2^f rounded up, for the radius terms of the face axes.
    let r_up = r.map(|row| row.map(|v| ceil_shift(v.abs(), f)));
    let pair = pa.margin + pb.margin;
    // Separated for certain: both sides cut to the comparator width by dropping k low bits;
    // floor(L / 2^k) > floor(R / 2^k) still implies L > R (docs/numerics.md, "Comparison
    // width").
    let k = m.compare_shift;
    let apart = |lhs: i64, radius: i64| lhs >> k > radius >> k;
    for i in 0..3 {
        let radius = (a.half[i] << f) + dot(&b.half, &r_up[i]) + m.face + pair;
        if apart(t[i].abs(), radius) {
            return false;
        }
    }
    for j in 0..3 {
        let column = [r_up[0][j], r_up[1][j], r_up[2][j]];
        let radius = (b.half[j] << f) + dot(&a.half, &column) + m.face + pair;
        if apart(u[j].abs(), radius) {
            return false;
        }
    }
    // Cross axes L = R̃_{i1 j} a_{i2} - R̃_{i2 j} a_{i1}, with R̃ = R / 2^f rounded to nearest
    // and t̂ = t / 2^f rounded down: every product fits one DSP.
    let rt = r.map(|row| row.map(|v| (v + (1 << (f - 1))) >> f));
    let th = t.map(|v| v >> f);
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let p = rt[i1][j] * th[i2] - rt[i2][j] * th[i1];
            let r_a = a.half[i1] * rt[i2][j].abs() + a.half[i2] * rt[i1][j].abs();
            // The minors R̃_{i1 j} R̃_{i2 l} - R̃_{i2 j} R̃_{i1 l} / 2^f, rounded up; zero for l = j.
            let r_b: i64 = (0..3)
                .filter(|&l| l != j)
                .map(|l| {
                    let minor = rt[i1][j] * rt[i2][l] - rt[i2][j] * rt[i1][l];
                    b.half[l] * ceil_shift(minor.abs(), f)
                })
                .sum();
            if apart(p.abs(), r_a + r_b + m.cross + pair) {
                return false;
            }
        }
    }
    true
}
