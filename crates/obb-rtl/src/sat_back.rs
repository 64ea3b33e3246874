//! The SAT after its first stage: rounding, the radius products, the minors, `r_B`, and the 15
//! comparisons, one pair per clock, bit for bit as `obb_model::fixed::sat::{sat_round,
//! sat_terms, sat_r_b, sat_decide}`.
//!
//! | clock | stage |
//! | --- | --- |
//! | 1 | `SatRound`: |t|, |u|, `ceil(|R|/2^f)`, `round(R/2^f)` and its magnitude, `floor(t/2^f)` |
//! | 2-6 | 51 DSP48E1: face radii (6 `SDot3`), `P` (9 `SDot2`), `r_A` (9), the 9 minors |
//! | 7 | `ceil(|minor|/2^f)` and `|P|` (`AbsShift`) |
//! | 8-12 | `r_B` (9 `SDot2`) |
//! | 13-16 | `SatDecide`: radius sums with the margins, then the 15 comparisons and their OR |

use crate::leaf::{sval, uval, zeroed, AbsShift, SDot2, SDot3, DOT_LATENCY};
use crate::pipe::Pipe;
use crate::sat_front::{RR, TU};
use crate::sat_round::{SatRound, ABS_TU, RT, R_UP, TH};
use obb_model::fixed::sat::{sat_decide, SatRounded, SatTerms};
use obb_model::fixed::{HwConfig, Margins};
use rust_hdl::prelude::*;
use std::fmt::Write as _;

/// A half-length, signed for the DSP ports (always non-negative).
pub const HALF_S: usize = 18;
/// The pair's margin `M_A + M_B`.
pub const PAIR_MARGIN: usize = crate::projection::MARGIN + 1;
/// Face radius sums `Σ h r_up` (19 x 18 bits, three terms).
pub const FACE: usize = R_UP + HALF_S + 2;
/// `P` and `|P|`.
pub const P_BITS: usize = TH + RT + 1;
/// `r_A` and the minors (18 x 18 bits, two terms).
pub const PAIR2: usize = 2 * RT + 1;
/// `ceil(|minor| / 2^f)` (at most 2^19, kept signed for the DSP's A port).
pub const MINOR: usize = 21;
/// `r_B` (21 x 18 bits, two terms).
pub const RB: usize = MINOR + HALF_S + 1;
/// The clocks after which each stage's results are registered (the table above): the values
/// that ride along are delayed from the stage that makes them to the stage that uses them.
const ROUNDED: usize = 1;
const PRODUCTS: usize = ROUNDED + DOT_LATENCY as usize;
const MINORS_ABS: usize = PRODUCTS + 1;
pub const R_B_DONE: usize = MINORS_ABS + DOT_LATENCY as usize;
/// Clocks from a pair's products on the inputs to its verdict: the stages, then the decision.
pub const LATENCY: u64 = R_B_DONE as u64 + SatDecide::LATENCY;

/// The radius sums and the 15 comparisons as one leaf (its arithmetic mixes signed products
/// with unsigned sums, which rust-hdl's Verilog gets wrong): four clocks, the sums in two
/// clocks of two-operand adds (a four-operand sum in one clock took 5.1 ns), the 15
/// comparisons (registered: with their OR in the same clock they took 5 LUT levels), their OR.
/// Its Rust model calls `obb_model::fixed::sat::sat_decide`. `f` and `k` are constants of the
/// configuration: the Verilog reads `f` in the first clock and `k` in the third, so a change
/// takes effect for the operands three clocks apart.
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SatDecide {
    pub abs_t: [Signal<In, Bits<ABS_TU>>; 3],
    pub abs_u: [Signal<In, Bits<ABS_TU>>; 3],
    pub face_a: [Signal<In, Signed<FACE>>; 3],
    pub face_b: [Signal<In, Signed<FACE>>; 3],
    pub abs_p: [Signal<In, Bits<P_BITS>>; 9],
    pub r_a: [Signal<In, Signed<PAIR2>>; 9],
    pub r_b: [Signal<In, Signed<RB>>; 9],
    pub half_a: [Signal<In, Signed<HALF_S>>; 3],
    pub half_b: [Signal<In, Signed<HALF_S>>; 3],
    pub pair_margin: Signal<In, Bits<PAIR_MARGIN>>,
    pub f: Signal<In, Bits<8>>,
    pub k: Signal<In, Bits<8>>,
    pub face_margin: Signal<In, Bits<24>>,
    pub cross_margin: Signal<In, Bits<24>>,
    /// No axis separates the pair.
    pub hit: Signal<Out, Bit>,
    pub clock: Signal<In, Clock>,
    // The verdict "some axis separates the pair" three, two and one clocks before its negation
    // shows on `hit` (the sums' and the comparisons' stages in the Verilog). Kept as
    // "separated" so that from reset, as in the Verilog (no comparison register set), `hit`
    // is high.
    verdict: Signal<Local, Bit>,
    verdict_q: Signal<Local, Bit>,
    verdict_qq: Signal<Local, Bit>,
}

/// Width of the radius sums and of the compared values.
const SUM: usize = 46;

impl SatDecide {
    /// Clocks from its operands to `hit`: two of sums, the comparisons, their OR.
    pub const LATENCY: u64 = 4;
}

impl Logic for SatDecide {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let shown = !self.verdict_qq.val();
            self.verdict_qq.next = self.verdict_q.val();
            self.verdict_q.next = self.verdict.val();
            let f = uval(self.f.val()) as u32;
            let k = uval(self.k.val()) as u32;
            let half = |h: &[Signal<In, Signed<HALF_S>>; 3]| h.each_ref().map(|s| sval(s.val()));
            let (half_a, half_b) = (half(&self.half_a), half(&self.half_b));
            let m = Margins {
                face: uval(self.face_margin.val()) as i64,
                cross: uval(self.cross_margin.val()) as i64,
                beta_num: 0,
                frac_bits: f,
                compare_shift: k,
            };
            let rounded = SatRounded {
                abs_t: self.abs_t.each_ref().map(|s| uval(s.val()) as i64),
                abs_u: self.abs_u.each_ref().map(|s| uval(s.val()) as i64),
                r_up: [[0; 3]; 3],
                rt: [[0; 3]; 3],
                th: [0; 3],
            };
            let grid = |s: &[Signal<In, Signed<PAIR2>>; 9]| {
                std::array::from_fn(|i| std::array::from_fn(|j| sval(s[3 * i + j].val())))
            };
            let terms = SatTerms {
                face_a: self.face_a.each_ref().map(|s| sval(s.val())),
                face_b: self.face_b.each_ref().map(|s| sval(s.val())),
                // |P| is what the comparisons use.
                p: std::array::from_fn(|i| {
                    std::array::from_fn(|j| uval(self.abs_p[3 * i + j].val()) as i64)
                }),
                r_a: grid(&self.r_a),
                minors: [[0; 3]; 3],
            };
            let r_b =
                std::array::from_fn(|i| std::array::from_fn(|j| sval(self.r_b[3 * i + j].val())));
            let pair = uval(self.pair_margin.val()) as i64;
            self.verdict.next = !sat_decide(&half_a, &half_b, pair, &rounded, &terms, &r_b, &m);
            self.hit.next = shown;
        }
    }
    fn connect(&mut self) {
        self.verdict.connect();
        self.verdict_q.connect();
        self.verdict_qq.connect();
        self.hit.connect();
    }
    fn hdl(&self) -> Verilog {
        let mut v = String::new();
        let s1 = SUM - 1;
        // Every operand is non-negative: zero-extend and add unsigned.
        let z = |name: &str| format!("{{{{{SUM}{{1'b0}}}}, {name}}}");
        let _ = writeln!(
            v,
            "reg [{s1}:0] part [0:14];\nreg [{s1}:0] face_m;\nreg [{s1}:0] cross_m;\n\
             reg [{s1}:0] lhs1 [0:14];\nreg [{s1}:0] lhs [0:14];\nreg [{s1}:0] rhs [0:14];\n\
             reg [14:0] apart;"
        );
        let arrays = ["part", "lhs1", "lhs", "rhs"];
        let entries = (0..15).flat_map(|x| arrays.map(|a| format!("{a}[{x}]")));
        let regs = ["face_m", "cross_m", "apart", "hit"].map(String::from);
        v.push_str(&zeroed(entries.chain(regs)));
        v.push_str("always @(posedge clock) begin\n");
        // Clock 1: the sums' two halves, each of two operands (one carry chain).
        for i in 0..3 {
            let _ = writeln!(
                v,
                "   part[{i}] <= ({} << f) + {};\n   lhs1[{i}] <= {};",
                z(&format!("half_a${i}")),
                z(&format!("face_a${i}")),
                z(&format!("abs_t${i}"))
            );
            let _ = writeln!(
                v,
                "   part[{}] <= ({} << f) + {};\n   lhs1[{}] <= {};",
                3 + i,
                z(&format!("half_b${i}")),
                z(&format!("face_b${i}")),
                3 + i,
                z(&format!("abs_u${i}"))
            );
        }
        for c in 0..9 {
            let _ = writeln!(
                v,
                "   part[{}] <= {} + {};\n   lhs1[{}] <= {};",
                6 + c,
                z(&format!("r_a${c}")),
                z(&format!("r_b${c}")),
                6 + c,
                z(&format!("abs_p${c}"))
            );
        }
        let _ = writeln!(
            v,
            "   face_m <= {} + {};\n   cross_m <= {} + {};",
            z("face_margin"),
            z("pair_margin"),
            z("cross_margin"),
            z("pair_margin")
        );
        // Clock 2: the radius sums; clock 3: the comparisons; clock 4: their OR.
        for x in 0..15 {
            let m = if x < 6 { "face_m" } else { "cross_m" };
            let _ = writeln!(
                v,
                "   lhs[{x}] <= lhs1[{x}];\n   rhs[{x}] <= part[{x}] + {m};\n   \
                 apart[{x}] <= (lhs[{x}] >> k) > (rhs[{x}] >> k);"
            );
        }
        v.push_str("   hit <= !(|apart);\nend\n");
        Verilog::Custom(v)
    }
}

#[derive(Clone, Debug, LogicBlock)]
pub struct SatBack {
    pub clock: Signal<In, Clock>,
    pub valid_in: Signal<In, Bit>,
    pub t: [Signal<In, Signed<TU>>; 3],
    pub u: [Signal<In, Signed<TU>>; 3],
    pub r: [Signal<In, Signed<RR>>; 9],
    pub half_a: [Signal<In, Signed<HALF_S>>; 3],
    pub half_b: [Signal<In, Signed<HALF_S>>; 3],
    pub pair_margin: Signal<In, Bits<PAIR_MARGIN>>,
    pub valid_out: Signal<Out, Bit>,
    /// No axis separates the pair.
    pub hit: Signal<Out, Bit>,
    frac: Constant<Bits<8>>,
    zero: Constant<Bits<8>>,
    shift: Constant<Bits<8>>,
    face_margin: Constant<Bits<24>>,
    cross_margin: Constant<Bits<24>>,
    /// `valid_in`, `LATENCY` clocks later.
    valid: Pipe<Bit, { LATENCY as usize }>,
    round: SatRound,
    // The half-lengths of A and B for the face radii and r_A (after the rounding), for r_B
    // (after the minors' magnitudes) and for the decision (after r_B).
    ha_products: [Pipe<Signed<HALF_S>, ROUNDED>; 3],
    hb_products: [Pipe<Signed<HALF_S>, ROUNDED>; 3],
    ha_r_b: [Pipe<Signed<HALF_S>, { MINORS_ABS - ROUNDED }>; 3],
    hb_r_b: [Pipe<Signed<HALF_S>, { MINORS_ABS - ROUNDED }>; 3],
    ha_decide: [Pipe<Signed<HALF_S>, { R_B_DONE - MINORS_ABS }>; 3],
    hb_decide: [Pipe<Signed<HALF_S>, { R_B_DONE - MINORS_ABS }>; 3],
    /// The pair's margin, for the decision.
    margin_decide: Pipe<Bits<PAIR_MARGIN>, R_B_DONE>,
    face_a_dot: [SDot3<R_UP, HALF_S, FACE>; 3],
    face_b_dot: [SDot3<R_UP, HALF_S, FACE>; 3],
    p_dot: [SDot2<TH, RT, P_BITS, true>; 9],
    ra_dot: [SDot2<HALF_S, RT, PAIR2, false>; 9],
    minor_dot: [SDot2<RT, RT, PAIR2, true>; 9],
    minor_abs: [AbsShift<PAIR2, MINOR>; 9],
    minor_s: [Signal<Local, Signed<MINOR>>; 9],
    p_abs: [AbsShift<P_BITS, P_BITS>; 9],
    rb_dot: [SDot2<MINOR, HALF_S, RB, false>; 9],
    // The decision's other operands, from the stage that makes them until r_B is done: |t|
    // and |u| (rounding), the face radii and r_A (products), |P| (magnitudes).
    abs_t_decide: [Pipe<Bits<ABS_TU>, { R_B_DONE - ROUNDED }>; 3],
    abs_u_decide: [Pipe<Bits<ABS_TU>, { R_B_DONE - ROUNDED }>; 3],
    face_a_decide: [Pipe<Signed<FACE>, { R_B_DONE - PRODUCTS }>; 3],
    face_b_decide: [Pipe<Signed<FACE>, { R_B_DONE - PRODUCTS }>; 3],
    r_a_decide: [Pipe<Signed<PAIR2>, { R_B_DONE - PRODUCTS }>; 9],
    abs_p_decide: [Pipe<Bits<P_BITS>, { R_B_DONE - MINORS_ABS }>; 9],
    /// The decision; its inputs hold every axis' sides (|t|, |u|, |P|, the face radii, r_A,
    /// r_B) of the pair `R_B_DONE` clocks after its products, which the tests read to compare
    /// the 15 axes value by value.
    pub decide: SatDecide,
}

impl SatBack {
    pub fn new(cfg: &HwConfig) -> SatBack {
        let m = Margins::new(cfg);
        assert!(m.face < 1 << 24 && m.cross < 1 << 24, "margins fit 24 bits");
        SatBack {
            clock: Default::default(),
            valid_in: Default::default(),
            t: Default::default(),
            u: Default::default(),
            r: Default::default(),
            half_a: Default::default(),
            half_b: Default::default(),
            pair_margin: Default::default(),
            valid_out: Default::default(),
            hit: Default::default(),
            frac: Constant::new(u64::from(cfg.frac_bits()).into()),
            zero: Constant::new(0u64.into()),
            shift: Constant::new(u64::from(cfg.sat_shift()).into()),
            face_margin: Constant::new((m.face as u64).into()),
            cross_margin: Constant::new((m.cross as u64).into()),
            valid: Default::default(),
            round: Default::default(),
            ha_products: Default::default(),
            hb_products: Default::default(),
            ha_r_b: Default::default(),
            hb_r_b: Default::default(),
            ha_decide: Default::default(),
            hb_decide: Default::default(),
            margin_decide: Default::default(),
            face_a_dot: Default::default(),
            face_b_dot: Default::default(),
            p_dot: Default::default(),
            ra_dot: Default::default(),
            minor_dot: Default::default(),
            minor_abs: Default::default(),
            minor_s: Default::default(),
            p_abs: Default::default(),
            rb_dot: Default::default(),
            abs_t_decide: Default::default(),
            abs_u_decide: Default::default(),
            face_a_decide: Default::default(),
            face_b_decide: Default::default(),
            r_a_decide: Default::default(),
            abs_p_decide: Default::default(),
            decide: Default::default(),
        }
    }
}

impl Logic for SatBack {
    #[hdl_gen]
    fn update(&mut self) {
        self.valid.clock.next = self.clock.val();
        self.margin_decide.clock.next = self.clock.val();
        for x in 0..3 {
            self.ha_products[x].clock.next = self.clock.val();
            self.hb_products[x].clock.next = self.clock.val();
            self.ha_r_b[x].clock.next = self.clock.val();
            self.hb_r_b[x].clock.next = self.clock.val();
            self.ha_decide[x].clock.next = self.clock.val();
            self.hb_decide[x].clock.next = self.clock.val();
            self.abs_t_decide[x].clock.next = self.clock.val();
            self.abs_u_decide[x].clock.next = self.clock.val();
            self.face_a_decide[x].clock.next = self.clock.val();
            self.face_b_decide[x].clock.next = self.clock.val();
        }
        for c in 0..9 {
            self.r_a_decide[c].clock.next = self.clock.val();
            self.abs_p_decide[c].clock.next = self.clock.val();
        }
        for i in 0..3 {
            self.face_a_dot[i].clock.next = self.clock.val();
        }
        for i in 0..3 {
            self.face_b_dot[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.p_dot[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.ra_dot[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.minor_dot[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.minor_abs[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.p_abs[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.rb_dot[i].clock.next = self.clock.val();
        }
        self.round.clock.next = self.clock.val();
        self.decide.clock.next = self.clock.val();
        // Valid, half-lengths and the pair margin ride along.
        self.valid.d.next = self.valid_in.val();
        self.margin_decide.d.next = self.pair_margin.val();
        for x in 0..3 {
            self.ha_products[x].d.next = self.half_a[x].val();
            self.hb_products[x].d.next = self.half_b[x].val();
            self.ha_r_b[x].d.next = self.ha_products[x].q.val();
            self.hb_r_b[x].d.next = self.hb_products[x].q.val();
            self.ha_decide[x].d.next = self.ha_r_b[x].q.val();
            self.hb_decide[x].d.next = self.hb_r_b[x].q.val();
        }
        // Clock 1: rounding.
        self.round.f.next = self.frac.val();
        for i in 0..3 {
            self.round.t[i].next = self.t[i].val();
            self.round.u[i].next = self.u[i].val();
        }
        for i in 0..9 {
            self.round.r[i].next = self.r[i].val();
        }
        // Clocks 2-6: face radii, P, r_A and the minors (the halves `*_products`), as
        // `obb_model::fixed::sat::sat_terms` states them. R = A Bᵀ row-major (`r_up`, `rt`,
        // `art` hold |R| rounded up, R rounded, |R| rounded, at `3 i + j`); `th` is t in A's
        // frame. For face i, and for the cross axis A_i x B_j at c = 3 i + j, with the
        // cyclic (i1, i2) = ((i + 1) % 3, (i + 2) % 3) and column pair p = j of
        // {0, 1}, {0, 2}, {1, 2} (its columns (j / 2, (j + 3) / 2)):
        //
        // | product | a0 * b0 + a1 * b1 (+ a2 * b2) |
        // | --- | --- |
        // | face_a[i] = r_A of axis A_i | r_up[3 i + k] * h^B_k, k = 0..3 |
        // | face_b[i] = r_B of axis B_i | r_up[3 k + i] * h^A_k, k = 0..3 |
        // | P[c] = t . (A_i x B_j) | th[i2] * rt[3 i1 + j] - th[i1] * rt[3 i2 + j] |
        // | r_A[c] | h^A_i1 * art[3 i2 + j] + h^A_i2 * art[3 i1 + j] |
        // | minor[3 i + p] of rows i1, i2, columns p | rt[3 i1 + p0] * rt[3 i2 + p1] - rt[3 i2 + p0] * rt[3 i1 + p1] |
        //
        // The loops unroll to the literal indices in the Verilog (`hdl_gen` evaluates index
        // expressions), in the order the products were written by hand before.
        for i in 0..3 {
            self.face_a_dot[i].a0.next = self.round.r_up[3 * i].val();
            self.face_a_dot[i].a1.next = self.round.r_up[3 * i + 1].val();
            self.face_a_dot[i].a2.next = self.round.r_up[3 * i + 2].val();
            self.face_a_dot[i].b0.next = self.hb_products[0].q.val();
            self.face_a_dot[i].b1.next = self.hb_products[1].q.val();
            self.face_a_dot[i].b2.next = self.hb_products[2].q.val();
            self.face_b_dot[i].a0.next = self.round.r_up[i].val();
            self.face_b_dot[i].a1.next = self.round.r_up[3 + i].val();
            self.face_b_dot[i].a2.next = self.round.r_up[6 + i].val();
            self.face_b_dot[i].b0.next = self.ha_products[0].q.val();
            self.face_b_dot[i].b1.next = self.ha_products[1].q.val();
            self.face_b_dot[i].b2.next = self.ha_products[2].q.val();
        }
        for i in 0..3 {
            for j in 0..3 {
                self.p_dot[3 * i + j].a0.next = self.round.th[(i + 2) % 3].val();
                self.p_dot[3 * i + j].b0.next = self.round.rt[3 * ((i + 1) % 3) + j].val();
                self.p_dot[3 * i + j].a1.next = self.round.th[(i + 1) % 3].val();
                self.p_dot[3 * i + j].b1.next = self.round.rt[3 * ((i + 2) % 3) + j].val();
                self.ra_dot[3 * i + j].a0.next = self.ha_products[(i + 1) % 3].q.val();
                self.ra_dot[3 * i + j].b0.next = self.round.art[3 * ((i + 2) % 3) + j].val();
                self.ra_dot[3 * i + j].a1.next = self.ha_products[(i + 2) % 3].q.val();
                self.ra_dot[3 * i + j].b1.next = self.round.art[3 * ((i + 1) % 3) + j].val();
            }
            for p in 0..3 {
                self.minor_dot[3 * i + p].a0.next = self.round.rt[3 * ((i + 1) % 3) + p / 2].val();
                self.minor_dot[3 * i + p].b0.next =
                    self.round.rt[3 * ((i + 2) % 3) + (p + 3) / 2].val();
                self.minor_dot[3 * i + p].a1.next = self.round.rt[3 * ((i + 2) % 3) + p / 2].val();
                self.minor_dot[3 * i + p].b1.next =
                    self.round.rt[3 * ((i + 1) % 3) + (p + 3) / 2].val();
            }
        }
        // Clock 7: ceil(|minor| / 2^f) and |P|.
        for c in 0..9 {
            self.minor_abs[c].x.next = self.minor_dot[c].p.val();
            self.minor_abs[c].s.next = self.frac.val();
            self.p_abs[c].x.next = self.p_dot[c].p.val();
            self.p_abs[c].s.next = self.zero.val();
        }
        // Written out: `hdl_gen` does not substitute a loop index inside a generic call's
        // arguments (`signed_cast::<MINOR>(self.minor_abs[c].y.val())` does not compile).
        self.minor_s[0].next = signed_cast::<MINOR>(self.minor_abs[0].y.val());
        self.minor_s[1].next = signed_cast::<MINOR>(self.minor_abs[1].y.val());
        self.minor_s[2].next = signed_cast::<MINOR>(self.minor_abs[2].y.val());
        self.minor_s[3].next = signed_cast::<MINOR>(self.minor_abs[3].y.val());
        self.minor_s[4].next = signed_cast::<MINOR>(self.minor_abs[4].y.val());
        self.minor_s[5].next = signed_cast::<MINOR>(self.minor_abs[5].y.val());
        self.minor_s[6].next = signed_cast::<MINOR>(self.minor_abs[6].y.val());
        self.minor_s[7].next = signed_cast::<MINOR>(self.minor_abs[7].y.val());
        self.minor_s[8].next = signed_cast::<MINOR>(self.minor_abs[8].y.val());
        // Clocks 8-12: r_B[3 i + j] = Σ_(l != j) h^B_l minor(i, {j, l}) (the halves `hb_r_b`): for j = 0, 1, 2 the column pairs {0, 1} and {0, 2}, {0, 1} and {1, 2},
        // {0, 2} and {1, 2}, that is minors 3 i + j / 2 and 3 i + (j + 3) / 2, times h^B of the
        // other column of each, (2 - j) / 2 and 2 - j / 2.
        for i in 0..3 {
            for j in 0..3 {
                self.rb_dot[3 * i + j].a0.next = self.minor_s[3 * i + j / 2].val();
                self.rb_dot[3 * i + j].b0.next = self.hb_r_b[(2 - j) / 2].q.val();
                self.rb_dot[3 * i + j].a1.next = self.minor_s[3 * i + (j + 3) / 2].val();
                self.rb_dot[3 * i + j].b1.next = self.hb_r_b[2 - j / 2].q.val();
            }
        }
        // The decision's operands wait for r_B.
        for i in 0..3 {
            self.abs_t_decide[i].d.next = self.round.abs_t[i].val();
            self.abs_u_decide[i].d.next = self.round.abs_u[i].val();
            self.face_a_decide[i].d.next = self.face_a_dot[i].p.val();
            self.face_b_decide[i].d.next = self.face_b_dot[i].p.val();
        }
        for c in 0..9 {
            self.r_a_decide[c].d.next = self.ra_dot[c].p.val();
            self.abs_p_decide[c].d.next = self.p_abs[c].y.val();
        }
        // Clocks 13-16: the decision.
        self.decide.f.next = self.frac.val();
        self.decide.k.next = self.shift.val();
        self.decide.face_margin.next = self.face_margin.val();
        self.decide.cross_margin.next = self.cross_margin.val();
        self.decide.pair_margin.next = self.margin_decide.q.val();
        for i in 0..3 {
            self.decide.abs_t[i].next = self.abs_t_decide[i].q.val();
            self.decide.abs_u[i].next = self.abs_u_decide[i].q.val();
            self.decide.face_a[i].next = self.face_a_decide[i].q.val();
            self.decide.face_b[i].next = self.face_b_decide[i].q.val();
            self.decide.half_a[i].next = self.ha_decide[i].q.val();
            self.decide.half_b[i].next = self.hb_decide[i].q.val();
        }
        for c in 0..9 {
            self.decide.abs_p[c].next = self.abs_p_decide[c].q.val();
            self.decide.r_a[c].next = self.r_a_decide[c].q.val();
            self.decide.r_b[c].next = self.rb_dot[c].p.val();
        }
        self.valid_out.next = self.valid.q.val();
        self.hit.next = self.decide.hit.val();
    }
}
