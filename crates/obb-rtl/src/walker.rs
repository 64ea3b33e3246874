//! The broad phase's walker: it visits index pairs (i, j), at most one per clock, in the order
//! of `obb_model::fixed::broad` for `brute` and `sweep`. It drives the read addresses of the
//! sorted entries (sweep) and of the key table (box i on port A, box j on port B); the core
//! checks each visit's keys and groups one clock later.
//!
//! - `brute`: i = 0, 1, ...; j = i+1, ..., n-1; one visit per clock, no overhead.
//! - `sweep` over the entries sorted by min x key (`radix`): per outer position p, one clock
//!   reads entry p (its box i) while the key table is addressed for i's max x key, then each
//!   clock reads the next entry q = p+1, p+2, ...; a read whose key is within i's max is a
//!   visit, one beyond it (seen the clock after its read) or the end of the entries ends p.
//!   Outer p costs 2 + its reads (visits plus the one read beyond), one clock more starts the
//!   walk: `obb_model::fixed::cycles` counts the same.
//!
//! `stall` holds back visits (the output is filling); it never drops one.

use crate::projection::CENTER;
use crate::radix::{KEY, VAL};
use rust_hdl::prelude::*;

#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum WalkState {
    Idle,
    /// Sweep: the entry of outer position p is on the sorted entries' read port.
    Head,
    /// Sweep: the walk over the successors of p.
    Walk,
    /// Brute: the pairs (i, j).
    Pairs,
    Finished,
}

#[derive(LogicBlock)]
pub struct Walker<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Begin a walk over `n` boxes (keys in the key table; sweep: entries sorted).
    pub start: Signal<In, Bit>,
    pub n: Signal<In, Bits<C>>,
    /// Do not visit this clock.
    pub stall: Signal<In, Bit>,
    /// Sweep: the sorted entries' read port (address out, key and box one clock later).
    pub rd_addr: Signal<Out, Bits<A>>,
    pub rd_key: Signal<In, Bits<KEY>>,
    pub rd_val: Signal<In, Bits<VAL>>,
    /// The key table: port A reads box i, port B box j; `a_max_x` is port A's max x key.
    pub a_addr: Signal<Out, Bits<A>>,
    pub b_addr: Signal<Out, Bits<A>>,
    pub a_max_x: Signal<In, Bits<CENTER>>,
    /// A visit this clock: (i, j), keys requested on ports A and B.
    pub visit: Signal<Out, Bit>,
    pub vi: Signal<Out, Bits<A>>,
    pub vj: Signal<Out, Bits<A>>,
    pub finished: Signal<Out, Bit>,
    /// Sweep (true) or brute (false).
    sweep: Constant<Bit>,
    state: DFF<WalkState>,
    /// Outer position (sweep) or box i (brute), and its box (sweep).
    p: DFF<Bits<C>>,
    i: DFF<Bits<A>>,
    /// Next successor to read (sweep) or box j (brute).
    succ: DFF<Bits<C>>,
    /// A successor was read last clock: its key and box are on `rd_key`, `rd_val`.
    pending: DFF<Bit>,
    last: Signal<Local, Bits<C>>,
    beyond: Signal<Local, Bit>,
    move_on: Signal<Local, Bit>,
}

impl<const A: usize, const C: usize> Walker<A, C> {
    pub fn new(sweep: bool) -> Walker<A, C> {
        assert!(C == A + 1, "counts need one bit more than addresses");
        Walker {
            clock: Default::default(),
            start: Default::default(),
            n: Default::default(),
            stall: Default::default(),
            rd_addr: Default::default(),
            rd_key: Default::default(),
            rd_val: Default::default(),
            a_addr: Default::default(),
            b_addr: Default::default(),
            a_max_x: Default::default(),
            visit: Default::default(),
            vi: Default::default(),
            vj: Default::default(),
            finished: Default::default(),
            sweep: Constant::new(sweep),
            state: Default::default(),
            p: Default::default(),
            i: Default::default(),
            succ: Default::default(),
            pending: Default::default(),
            last: Default::default(),
            beyond: Default::default(),
            move_on: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for Walker<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, state, p, i, succ, pending);
        self.last.next = self.n.val() - 1;
        // Sweep: the successor read last clock starts beyond box i's max x key.
        self.beyond.next = self.rd_key.val() > bit_cast::<KEY, CENTER>(self.a_max_x.val());
        self.move_on.next =
            (self.pending.q.val() & self.beyond.val()) | (self.succ.q.val() == self.n.val());
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
            WalkState::Head => {
                // Entry p arrives: it is box i, and the key table reads i's keys for the walk.
                self.i.d.next = bit_cast::<A, VAL>(self.rd_val.val());
                self.a_addr.next = bit_cast::<A, VAL>(self.rd_val.val());
                self.succ.d.next = self.p.q.val() + 1;
                self.state.d.next = WalkState::Walk;
            }
            WalkState::Walk => {
                // The successor read last clock is a visit unless it starts beyond i.
                if self.pending.q.val() & !self.beyond.val() {
                    self.visit.next = true;
                }
                if self.move_on.val() {
                    // This clock reads the next outer position's entry.
                    self.rd_addr.next = bit_cast::<A, C>(self.p.q.val() + 1);
                    self.p.d.next = self.p.q.val() + 1;
                    self.state.d.next = WalkState::Head;
                    if self.p.q.val() + 1 == self.last.val() {
                        self.state.d.next = WalkState::Finished;
                    }
                } else if !self.stall.val() {
                    self.succ.d.next = self.succ.q.val() + 1;
                    self.pending.d.next = true;
                }
            }
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
            WalkState::Finished => {}
        }
        if self.start.val() {
            self.p.d.next = 0.into();
            self.i.d.next = 0.into();
            self.succ.d.next = 1.into();
            self.state.d.next = WalkState::Finished;
            if self.n.val() > 1 {
                self.state.d.next = WalkState::Pairs;
                if self.sweep.val() {
                    // The start clock reads entry 0.
                    self.rd_addr.next = 0.into();
                    self.state.d.next = WalkState::Head;
                }
            }
        }
    }
}
