//! The sweep broad phase's walker: over the entries sorted by min x key (`radix`), each outer
//! position p walks its successors q = p+1, p+2, ... while their min key is within the max x
//! key of p's box i, visiting (i, j) for each, in the order of `obb_model::fixed::broad`. It
//! drives the sorted entries' read address and the key table's (box i on port A, box j on
//! port B); the core checks each visit's keys and groups one clock later.
//!
//! Every decision is taken on registers, so no path runs from a block RAM's output through the
//! walk's control back into an address (that loop was the core's deepest path):
//!
//! - The reader issues one read per clock from a register (`raddr`), ahead of any decision.
//!   Each read carries a tag (`f_*`: a real read, the outer box's first successor, the end of
//!   the entries), and the entry is registered with it a clock after the RAM's output (`e_*`).
//! - An entry is compared with `maxk`, the outer box's max x key in a register. Within it, it
//!   is a visit (registered: `visit`, `vj`, `b_addr`). Beyond it, or the end of the entries,
//!   ends the outer position: that is registered (`stop`), and the next clock drops the three
//!   reads in flight behind it and restarts the reader at the next outer position's first
//!   successor (`nxt_pos` = p+2). (Restarting in the clock of the compare would put the
//!   compare, the decision and the address multiplexer in one clock: 5 LUT levels.)
//! - The next outer box is the current one's first successor (entry p+1), so its box is
//!   captured as it passes (`nxt_i`). On the restart it becomes `i`, which addresses port A;
//!   its max x key comes out of port A two clocks later into `maxk`, a clock before its own
//!   first successor arrives.
//! - The walk begins with a virtual outer position -1 whose only read, entry 0, ends it at
//!   once: entry 0's box becomes the first outer box like any other.
//! - Between walks the reader rests at its starting point, so `start` only sets `running`.
//!
//! Clocks (n >= 2), from the one after `start`: 4 until the virtual position restarts the
//! reader, then per outer position p < n-1 four (the read of p+1, the RAM's output, the entry
//! register, the restart) plus its visits: `4n + visits` up to the last restart, the model's
//! `broad::walk_cycles`; `finished` rises the clock after. Fewer than two boxes finish at once.
//!
//! `stall` stops the reads; the entries already read still arrive and may be visits: at most
//! [`RUN_ON`] visits after `stall` rises.

use crate::projection::CENTER;
use crate::radix::{KEY, VAL};
use rust_hdl::prelude::*;

/// Visits the walker may still make from the clock `stall` rises: the one registered already
/// and the entries of the two reads in flight.
pub const RUN_ON: u64 = 3;

#[derive(LogicBlock)]
pub struct SweepWalker<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Begin a walk over the `n` sorted entries (their keys in the key table).
    pub start: Signal<In, Bit>,
    /// The number of entries, taken with `start`.
    pub n: Signal<In, Bits<C>>,
    /// Read no further entry this clock.
    pub stall: Signal<In, Bit>,
    /// The sorted entries' read port: the address read.
    pub rd_addr: Signal<Out, Bits<A>>,
    /// The entry's min x key, one clock after its address.
    pub rd_key: Signal<In, Bits<KEY>>,
    /// The entry's box, one clock after its address.
    pub rd_val: Signal<In, Bits<VAL>>,
    /// The key table's port A: box i's address.
    pub a_addr: Signal<Out, Bits<A>>,
    /// The key table's port B: box j's address.
    pub b_addr: Signal<Out, Bits<A>>,
    /// Port A's max x key (box i's), one clock after its address.
    pub a_max: Signal<In, Bits<CENTER>>,
    /// A visit this clock: (i, j), keys requested on ports A and B.
    pub visit: Signal<Out, Bit>,
    /// The visit's box i (the outer box).
    pub vi: Signal<Out, Bits<A>>,
    /// The visit's box j.
    pub vj: Signal<Out, Bits<A>>,
    /// The walk is over (held until the next `start`).
    pub finished: Signal<Out, Bit>,
    // A walk is on; it is over (held until the next `start`).
    running: DFF<Bit>,
    finished_q: DFF<Bit>,
    // The next read's address, and whether it is the outer box's first successor.
    raddr: DFF<Bits<C>>,
    rfirst: DFF<Bit>,
    // The read issued last clock (its entry is on `rd_key`, `rd_val`): a real one, the first
    // successor, at the end of the entries.
    f_valid: DFF<Bit>,
    f_first: DFF<Bit>,
    f_end: DFF<Bit>,
    // The entry read two clocks ago, registered, with its tag.
    e_valid: DFF<Bit>,
    e_first: DFF<Bit>,
    e_end: DFF<Bit>,
    e_key: DFF<Bits<KEY>>,
    e_val: DFF<Bits<A>>,
    /// Last clock's entry ended the outer position: this clock restarts the reader.
    stop: DFF<Bit>,
    /// The virtual outer position -1 is over: `maxk` holds a real box's key.
    primed: DFF<Bit>,
    // The outer box and its max x key; the next outer box.
    i: DFF<Bits<A>>,
    maxk: DFF<Bits<KEY>>,
    nxt_i: DFF<Bits<A>>,
    // The next outer position's first successor (p+2); `n - 1`; the outer position is the
    // last one (p = n-2).
    nxt_pos: DFF<Bits<C>>,
    n_last: DFF<Bits<C>>,
    last_outer: DFF<Bit>,
    // A restart one and two clocks ago: the new box's max x key is on port A at the second.
    load1: DFF<Bit>,
    load2: DFF<Bit>,
    visit_q: DFF<Bit>,
    vj_q: DFF<Bits<A>>,
    beyond: Signal<Local, Bit>,
}

impl<const A: usize, const C: usize> Default for SweepWalker<A, C> {
    fn default() -> Self {
        assert!(C == A + 1, "counts need one bit more than addresses");
        SweepWalker {
            clock: Default::default(),
            start: Default::default(),
            n: Default::default(),
            stall: Default::default(),
            rd_addr: Default::default(),
            rd_key: Default::default(),
            rd_val: Default::default(),
            a_addr: Default::default(),
            b_addr: Default::default(),
            a_max: Default::default(),
            visit: Default::default(),
            vi: Default::default(),
            vj: Default::default(),
            finished: Default::default(),
            running: Default::default(),
            finished_q: Default::default(),
            raddr: Default::default(),
            rfirst: Default::default(),
            f_valid: Default::default(),
            f_first: Default::default(),
            f_end: Default::default(),
            e_valid: Default::default(),
            e_first: Default::default(),
            e_end: Default::default(),
            e_key: Default::default(),
            e_val: Default::default(),
            stop: Default::default(),
            primed: Default::default(),
            i: Default::default(),
            maxk: Default::default(),
            nxt_i: Default::default(),
            nxt_pos: Default::default(),
            n_last: Default::default(),
            last_outer: Default::default(),
            load1: Default::default(),
            load2: Default::default(),
            visit_q: Default::default(),
            vj_q: Default::default(),
            beyond: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for SweepWalker<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, running, finished_q, raddr, rfirst, f_valid, f_first, f_end, e_valid,
            e_first, e_end, e_key, e_val, stop, primed, i, maxk, nxt_i, nxt_pos, n_last,
            last_outer, load1, load2, visit_q, vj_q
        );
        self.rd_addr.next = bit_cast::<A, C>(self.raddr.q.val());
        self.a_addr.next = self.i.q.val();
        self.vi.next = self.i.q.val();
        self.b_addr.next = self.vj_q.q.val();
        self.vj.next = self.vj_q.q.val();
        self.visit.next = self.visit_q.q.val();
        self.finished.next = self.finished_q.q.val();
        self.n_last.d.next = self.n.val() - 1;

        // The entry read last clock, registered with its tag (dropped behind a stop).
        self.e_valid.d.next = self.f_valid.q.val() & !self.stop.q.val();
        self.e_first.d.next = self.f_first.q.val();
        self.e_end.d.next = self.f_end.q.val();
        self.e_key.d.next = self.rd_key.val();
        self.e_val.d.next = bit_cast::<A, VAL>(self.rd_val.val());

        // The registered entry: a visit, or the end of the outer position. The entry behind a
        // stop is neither.
        self.beyond.next = self.e_key.q.val() > self.maxk.q.val();
        self.stop.d.next = self.e_valid.q.val()
            & !self.stop.q.val()
            & (self.e_end.q.val() | !self.primed.q.val() | self.beyond.val());
        self.visit_q.d.next = self.e_valid.q.val()
            & !self.stop.q.val()
            & self.primed.q.val()
            & !self.e_end.q.val()
            & !self.beyond.val();
        self.vj_q.d.next = self.e_val.q.val();
        if self.e_valid.q.val() & self.e_first.q.val() {
            self.nxt_i.d.next = self.e_val.q.val();
        }

        // The new outer box's max x key arrives on port A two clocks after the restart.
        self.load1.d.next = self.stop.q.val();
        self.load2.d.next = self.load1.q.val();
        if self.load2.q.val() {
            self.maxk.d.next = bit_cast::<KEY, CENTER>(self.a_max.val());
        }

        // The reader: one entry per clock, unless stalled or restarting.
        self.f_valid.d.next = self.running.q.val() & !self.stall.val() & !self.stop.q.val();
        self.f_first.d.next = self.rfirst.q.val();
        self.f_end.d.next = self.raddr.q.val() == self.n.val();
        if self.f_valid.d.val() {
            self.raddr.d.next = self.raddr.q.val() + 1;
            self.rfirst.d.next = false;
        }
        if self.stop.q.val() {
            if self.last_outer.q.val() {
                self.running.d.next = false;
                self.finished_q.d.next = true;
            } else {
                self.raddr.d.next = self.nxt_pos.q.val();
                self.rfirst.d.next = true;
                self.nxt_pos.d.next = self.nxt_pos.q.val() + 1;
                self.last_outer.d.next = self.nxt_pos.q.val() == self.n_last.q.val();
                self.primed.d.next = true;
                self.i.d.next = self.nxt_i.q.val();
            }
        }
        // Between walks the reader rests at its start: entry 0, the virtual outer position.
        if !self.running.q.val() {
            self.raddr.d.next = 0.into();
            self.rfirst.d.next = true;
            self.primed.d.next = false;
            self.nxt_pos.d.next = 1.into();
            self.last_outer.d.next = false;
        }

        if self.start.val() {
            self.running.d.next = self.n.val() > 1;
            self.finished_q.d.next = self.n.val() <= 1;
        }
    }
}
