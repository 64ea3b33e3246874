//! The broad phase's walker for `brute` and `improved-sap` (`sweep` has its own, `sweep.rs`):
//! it visits index pairs (i, j), at most one per clock, in the order of
//! `obb_model::fixed::broad`. It drives the read addresses of the key table (box i on port A,
//! box j on port B); the core checks each visit's keys and groups one clock later.
//!
//! - `brute`: i = 0, 1, ...; j = i+1, ..., n-1; one visit per clock, no overhead.
//! - `improved-sap` (the paper's Algorithm 2), per axis x, y, z: the walker loads the 2n end
//!   points (box 0 min, box 0 max, box 1 min, ...: key `2k + is_max`, value `2b + is_max`) into
//!   the radix sort from the key table, two clocks per box, sorts them, then reads them in
//!   order: a max end point costs one clock; a min end point of box i one clock, then one per
//!   end point read until i's own max (each other box met is a visit, with no key check); one
//!   clock starts the next axis.
//!
//! `stall` holds back visits (the output is filling); it never drops one. Brute makes no visit
//! on a stalled clock; improved-sap may make [`RUN_ON`] (the end point read before the stall).

use crate::projection::CENTER;
use crate::radix::{KEY, VAL};
use rust_hdl::prelude::*;

/// Visits the walker may still make from the clock `stall` rises until it falls: improved-sap's
/// end point already read when a walk step stalls (its read is not repeated), or a walk's first
/// one, read by the head; brute none.
pub const RUN_ON: u64 = 1;

#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum WalkState {
    Idle,
    /// Brute: the pairs (i, j).
    Pairs,
    /// Improved-sap: the end points of the axis into the radix sort, two clocks per box.
    Ends,
    /// Improved-sap: the clock that takes `go`, then the sort.
    EndsGo,
    EndsSort,
    /// Improved-sap: the end point at position p arrives; a min end point starts a walk.
    SapHead,
    SapWalk,
    /// Improved-sap: the next axis starts (the sort is cleared).
    NextAxis,
    Finished,
}

#[derive(LogicBlock)]
pub struct Walker<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Begin a walk over `n` boxes (keys in the key table).
    pub start: Signal<In, Bit>,
    /// The number of boxes, taken with `start`.
    pub n: Signal<In, Bits<C>>,
    /// Do not visit this clock.
    pub stall: Signal<In, Bit>,
    /// Improved-sap: the sorted end points' read port, the address read.
    pub rd_addr: Signal<Out, Bits<A>>,
    /// Improved-sap: the end point read, one clock after its address.
    pub rd_val: Signal<In, Bits<VAL>>,
    // The keys come axis by axis, not as arrays: the core holds the walker in a list, and
    // rust-hdl emits an array port of a listed block wrongly.
    /// The key table's port A: box i's address.
    pub a_addr: Signal<Out, Bits<A>>,
    /// The key table's port B: box j's address.
    pub b_addr: Signal<Out, Bits<A>>,
    /// Port A's min key on x (box i's), one clock after its address.
    pub a_min_x: Signal<In, Bits<CENTER>>,
    /// Port A's min key on y (box i's), one clock after its address.
    pub a_min_y: Signal<In, Bits<CENTER>>,
    /// Port A's min key on z (box i's), one clock after its address.
    pub a_min_z: Signal<In, Bits<CENTER>>,
    /// Port A's max key on x (box i's), one clock after its address.
    pub a_max_x: Signal<In, Bits<CENTER>>,
    /// Port A's max key on y (box i's), one clock after its address.
    pub a_max_y: Signal<In, Bits<CENTER>>,
    /// Port A's max key on z (box i's), one clock after its address.
    pub a_max_z: Signal<In, Bits<CENTER>>,
    /// Improved-sap: a sort starts.
    pub sort_start: Signal<Out, Bit>,
    /// Improved-sap: an entry for the sort is on `sort_key`, `sort_val` (one per clock).
    pub sort_valid: Signal<Out, Bit>,
    /// Improved-sap: the entry's key (the end point).
    pub sort_key: Signal<Out, Bits<KEY>>,
    /// Improved-sap: the entry's value (the box and the kind of end point).
    pub sort_val: Signal<Out, Bits<VAL>>,
    /// Improved-sap: every entry is in; the sort runs.
    pub sort_go: Signal<Out, Bit>,
    /// Improved-sap: the sort is done.
    pub sort_done: Signal<In, Bit>,
    /// A visit this clock: (i, j), keys requested on ports A and B.
    pub visit: Signal<Out, Bit>,
    /// The visit's box i.
    pub vi: Signal<Out, Bits<A>>,
    /// The visit's box j.
    pub vj: Signal<Out, Bits<A>>,
    /// The walk is over (held until the next `start`).
    pub finished: Signal<Out, Bit>,
    /// Improved-sap, or brute.
    sap: Constant<Bit>,
    state: DFF<WalkState>,
    // Improved-sap: the end point's position; box i.
    p: DFF<Bits<C>>,
    i: DFF<Bits<A>>,
    /// Next end point to read (improved-sap) or box j (brute).
    succ: DFF<Bits<C>>,
    /// Improved-sap: an end point was read last clock: it is on `rd_val`.
    pending: DFF<Bit>,
    // Improved-sap: the axis, and which end point of box `i` goes into the sort next.
    axis: DFF<Bits<2>>,
    upper: DFF<Bit>,
    last: Signal<Local, Bits<C>>,
    // Improved-sap: 2n end points; the axis's keys of box i; the box and kind of the entry read.
    ends: Signal<Local, Bits<C>>,
    key_lo: Signal<Local, Bits<CENTER>>,
    key_hi: Signal<Local, Bits<CENTER>>,
    end_box: Signal<Local, Bits<A>>,
}

/// What the walker walks.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum WalkMode {
    Brute,
    ImprovedSap,
}

impl<const A: usize, const C: usize> Walker<A, C> {
    pub fn new(mode: WalkMode) -> Walker<A, C> {
        assert!(C == A + 1, "counts need one bit more than addresses");
        Walker {
            clock: Default::default(),
            start: Default::default(),
            n: Default::default(),
            stall: Default::default(),
            rd_addr: Default::default(),
            rd_val: Default::default(),
            a_addr: Default::default(),
            b_addr: Default::default(),
            a_min_x: Default::default(),
            a_min_y: Default::default(),
            a_min_z: Default::default(),
            a_max_x: Default::default(),
            a_max_y: Default::default(),
            a_max_z: Default::default(),
            sort_start: Default::default(),
            sort_valid: Default::default(),
            sort_key: Default::default(),
            sort_val: Default::default(),
            sort_go: Default::default(),
            sort_done: Default::default(),
            visit: Default::default(),
            vi: Default::default(),
            vj: Default::default(),
            finished: Default::default(),
            sap: Constant::new(mode == WalkMode::ImprovedSap),
            state: Default::default(),
            p: Default::default(),
            i: Default::default(),
            succ: Default::default(),
            pending: Default::default(),
            axis: Default::default(),
            upper: Default::default(),
            last: Default::default(),
            ends: Default::default(),
            key_lo: Default::default(),
            key_hi: Default::default(),
            end_box: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for Walker<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, state, p, i, succ, pending, axis, upper);
        self.last.next = self.n.val() - 1;
        self.ends.next = self.n.val() << 1_u64;
        self.key_lo.next = self.a_min_x.val();
        self.key_hi.next = self.a_max_x.val();
        if self.axis.q.val() == 1 {
            self.key_lo.next = self.a_min_y.val();
            self.key_hi.next = self.a_max_y.val();
        }
        if self.axis.q.val() == 2 {
            self.key_lo.next = self.a_min_z.val();
            self.key_hi.next = self.a_max_z.val();
        }
        self.end_box.next = bit_cast::<A, VAL>(self.rd_val.val() >> 1_u64);
        self.sort_start.next = false;
        self.sort_valid.next = false;
        self.sort_go.next = false;
        self.sort_key.next = bit_cast::<KEY, CENTER>(self.key_lo.val()) << 1_u64;
        self.sort_val.next = bit_cast::<VAL, A>(self.i.q.val()) << 1_u64;
        self.finished.next = self.state.q.val() == WalkState::Finished;
        self.rd_addr.next = bit_cast::<A, C>(self.succ.q.val());
        self.a_addr.next = self.i.q.val();
        self.b_addr.next = bit_cast::<A, VAL>(self.rd_val.val());
        self.vi.next = self.i.q.val();
        self.vj.next = bit_cast::<A, VAL>(self.rd_val.val());
        self.visit.next = false;
        self.pending.d.next = false;
        match self.state.q.val() {
            WalkState::Idle => {}
            WalkState::Pairs => {
                self.b_addr.next = bit_cast::<A, C>(self.succ.q.val());
                self.vj.next = bit_cast::<A, C>(self.succ.q.val());
                if !self.stall.val() {
                    self.visit.next = true;
                    self.succ.d.next = self.succ.q.val() + 1;
                    if self.succ.q.val() == self.last.val() {
                        self.i.d.next = self.i.q.val() + 1;
                        self.succ.d.next = bit_cast::<C, A>(self.i.q.val()) + 2;
                        if bit_cast::<C, A>(self.i.q.val()) + 2 == self.n.val() {
                            self.state.d.next = WalkState::Finished;
                        }
                    }
                }
            }
            WalkState::Ends => {
                // Box i's keys were addressed last clock: its min end point, then (addressing
                // the next box) its max end point.
                self.a_addr.next = self.i.q.val();
                self.sort_valid.next = true;
                self.upper.d.next = !self.upper.q.val();
                if self.upper.q.val() {
                    self.sort_key.next =
                        (bit_cast::<KEY, CENTER>(self.key_hi.val()) << 1_u64) | 1_u64;
                    self.sort_val.next = (bit_cast::<VAL, A>(self.i.q.val()) << 1_u64) | 1_u64;
                    self.a_addr.next = self.i.q.val() + 1;
                    self.i.d.next = self.i.q.val() + 1;
                    if bit_cast::<C, A>(self.i.q.val()) == self.last.val() {
                        self.state.d.next = WalkState::EndsGo;
                    }
                }
            }
            WalkState::EndsGo => {
                self.sort_go.next = true;
                self.state.d.next = WalkState::EndsSort;
            }
            WalkState::EndsSort => {
                if self.sort_done.val() {
                    // This clock reads end point 0.
                    self.rd_addr.next = 0.into();
                    self.p.d.next = 0.into();
                    self.state.d.next = WalkState::SapHead;
                }
            }
            WalkState::SapHead => {
                // End point p: a max moves on (reading p + 1 now); a min of box i starts a
                // walk, reading p + 1 now.
                self.rd_addr.next = bit_cast::<A, C>(self.p.q.val() + 1);
                if self.rd_val.val().get_bit(0) {
                    self.p.d.next = self.p.q.val() + 1;
                    if self.p.q.val() + 1 == self.ends.val() {
                        // The axis is done: the next one starts, or the walk ends.
                        self.state.d.next = WalkState::Finished;
                        if self.axis.q.val() != 2 {
                            self.state.d.next = WalkState::NextAxis;
                        }
                    }
                } else {
                    self.i.d.next = self.end_box.val();
                    self.succ.d.next = self.p.q.val() + 2;
                    self.pending.d.next = true;
                    self.state.d.next = WalkState::SapWalk;
                }
            }
            WalkState::SapWalk => {
                // The end point read last clock: box i's own max ends the walk (and this clock
                // reads p + 1); any other box is a visit.
                self.vj.next = self.end_box.val();
                self.b_addr.next = self.end_box.val();
                if self.pending.q.val() & (self.end_box.val() == self.i.q.val()) {
                    self.rd_addr.next = bit_cast::<A, C>(self.p.q.val() + 1);
                    self.p.d.next = self.p.q.val() + 1;
                    self.state.d.next = WalkState::SapHead;
                } else {
                    if self.pending.q.val() {
                        self.visit.next = true;
                    }
                    if !self.stall.val() {
                        self.succ.d.next = self.succ.q.val() + 1;
                        self.pending.d.next = true;
                    }
                }
            }
            WalkState::NextAxis => {
                // Clears the sort and addresses box 0's keys. (This takes a clock of its own:
                // `sort_start` must not depend on the sort's outputs, or Verilator sees a
                // combinational loop through the sort's logic.)
                self.axis.d.next = self.axis.q.val() + 1;
                self.sort_start.next = true;
                self.a_addr.next = 0.into();
                self.i.d.next = 0.into();
                self.upper.d.next = false;
                self.state.d.next = WalkState::Ends;
            }
            WalkState::Finished => {}
        }
        if self.start.val() {
            self.p.d.next = 0.into();
            self.i.d.next = 0.into();
            self.succ.d.next = 1.into();
            self.state.d.next = WalkState::Finished;
            if self.n.val() > 1 {
                self.state.d.next = WalkState::Pairs;
                if self.sap.val() {
                    // The start clock clears the sort and addresses box 0's keys.
                    self.axis.d.next = 0.into();
                    self.upper.d.next = false;
                    self.sort_start.next = true;
                    self.a_addr.next = 0.into();
                    self.state.d.next = WalkState::Ends;
                }
            }
        }
    }
}
