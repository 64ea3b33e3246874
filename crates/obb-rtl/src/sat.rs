//! The SAT pipeline: one pair of boxes per clock in, the verdict (no axis separates them) out
//! `LATENCY` clocks later, bit for bit as `obb_model::fixed::sat::collide`. `sat_front` (the
//! exact products) followed by `sat_back`; the half-lengths and the pair's margin ride along.

use crate::pipe::Pipe;
use crate::projection::{CENTER, HALF, MARGIN, ROT};
use crate::sat_back::{SatBack, HALF_S, PAIR_MARGIN};
use crate::sat_front::{self, SatFront};
use obb_model::fixed::HwConfig;
use rust_hdl::prelude::*;

/// Clocks from a pair on the inputs to its verdict.
pub const LATENCY: u64 = sat_front::LATENCY + crate::sat_back::LATENCY;
/// The front's latency, the back end's inputs' delay behind `valid_in`.
const FRONT: usize = sat_front::LATENCY as usize;

#[derive(Clone, Debug, LogicBlock)]
pub struct Sat {
    pub clock: Signal<In, Clock>,
    pub valid_in: Signal<In, Bit>,
    /// Box A (the lower index): its center, offset binary.
    pub center_a: [Signal<In, Bits<CENTER>>; 3],
    /// Box A's half-lengths.
    pub half_a: [Signal<In, Bits<HALF>>; 3],
    /// Box A's axes, `axes_a[3k + x]`.
    pub axes_a: [Signal<In, Signed<ROT>>; 9],
    /// Box A's projection margin.
    pub margin_a: Signal<In, Bits<MARGIN>>,
    /// Box B (the higher index): its center, offset binary.
    pub center_b: [Signal<In, Bits<CENTER>>; 3],
    /// Box B's half-lengths.
    pub half_b: [Signal<In, Bits<HALF>>; 3],
    /// Box B's axes, `axes_b[3k + x]`.
    pub axes_b: [Signal<In, Signed<ROT>>; 9],
    /// Box B's projection margin.
    pub margin_b: Signal<In, Bits<MARGIN>>,
    /// The pair's verdict is on `hit`, `LATENCY` clocks after `valid_in`.
    pub valid_out: Signal<Out, Bit>,
    /// No axis separates the pair: it is reported.
    pub hit: Signal<Out, Bit>,
    front: SatFront,
    /// The back end (public for the tests, which read the sides of every axis it decides on).
    pub back: SatBack,
    // The half-lengths, signed, and the pair margin, delayed to the back end's inputs.
    ha: [Pipe<Signed<HALF_S>, FRONT>; 3],
    hb: [Pipe<Signed<HALF_S>, FRONT>; 3],
    pm: Pipe<Bits<PAIR_MARGIN>, FRONT>,
    ha_s: [Signal<Local, Signed<HALF_S>>; 3],
    hb_s: [Signal<Local, Signed<HALF_S>>; 3],
    pair: Signal<Local, Bits<PAIR_MARGIN>>,
}

impl Sat {
    pub fn new(cfg: &HwConfig) -> Sat {
        Sat {
            clock: Default::default(),
            valid_in: Default::default(),
            center_a: Default::default(),
            half_a: Default::default(),
            axes_a: Default::default(),
            margin_a: Default::default(),
            center_b: Default::default(),
            half_b: Default::default(),
            axes_b: Default::default(),
            margin_b: Default::default(),
            valid_out: Default::default(),
            hit: Default::default(),
            front: Default::default(),
            back: SatBack::new(cfg),
            ha: Default::default(),
            hb: Default::default(),
            pm: Default::default(),
            ha_s: Default::default(),
            hb_s: Default::default(),
            pair: Default::default(),
        }
    }
}

impl Logic for Sat {
    #[hdl_gen]
    fn update(&mut self) {
        self.front.clock.next = self.clock.val();
        self.back.clock.next = self.clock.val();
        for x in 0..3 {
            self.ha[x].clock.next = self.clock.val();
            self.hb[x].clock.next = self.clock.val();
        }
        self.pm.clock.next = self.clock.val();
        self.front.valid_in.next = self.valid_in.val();
        for x in 0..3 {
            self.front.center_a[x].next = self.center_a[x].val();
            self.front.center_b[x].next = self.center_b[x].val();
        }
        for i in 0..9 {
            self.front.axes_a[i].next = self.axes_a[i].val();
            self.front.axes_b[i].next = self.axes_b[i].val();
        }
        // Half-lengths as signed DSP operands (casts written out: see docs/hardware.md).
        self.ha_s[0].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_a[0].val()));
        self.ha_s[1].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_a[1].val()));
        self.ha_s[2].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_a[2].val()));
        self.hb_s[0].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_b[0].val()));
        self.hb_s[1].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_b[1].val()));
        self.hb_s[2].next = signed_cast::<HALF_S>(bit_cast::<HALF_S, HALF>(self.half_b[2].val()));
        self.pair.next = bit_cast::<PAIR_MARGIN, MARGIN>(self.margin_a.val())
            + bit_cast::<PAIR_MARGIN, MARGIN>(self.margin_b.val());
        for x in 0..3 {
            self.ha[x].d.next = self.ha_s[x].val();
            self.hb[x].d.next = self.hb_s[x].val();
        }
        self.pm.d.next = self.pair.val();
        // The back end takes the products with the box data delayed by the front's latency.
        self.back.valid_in.next = self.front.valid_out.val();
        for i in 0..3 {
            self.back.t[i].next = self.front.t[i].val();
            self.back.u[i].next = self.front.u[i].val();
            self.back.half_a[i].next = self.ha[i].q.val();
            self.back.half_b[i].next = self.hb[i].q.val();
        }
        for i in 0..9 {
            self.back.r[i].next = self.front.r[i].val();
        }
        self.back.pair_margin.next = self.pm.q.val();
        self.valid_out.next = self.back.valid_out.val();
        self.hit.next = self.back.hit.val();
    }
}
