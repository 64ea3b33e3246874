//! Every axis' two sides where the SAT's decision reads them, for the SAT tests: the probes
//! into the emitted Verilog, their rust-hdl twins, and a reference written from the arithmetic
//! of docs/numerics.md (not from the model's stage functions).

use super::{ceil_div, floor_div, nearest, ports, raw};
use obb_model::fixed::ModelFrame;
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::{sval, uval};
use obb_rtl::sat_back::{SatDecide, FACE, PAIR2, P_BITS, RB};
use obb_rtl::sat_round::ABS_TU;

/// The decision's inputs, in the order the probes list them: (name, count, bits).
const SIDES: [(&str, usize, usize); 7] = [
    ("abs_t", 3, ABS_TU),
    ("abs_u", 3, ABS_TU),
    ("face_a", 3, FACE),
    ("face_b", 3, FACE),
    ("abs_p", 9, P_BITS),
    ("r_a", 9, PAIR2),
    ("r_b", 9, RB),
];

/// Probes of the decision's inputs, `<decide>$<side>$<k>` (`decide`: its hierarchical name
/// below the test bench, e.g. `dut.decide`).
pub fn probes(decide: &str) -> Vec<Port> {
    SIDES
        .iter()
        .flat_map(|&(name, n, bits)| ports(&format!("{decide}${name}"), n, bits))
        .collect()
}

/// The same values in rust-hdl's simulation.
pub fn read(d: &SatDecide) -> Vec<u64> {
    let mut row: Vec<u64> = d
        .abs_t
        .iter()
        .chain(&d.abs_u)
        .map(|x| uval(x.val()))
        .collect();
    row.extend(
        d.face_a
            .iter()
            .chain(&d.face_b)
            .map(|x| raw(sval(x.val()), FACE)),
    );
    row.extend(d.abs_p.iter().map(|x| uval(x.val())));
    row.extend(d.r_a.iter().map(|x| raw(sval(x.val()), PAIR2)));
    row.extend(d.r_b.iter().map(|x| raw(sval(x.val()), RB)));
    row
}

/// The products of the SAT's first stage and the half-lengths: `t_i = a_i·T`, `u_j = b_j·T`
/// (`T = c_B - c_A`), `R_ij = a_i·b_j`.
pub struct Products {
    pub t: [i64; 3],
    pub u: [i64; 3],
    pub r: [[i64; 3]; 3],
    pub half_a: [i64; 3],
    pub half_b: [i64; 3],
}

/// Every axis' sides with `f` fraction bits: |t|, |u|; the face radii `Σ h ceil(|R|/2^f)`;
/// per cross axis (i, j), with (i, i1, i2) cyclic, `rt = round(R/2^f)` and `th =
/// floor(t/2^f)`: `|rt_i1j th_i2 - rt_i2j th_i1|`, `r_A = hA_i1 |rt_i2j| + hA_i2 |rt_i1j|` and
/// `r_B = Σ_(l != j) hB_l ceil(|rt_i1j rt_i2l - rt_i2j rt_i1l| / 2^f)`.
pub fn sides(p: &Products, f: u32) -> Vec<u64> {
    let (ha, hb) = (p.half_a, p.half_b);
    let up = |i: usize, j: usize| ceil_div(p.r[i][j].abs(), f);
    let rt = |i: usize, j: usize| nearest(p.r[i][j], f);
    let th = |i: usize| floor_div(p.t[i], f);
    let cross = |g: &dyn Fn(usize, usize, usize) -> u64| -> Vec<u64> {
        (0..9)
            .map(|k| g((k / 3 + 1) % 3, (k / 3 + 2) % 3, k % 3))
            .collect()
    };
    let mut out: Vec<u64> = p.t.iter().chain(&p.u).map(|x| x.unsigned_abs()).collect();
    out.extend((0..3).map(|i| raw((0..3).map(|j| hb[j] * up(i, j)).sum(), FACE)));
    out.extend((0..3).map(|j| raw((0..3).map(|i| ha[i] * up(i, j)).sum(), FACE)));
    out.extend(cross(&|i1, i2, j| {
        (rt(i1, j) * th(i2) - rt(i2, j) * th(i1)).unsigned_abs()
    }));
    out.extend(cross(&|i1, i2, j| {
        raw(ha[i1] * rt(i2, j).abs() + ha[i2] * rt(i1, j).abs(), PAIR2)
    }));
    out.extend(cross(&|i1, i2, j| {
        let minor = |l: usize| ceil_div((rt(i1, j) * rt(i2, l) - rt(i2, j) * rt(i1, l)).abs(), f);
        raw(
            (0..3).filter(|&l| l != j).map(|l| hb[l] * minor(l)).sum(),
            RB,
        )
    }));
    out
}

/// The first pair k whose sides (the columns of `got` from `column` on, at row `k + at`)
/// differ from `want[k]`: which side, what the block gave and what was wanted.
pub fn differ(got: &[Vec<u64>], want: &[Vec<u64>], at: usize, column: usize) -> Option<String> {
    let names: Vec<String> = SIDES
        .iter()
        .flat_map(|&(name, n, _)| (0..n).map(move |k| format!("{name}[{k}]")))
        .collect();
    want.iter().enumerate().find_map(|(k, w)| {
        let g = &got[k + at][column..];
        let c = (0..w.len()).find(|&c| g[c] != w[c])?;
        Some(format!("pair {k}: {} is {}, want {}", names[c], g[c], w[c]))
    })
}

/// The verdict columns (valid, hit) of each clock, the sides left out.
pub fn verdicts(rows: &[Vec<u64>]) -> Vec<Vec<u64>> {
    rows.iter().map(|r| r[..2].to_vec()).collect()
}

/// A run of a SAT block, one pair per clock: its input vectors and what it must give.
pub struct Stimulus {
    /// One per clock: the pairs, then idle clocks to drain.
    pub vectors: Vec<Vec<u64>>,
    /// The verdict (valid, hit) the model gives at each clock.
    pub want: Vec<Vec<u64>>,
    /// Each pair's sides.
    pub want_sides: Vec<Vec<u64>>,
}

impl Stimulus {
    /// `pairs` of `m` as their input `vectors` (one per pair) and first-stage `products`, into
    /// a block whose verdict comes `latency` clocks after its inputs: the vectors followed by
    /// idle clocks, the model's verdicts on their clocks, and the pairs' sides.
    pub fn new(
        m: &ModelFrame,
        pairs: &[(usize, usize)],
        latency: u64,
        mut vectors: Vec<Vec<u64>>,
        products: impl Iterator<Item = Products>,
    ) -> Stimulus {
        let want_sides = products.map(|p| sides(&p, m.cfg.frac_bits())).collect();
        let width = vectors[0].len();
        vectors.extend(std::iter::repeat_n(vec![0; width], latency as usize + 1));
        let mut want = vec![vec![0, 0]; vectors.len()];
        for (k, &(i, j)) in pairs.iter().enumerate() {
            want[k + latency as usize - 1] = vec![1, u64::from(m.sat(i, j))];
        }
        Stimulus {
            vectors,
            want,
            want_sides,
        }
    }
}
