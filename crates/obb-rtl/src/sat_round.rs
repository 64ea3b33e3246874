//! The SAT's rounding stage as one registered leaf (shifts with rounding and absolute values of
//! signed values, which rust-hdl's Verilog gets wrong): `obb_model::fixed::sat::sat_round` plus
//! `|R̃|`. Its Rust model calls the model itself, and its Verilog is checked against it.

use crate::leaf::{sbits, sval, uval, zeroed};
use crate::sat_front::{RR, TU};
use obb_model::fixed::sat::{sat_round, SatProducts};
use rust_hdl::prelude::*;
use std::fmt::Write as _;

/// |t| and |u| (below 2^43).
pub const ABS_TU: usize = TU - 1;
/// `ceil(|R| / 2^f)` (at most 2^17 + 1, kept signed for the DSP's A port).
pub const R_UP: usize = 19;
/// `round(R / 2^f)` and its magnitude (|R̃| < 2^17).
pub const RT: usize = 18;
/// `floor(t / 2^f)` (|t̂| < 2^24, `HwConfig::validate`).
pub const TH: usize = 25;

#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SatRound {
    pub t: [Signal<In, Signed<TU>>; 3],
    pub u: [Signal<In, Signed<TU>>; 3],
    pub r: [Signal<In, Signed<RR>>; 9],
    /// The rotation fraction bits f.
    pub f: Signal<In, Bits<8>>,
    pub abs_t: [Signal<Out, Bits<ABS_TU>>; 3],
    pub abs_u: [Signal<Out, Bits<ABS_TU>>; 3],
    pub r_up: [Signal<Out, Signed<R_UP>>; 9],
    pub rt: [Signal<Out, Signed<RT>>; 9],
    pub art: [Signal<Out, Signed<RT>>; 9],
    pub th: [Signal<Out, Signed<TH>>; 3],
    pub clock: Signal<In, Clock>,
}

impl Logic for SatRound {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let p = SatProducts {
                t: std::array::from_fn(|i| sval(self.t[i].val())),
                u: std::array::from_fn(|i| sval(self.u[i].val())),
                r: std::array::from_fn(|i| std::array::from_fn(|j| sval(self.r[3 * i + j].val()))),
            };
            let f = uval(self.f.val()) as u32;
            if f == 0 {
                return; // before the constant reaches the leaf
            }
            let q = sat_round(&p, f);
            for i in 0..3 {
                self.abs_t[i].next = Bits::from(q.abs_t[i] as u64);
                self.abs_u[i].next = Bits::from(q.abs_u[i] as u64);
                self.th[i].next = sbits(q.th[i]);
                for j in 0..3 {
                    self.r_up[3 * i + j].next = sbits(q.r_up[i][j]);
                    self.rt[3 * i + j].next = sbits(q.rt[i][j]);
                    self.art[3 * i + j].next = sbits(q.rt[i][j].abs());
                }
            }
        }
    }
    fn connect(&mut self) {
        for i in 0..3 {
            self.abs_t[i].connect();
            self.abs_u[i].connect();
            self.th[i].connect();
        }
        for i in 0..9 {
            self.r_up[i].connect();
            self.rt[i].connect();
            self.art[i].connect();
        }
    }
    fn hdl(&self) -> Verilog {
        let mut v = String::new();
        let (tu1, rr1) = (TU - 1, RR - 1);
        // 2^(f-1) (positive, one bit wider than R) and 2^f - 1.
        let _ = writeln!(
            v,
            "wire [{rr}:0] half_u = {{{{{rr}{{1'b0}}}}, 1'b1}} << (f - 1);",
            rr = RR
        );
        let _ = writeln!(v, "wire signed [{rr}:0] half = $signed(half_u);", rr = RR);
        let _ = writeln!(
            v,
            "wire [{rr}:0] ones = ({{{{{rr}{{1'b0}}}}, 1'b1}} << f) - 1;",
            rr = RR
        );
        for i in 0..3 {
            let _ = writeln!(v, "wire [{tu1}:0] mt{i} = t${i}[{tu1}] ? -t${i} : t${i};");
            let _ = writeln!(v, "wire [{tu1}:0] mu{i} = u${i}[{tu1}] ? -u${i} : u${i};");
        }
        // The magnitudes take one carry chain each, not a negation and then an add: with
        // x = (R < 0 ? ~R : R) = |R| - (R < 0), `ceil(|R|/2^f) = (x + 2^f - 1 + (R < 0)) >> f`
        // and `|round(R/2^f)| = (x + 2^(f-1)) >> f` (for R < 0, -floor((R + 2^(f-1)) / 2^f)
        // = floor((|R| + 2^(f-1) - 1) / 2^f)).
        for k in 0..9 {
            let _ = writeln!(v, "wire [{rr1}:0] xr{k} = r${k}[{rr1}] ? ~r${k} : r${k};");
            let _ = writeln!(
                v,
                "wire [{rr}:0] up{k} = ({{1'b0, xr{k}}} + ones + r${k}[{rr1}]) >> f;",
                rr = RR
            );
            let _ = writeln!(
                v,
                "wire signed [{rr}:0] near{k} = ($signed({{r${k}[{rr1}], r${k}}}) + half) >>> f;",
                rr = RR
            );
            let _ = writeln!(
                v,
                "wire [{rr}:0] anear{k} = ({{1'b0, xr{k}}} + half_u) >> f;",
                rr = RR
            );
        }
        let regs = (0..3).flat_map(|i| {
            [
                format!("abs_t${i}"),
                format!("abs_u${i}"),
                format!("th${i}"),
            ]
        });
        let rounded =
            (0..9).flat_map(|k| [format!("r_up${k}"), format!("rt${k}"), format!("art${k}")]);
        v.push_str(&zeroed(regs.chain(rounded)));
        v.push_str("always @(posedge clock) begin\n");
        for i in 0..3 {
            let _ = writeln!(
                v,
                "   abs_t${i} <= mt{i};\n   abs_u${i} <= mu{i};\n   th${i} <= t${i} >>> f;"
            );
        }
        for k in 0..9 {
            let _ = writeln!(
                v,
                "   r_up${k} <= up{k};\n   rt${k} <= near{k};\n   art${k} <= anear{k};"
            );
        }
        v.push_str("end\n");
        Verilog::Custom(v)
    }
}
