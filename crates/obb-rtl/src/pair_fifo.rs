//! The pair FIFO between the SAT and the pair stream: 64 entries of distributed RAM and an
//! output register (first word fall-through: `valid` and `data_out` come from registers). It
//! replaces rust-hdl's `SynchronousFIFO`, whose read logic passed 5 LUT levels: here every
//! decision is on registers, so no path between registers passes more than 3 LUT levels.
//!
//! - A `write` stores `data_in` at the write pointer (the caller never writes a full FIFO: the
//!   core stalls its broad phase at `almost_full` with room for every pair in flight). Should
//!   one come with every entry stored and none leaving, `overflow` rises and stays up until
//!   `clear`: a pair was lost, and the tests assert it never happens.
//! - The output register loads the oldest stored entry when it is empty or taken this clock
//!   (`valid` and `ready` high), so a steady stream leaves one entry per clock.
//! - Beside the stored count, two registered flags say whether anything is stored and whether
//!   exactly one entry is, so that the load never waits for a compare of the pointers or the
//!   count: the flags' next values need only the count's "two" besides this clock's write and
//!   load.
//! - `write` may come late in its clock (the grid's key check decides it): the count's next
//!   value and `almost_full`'s (a register) are chosen by it among values computed from the
//!   registers alone (an AND-OR of masks: a multiplexer of sums is folded by synthesis into
//!   one adder of a selected operand, a carry chain behind the write).
//!
//! Timing: an entry written on the edge ending clock t is stored from t+1 (`empty` low) and
//! on `data_out` from t+2.

use crate::dist_ram::DistRam;
use rust_hdl::prelude::*;

/// Address bits: 64 entries.
const ADDRESS: usize = 6;
/// Count bits: 0 to 64.
const COUNT: usize = ADDRESS + 1;
/// Entries the FIFO stores besides its output register.
pub const DEPTH: u64 = 1 << ADDRESS;

#[derive(LogicBlock)]
pub struct PairFifo<const W: usize> {
    pub clock: Signal<In, Clock>,
    pub write: Signal<In, Bit>,
    pub data_in: Signal<In, Bits<W>>,
    /// The receiver takes `data_out` on a clock with `valid` and `ready` high.
    pub ready: Signal<In, Bit>,
    /// An entry is on `data_out`.
    pub valid: Signal<Out, Bit>,
    /// The oldest entry.
    pub data_out: Signal<Out, Bits<W>>,
    /// Nothing stored and nothing on the output.
    pub empty: Signal<Out, Bit>,
    /// At least `stall_at` entries stored (the output register not counted).
    pub almost_full: Signal<Out, Bit>,
    /// Pulse: `overflow` falls.
    pub clear: Signal<In, Bit>,
    /// Sticky: an entry was written with every entry stored and none leaving (it is lost).
    pub overflow: Signal<Out, Bit>,
    depth: Constant<Bits<COUNT>>,
    stall_at: Constant<Bits<COUNT>>,
    // `stall_at` less one and plus one; all ones.
    stall_lo: Constant<Bits<COUNT>>,
    stall_hi: Constant<Bits<COUNT>>,
    ones: Constant<Bits<COUNT>>,
    ram: DistRam<Bits<W>, ADDRESS>,
    wptr: DFF<Bits<ADDRESS>>,
    rptr: DFF<Bits<ADDRESS>>,
    count: DFF<Bits<COUNT>>,
    // Something is stored; exactly one entry is.
    stored: DFF<Bit>,
    one: DFF<Bit>,
    out_valid: DFF<Bit>,
    out_data: DFF<Bits<W>>,
    /// `almost_full`, registered with the count.
    full_q: DFF<Bit>,
    overflow_q: DFF<Bit>,
    load: Signal<Local, Bit>,
    two: Signal<Local, Bit>,
    // The count plus and less one; masks: it stays, rises, falls.
    count_inc: Signal<Local, Bits<COUNT>>,
    count_dec: Signal<Local, Bits<COUNT>>,
    keep_m: Signal<Local, Bits<COUNT>>,
    up_m: Signal<Local, Bits<COUNT>>,
    down_m: Signal<Local, Bits<COUNT>>,
    up: Signal<Local, Bit>,
    down: Signal<Local, Bit>,
}

impl<const W: usize> PairFifo<W> {
    /// A FIFO that is `almost_full` from `stall_at` stored entries.
    pub fn new(stall_at: u64) -> Self {
        assert!(
            (1..=DEPTH).contains(&stall_at),
            "the stall threshold is within the depth"
        );
        PairFifo {
            clock: Default::default(),
            write: Default::default(),
            data_in: Default::default(),
            ready: Default::default(),
            valid: Default::default(),
            data_out: Default::default(),
            empty: Default::default(),
            almost_full: Default::default(),
            clear: Default::default(),
            overflow: Default::default(),
            depth: Constant::new(DEPTH.into()),
            stall_at: Constant::new(stall_at.into()),
            stall_lo: Constant::new((stall_at - 1).into()),
            stall_hi: Constant::new((stall_at + 1).into()),
            ones: Constant::new(((1u64 << COUNT) - 1).into()),
            ram: Default::default(),
            wptr: Default::default(),
            rptr: Default::default(),
            count: Default::default(),
            stored: Default::default(),
            one: Default::default(),
            out_valid: Default::default(),
            out_data: Default::default(),
            full_q: Default::default(),
            overflow_q: Default::default(),
            load: Default::default(),
            two: Default::default(),
            count_inc: Default::default(),
            count_dec: Default::default(),
            keep_m: Default::default(),
            up_m: Default::default(),
            down_m: Default::default(),
            up: Default::default(),
            down: Default::default(),
        }
    }
}

impl<const W: usize> Logic for PairFifo<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, wptr, rptr, count, stored, one, out_valid, out_data, full_q, overflow_q
        );
        clock!(self, clock, ram);
        self.ram.write_enable.next = self.write.val();
        self.ram.write_address.next = self.wptr.q.val();
        self.ram.write_data.next = self.data_in.val();
        self.ram.read_address.next = self.rptr.q.val();
        self.load.next = self.stored.q.val() & (!self.out_valid.q.val() | self.ready.val());
        if self.write.val() {
            self.wptr.d.next = self.wptr.q.val() + 1;
        }
        if self.load.val() {
            self.rptr.d.next = self.rptr.q.val() + 1;
            self.out_data.d.next = self.ram.read_data.val();
            self.out_valid.d.next = true;
        } else if self.ready.val() {
            self.out_valid.d.next = false;
        }
        self.up.next = self.write.val() & !self.load.val();
        self.down.next = self.load.val() & !self.write.val();
        self.keep_m.next = 0.into();
        self.up_m.next = 0.into();
        self.down_m.next = 0.into();
        if self.up.val() {
            self.up_m.next = self.ones.val();
        } else if self.down.val() {
            self.down_m.next = self.ones.val();
        } else {
            self.keep_m.next = self.ones.val();
        }
        self.count_inc.next = self.count.q.val() + 1;
        self.count_dec.next = self.count.q.val() - 1;
        self.count.d.next = (self.count.q.val() & self.keep_m.val())
            | (self.count_inc.val() & self.up_m.val())
            | (self.count_dec.val() & self.down_m.val());
        self.full_q.d.next =
            ((self.count.q.val() >= self.stall_at.val()) & !self.up.val() & !self.down.val())
                | ((self.count.q.val() >= self.stall_lo.val()) & self.up.val())
                | ((self.count.q.val() >= self.stall_hi.val()) & self.down.val());
        // Stored after this clock: something, and exactly one entry.
        self.two.next = self.count.q.val() == 2;
        self.stored.d.next =
            self.write.val() | (self.stored.q.val() & !(self.one.q.val() & self.load.val()));
        self.one.d.next = (!self.stored.q.val() & self.write.val())
            | (self.one.q.val() & (self.write.val() == self.load.val()))
            | (self.two.val() & self.load.val() & !self.write.val());
        self.valid.next = self.out_valid.q.val();
        self.data_out.next = self.out_data.q.val();
        self.empty.next = !self.stored.q.val() & !self.out_valid.q.val();
        self.almost_full.next = self.full_q.q.val();
        if self.clear.val() {
            self.overflow_q.d.next = false;
        }
        if self.up.val() & (self.count.q.val() == self.depth.val()) {
            self.overflow_q.d.next = true;
        }
        self.overflow.next = self.overflow_q.q.val();
    }
}
