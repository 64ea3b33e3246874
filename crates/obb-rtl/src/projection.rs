//! The projection pipeline: one OBB per clock in, its sort keys (min and max per axis) and its
//! SAT margin out, `LATENCY` clocks later, bit for bit as `obb_model::fixed::quantize::project`
//! and `keys` compute them.
//!
//! On the wire a center is offset binary (`u = c + 2^(center_bits-1)`), so every value in the
//! pipeline is unsigned: an end point `u ± E` is already the offset end point the keys cut.
//!
//! | clock | stage |
//! | --- | --- |
//! | 1 | input registers |
//! | 2 | `2|r|+1` for the 9 rotation entries; `S = Σh` |
//! | 3-5 | 9 products `h_k (2|r_kx|+1)` and `S·B`, one DSP48E1 each |
//! | 6 | per axis the sum of 3 products plus `3·2^f - 1`; the margin `(S·B + 255) >> 8` |
//! | 7 | `E = sum >> (f+1)`; `min = u - E`, `max = u + E` |
//! | 8 | keys: `min >> s`, `(max + 2^s - 1) >> s` |

use crate::leaf::{AbsTwice, UMul};
use crate::pipe::Pipe;
use obb_model::fixed::margins::BETA_SHIFT;
use obb_model::fixed::{HwConfig, Margins};
use rust_hdl::prelude::*;

/// Widest formats the datapath carries (docs/numerics.md): narrower configurations use the low
/// bits; the shifts and constants come from the configuration.
pub const CENTER: usize = 23;
pub const HALF: usize = 17;
pub const ROT: usize = 18;
/// `2|r| + 1` for |r| <= 2^17.
const TERM: usize = 19;
const PRODUCT: usize = HALF + TERM;
/// A sum of three products plus `3·2^f`.
const SUM: usize = PRODUCT + 2;
/// End points `u ± E` (below 2^23 by the range check, with a bit of room).
const END: usize = CENTER + 1;
/// Σh of three half-lengths.
const HSUM: usize = HALF + 2;
/// The margin slope `B = β·2^8` (below 2^16 for every supported configuration).
const BETA: usize = 16;
const SB: usize = HSUM + BETA;
/// The per-box margin.
pub const MARGIN: usize = SB - BETA_SHIFT as usize + 1;

/// Clocks from an OBB on the inputs to its keys on the outputs.
pub const LATENCY: u64 = 8;

#[derive(Clone, Debug, LogicBlock)]
pub struct Projection {
    pub clock: Signal<In, Clock>,
    pub valid_in: Signal<In, Bit>,
    /// Centers, offset binary.
    pub center: [Signal<In, Bits<CENTER>>; 3],
    /// Half-lengths, rounded up.
    pub half: [Signal<In, Bits<HALF>>; 3],
    /// `axes[3k + x]`: entry x of axis k, Q1.f.
    pub axes: [Signal<In, Signed<ROT>>; 9],
    /// The box's keys and margin are on the outputs, `LATENCY` clocks after `valid_in`.
    pub valid_out: Signal<Out, Bit>,
    /// The AABB's lower end points, as keys.
    pub key_min: [Signal<Out, Bits<CENTER>>; 3],
    /// The AABB's upper end points, as keys.
    pub key_max: [Signal<Out, Bits<CENTER>>; 3],
    /// The box's SAT margin (docs/numerics.md).
    pub margin: Signal<Out, Bits<MARGIN>>,
    // Configuration constants.
    frac1: Constant<Bits<8>>,
    round: Constant<Bits<SUM>>,
    key_shift: Constant<Bits<8>>,
    key_round: Constant<Bits<END>>,
    beta: Constant<Bits<BETA>>,
    margin_round: Constant<Bits<SB>>,
    margin_shift: Constant<Bits<8>>,
    // Pipeline.
    /// `valid_in`, `LATENCY` clocks later.
    valid: Pipe<Bit, { LATENCY as usize }>,
    /// The centers, from the input to clock 7's end points: after clock 6.
    center_r: [Pipe<Bits<CENTER>, 6>; 3],
    half_r: [DFF<Bits<HALF>>; 3],
    hdelay: [DFF<Bits<HALF>>; 3],
    axes_r: [DFF<Signed<ROT>>; 9],
    terms: [AbsTwice<ROT, TERM>; 9],
    products: [UMul<HALF, TERM, PRODUCT>; 9],
    hsum: DFF<Bits<HSUM>>,
    sb: UMul<HSUM, BETA, SB>,
    sum: [DFF<Bits<SUM>>; 3],
    margin_r: [DFF<Bits<MARGIN>>; 2],
    lo: [DFF<Bits<END>>; 3],
    hi: [DFF<Bits<END>>; 3],
    kmin: [DFF<Bits<CENTER>>; 3],
    kmax: [DFF<Bits<CENTER>>; 3],
    margin_o: DFF<Bits<MARGIN>>,
    // Combinational intermediates.
    hsum_c: Signal<Local, Bits<HSUM>>,
    sum_c: [Signal<Local, Bits<SUM>>; 3],
    extent: [Signal<Local, Bits<END>>; 3],
    rounded: [Signal<Local, Bits<END>>; 3],
    wide: [Signal<Local, Bits<END>>; 3],
    low_key: [Signal<Local, Bits<END>>; 3],
    high_key: [Signal<Local, Bits<END>>; 3],
    sb_c: Signal<Local, Bits<SB>>,
}

impl Projection {
    /// The pipeline for configuration `cfg` (which must be valid: `HwConfig::validate`).
    pub fn new(cfg: &HwConfig) -> Projection {
        let f = u64::from(cfg.frac_bits());
        let s = u64::from(cfg.key_shift());
        let margins = Margins::new(cfg);
        let beta = margins.beta_num as u64;
        assert!(
            beta < 1 << BETA,
            "the margin slope {beta} needs more than {BETA} bits"
        );
        Projection {
            clock: Default::default(),
            valid_in: Default::default(),
            center: Default::default(),
            half: Default::default(),
            axes: Default::default(),
            valid_out: Default::default(),
            key_min: Default::default(),
            key_max: Default::default(),
            margin: Default::default(),
            frac1: Constant::new((f + 1).into()),
            round: Constant::new((3 * (1u64 << f) - 1).into()),
            key_shift: Constant::new(s.into()),
            key_round: Constant::new(((1u64 << s) - 1).into()),
            beta: Constant::new(beta.into()),
            margin_round: Constant::new(((1u64 << BETA_SHIFT) - 1).into()),
            margin_shift: Constant::new(u64::from(BETA_SHIFT).into()),
            valid: Default::default(),
            center_r: Default::default(),
            half_r: Default::default(),
            hdelay: Default::default(),
            axes_r: Default::default(),
            terms: Default::default(),
            products: Default::default(),
            hsum: Default::default(),
            sb: Default::default(),
            sum: Default::default(),
            margin_r: Default::default(),
            lo: Default::default(),
            hi: Default::default(),
            kmin: Default::default(),
            kmax: Default::default(),
            margin_o: Default::default(),
            hsum_c: Default::default(),
            sum_c: Default::default(),
            extent: Default::default(),
            rounded: Default::default(),
            wide: Default::default(),
            low_key: Default::default(),
            high_key: Default::default(),
            sb_c: Default::default(),
        }
    }
}

impl Logic for Projection {
    #[hdl_gen]
    fn update(&mut self) {
        // Clocks and register feedback.
        self.valid.clock.next = self.clock.val();
        for k in 0..3 {
            self.center_r[k].clock.next = self.clock.val();
            self.half_r[k].clock.next = self.clock.val();
            self.hdelay[k].clock.next = self.clock.val();
            self.sum[k].clock.next = self.clock.val();
            self.lo[k].clock.next = self.clock.val();
            self.hi[k].clock.next = self.clock.val();
            self.kmin[k].clock.next = self.clock.val();
            self.kmax[k].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.axes_r[i].clock.next = self.clock.val();
            self.terms[i].clock.next = self.clock.val();
            self.products[i].clock.next = self.clock.val();
        }
        self.hsum.clock.next = self.clock.val();
        self.sb.clock.next = self.clock.val();
        self.margin_r[0].clock.next = self.clock.val();
        self.margin_r[1].clock.next = self.clock.val();
        self.margin_o.clock.next = self.clock.val();
        // Clock 1: input registers; the valid bit and the centers ride along to the end.
        self.valid.d.next = self.valid_in.val();
        for x in 0..3 {
            self.center_r[x].d.next = self.center[x].val();
            self.half_r[x].d.next = self.half[x].val();
        }
        for i in 0..9 {
            self.axes_r[i].d.next = self.axes[i].val();
        }
        // Clock 2: 2|r| + 1, the half-lengths alongside, and S = Σh.
        for i in 0..9 {
            self.terms[i].r.next = self.axes_r[i].q.val();
        }
        for k in 0..3 {
            self.hdelay[k].d.next = self.half_r[k].q.val();
        }
        self.hsum_c.next = bit_cast::<HSUM, HALF>(self.half_r[0].q.val())
            + bit_cast::<HSUM, HALF>(self.half_r[1].q.val());
        self.hsum.d.next = self.hsum_c.val() + bit_cast::<HSUM, HALF>(self.half_r[2].q.val());
        // Clocks 3-5: the products h_k (2|r_kx| + 1) and S·B.
        for k in 0..3 {
            for x in 0..3 {
                self.products[k * 3 + x].a.next = self.hdelay[k].q.val();
                self.products[k * 3 + x].b.next = self.terms[k * 3 + x].t.val();
            }
        }
        self.sb.a.next = self.hsum.q.val();
        self.sb.b.next = self.beta.val();
        // Clock 6: per axis Σ_k of the products plus 3·2^f - 1 (so that the shift below rounds
        // (sum + 2^f) / 2^(f+1) up); the margin ceil(S·B / 2^8). (rust-hdl does not substitute
        // a loop index inside a cast's argument: the casts are written out per axis.)
        self.sum_c[0].next = bit_cast::<SUM, PRODUCT>(self.products[0].p.val())
            + bit_cast::<SUM, PRODUCT>(self.products[3].p.val());
        self.sum_c[1].next = bit_cast::<SUM, PRODUCT>(self.products[1].p.val())
            + bit_cast::<SUM, PRODUCT>(self.products[4].p.val());
        self.sum_c[2].next = bit_cast::<SUM, PRODUCT>(self.products[2].p.val())
            + bit_cast::<SUM, PRODUCT>(self.products[5].p.val());
        self.sum[0].d.next = self.sum_c[0].val()
            + bit_cast::<SUM, PRODUCT>(self.products[6].p.val())
            + self.round.val();
        self.sum[1].d.next = self.sum_c[1].val()
            + bit_cast::<SUM, PRODUCT>(self.products[7].p.val())
            + self.round.val();
        self.sum[2].d.next = self.sum_c[2].val()
            + bit_cast::<SUM, PRODUCT>(self.products[8].p.val())
            + self.round.val();
        self.sb_c.next = self.sb.p.val() + self.margin_round.val();
        self.margin_r[0].d.next =
            bit_cast::<MARGIN, SB>(self.sb_c.val() >> self.margin_shift.val());
        self.margin_r[1].d.next = self.margin_r[0].q.val();
        // Clock 7: E and the end points.
        self.extent[0].next = bit_cast::<END, SUM>(self.sum[0].q.val() >> self.frac1.val());
        self.extent[1].next = bit_cast::<END, SUM>(self.sum[1].q.val() >> self.frac1.val());
        self.extent[2].next = bit_cast::<END, SUM>(self.sum[2].q.val() >> self.frac1.val());
        self.wide[0].next = bit_cast::<END, CENTER>(self.center_r[0].q.val());
        self.wide[1].next = bit_cast::<END, CENTER>(self.center_r[1].q.val());
        self.wide[2].next = bit_cast::<END, CENTER>(self.center_r[2].q.val());
        for x in 0..3 {
            self.lo[x].d.next = self.wide[x].val() - self.extent[x].val();
            self.hi[x].d.next = self.wide[x].val() + self.extent[x].val();
            self.rounded[x].next = self.hi[x].q.val() + self.key_round.val();
            self.low_key[x].next = self.lo[x].q.val() >> self.key_shift.val();
            self.high_key[x].next = self.rounded[x].val() >> self.key_shift.val();
        }
        self.margin_o.d.next = self.margin_r[1].q.val();
        // Clock 8: the keys, min rounded down and max up.
        self.kmin[0].d.next = bit_cast::<CENTER, END>(self.low_key[0].val());
        self.kmin[1].d.next = bit_cast::<CENTER, END>(self.low_key[1].val());
        self.kmin[2].d.next = bit_cast::<CENTER, END>(self.low_key[2].val());
        self.kmax[0].d.next = bit_cast::<CENTER, END>(self.high_key[0].val());
        self.kmax[1].d.next = bit_cast::<CENTER, END>(self.high_key[1].val());
        self.kmax[2].d.next = bit_cast::<CENTER, END>(self.high_key[2].val());
        for x in 0..3 {
            self.key_min[x].next = self.kmin[x].q.val();
            self.key_max[x].next = self.kmax[x].q.val();
        }
        self.valid_out.next = self.valid.q.val();
        self.margin.next = self.margin_o.q.val();
    }
}
