//! Stable LSD radix sort of (key, value) entries in block RAM, as `obb_model::radix::RadixSorter`
//! sorts them (a stable sort has one result). Ping-pong RAMs; per pass a prefix sum over the
//! digit's bins turns the histogram into write pointers, then every entry is read and written
//! to its bin's next slot while the next digit's histogram is counted. The bins are a
//! [`BinTable`]; every path between registers here passes at most 3 LUT levels: the entries and
//! digits move through registered stages, and every end-of-loop test is a flag registered one
//! clock ahead.
//!
//! Protocol: pulse `start` (clears the count and the histogram, and drops whatever is in
//! flight: a frame may end a sort early), stream the entries on `in_valid`/`in_key`/`in_val` one
//! per clock (the first digit's histogram is counted as they arrive), then pulse `go`, at the
//! earliest with the last entry. `done` rises when the entries are sorted; `rd_addr` then reads
//! entry i of the result (`rd_key`, `rd_val`) one clock later.
//!
//! Clocks from `go` to `done`: [`START`] (the last entries' counts settle), then per pass `2^d`
//! (the prefix sum) plus `n` reads plus [`PASS`] (the last entry's way through the scatter
//! pipeline to its write): the model's `sort_cycles`. The scatter pipeline, by the clock after
//! an entry's read: 1 the RAM's output, 2 the entry registered, 3 its digits registered (the
//! bin table's inputs), 6 its write pointer (`TAKE_LATENCY` later), written that clock.

use crate::bin_table::{BinTable, COUNT_LATENCY, TAKE_LATENCY};
use obb_model::radix::RadixSorter;
use rust_hdl::prelude::*;

/// Key bits of the core's sorts (sweep keys, or improved-sap's end point keys of up to 24
/// bits). The sort itself takes any key width K (the grid's cell keys take up to 63 bits).
pub const KEY: usize = 24;
/// Value bits (box indices).
pub const VAL: usize = 20;
/// Entry bits of the core's sorts: key above value.
pub const ENTRY: usize = KEY + VAL;
/// Digit bits at most (256 bins).
pub const MAX_DIGIT: u32 = 8;
/// Passes at most: 63-bit keys in 8-bit digits.
const MAX_PASSES: usize = 8;
/// Address bits at least: the counters (one bit wider) also step through the bins.
pub const MIN_ADDRESS: usize = MAX_DIGIT as usize;
/// Clocks from an entry's read to its write, the clock of the write included.
const SCATTER_DEPTH: u64 = 3 + TAKE_LATENCY;
/// Clocks of a pass besides its prefix sum and its reads (`cycles::LAT_SORT_PASS`).
pub const PASS: u64 = SCATTER_DEPTH;
/// Clocks from `go` to the first prefix step: `go`, and the last entry's count, which may
/// arrive with `go` (`cycles::LAT_SORT_START`).
pub const START: u64 = 1 + COUNT_LATENCY;
const _: () = assert!(
    PASS == 6 && START == 3,
    "the drain and settle counters' last values"
);

/// The core's sort: 24-bit keys.
pub type KeySort<const A: usize, const C: usize> = RadixSort<A, C, KEY, ENTRY>;

#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum Phase {
    Load,
    /// The last entries' counts reach the histogram.
    Settle,
    Prefix,
    Scatter,
    Finished,
}

/// Scatter stages after the entry register: the entry waits for its write pointer.
const STAGES: usize = 5;
// The update's loops spell these bounds out as literals (`for k in 0..5`, `for p in 0..8`), as
// the crate's other blocks do; this ties them to the constants.
const _: () = assert!(STAGES == 5 && MAX_PASSES == 8 && STAGES as u64 == SCATTER_DEPTH - 1);

#[derive(LogicBlock)]
pub struct RadixSort<const A: usize, const C: usize, const K: usize, const E: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub in_valid: Signal<In, Bit>,
    pub in_key: Signal<In, Bits<K>>,
    pub in_val: Signal<In, Bits<VAL>>,
    pub go: Signal<In, Bit>,
    pub done: Signal<Out, Bit>,
    pub rd_addr: Signal<In, Bits<A>>,
    pub rd_key: Signal<Out, Bits<K>>,
    pub rd_val: Signal<Out, Bits<VAL>>,
    // Configuration.
    mask: Constant<Bits<8>>,
    last_bin: Constant<Bits<C>>,
    // One pass only; else the pass before the last (mod 8).
    one_pass: Constant<Bit>,
    penultimate: Constant<Bits<3>>,
    /// Pass p's digit starts at entry bit `offsets[p]`.
    offsets: [Constant<Bits<8>>; MAX_PASSES + 1],
    passc: [Constant<Bits<3>>; MAX_PASSES],
    // State.
    phase: DFF<Phase>,
    ram: [RAM<Bits<E>, A>; 2],
    bin_table: BinTable<C>,
    // RAM the current pass reads (0 or 1); the other is written.
    src: DFF<Bit>,
    count: DFF<Bits<C>>,
    /// From the count, for the scatter's end test one clock ahead: `count - 2`, `count == 1`,
    /// `count != 0`.
    second_last: DFF<Bits<C>>,
    single: DFF<Bit>,
    nonempty: DFF<Bit>,
    pass: DFF<Bits<3>>,
    final_pass: DFF<Bit>,
    /// The prefix step, or the scatter's read address.
    idx: DFF<Bits<C>>,
    reading: DFF<Bit>,
    last_read: DFF<Bit>,
    /// Clocks of the settle and of the scatter's drain.
    ticks: DFF<Bits<3>>,
    /// The loaded entry, written the next clock.
    l_valid: DFF<Bit>,
    l_entry: DFF<Bits<E>>,
    /// The RAM's output holds an entry of the pass.
    r_valid: DFF<Bit>,
    // The entry (from the RAM's output) and its way to the write.
    e: [DFF<Bits<E>>; STAGES],
    v: [DFF<Bit>; STAGES],
    // The bin table's inputs: this pass's digit (take) and the next pass's (count).
    t_valid: DFF<Bit>,
    t_bin: DFF<Bits<8>>,
    c_valid: DFF<Bit>,
    c_bin: DFF<Bits<8>>,
    // Combinational.
    entry: Signal<Local, Bits<E>>,
    this_digit: Signal<Local, Bits<E>>,
    next_digit: Signal<Local, Bits<E>>,
    new_entry: Signal<Local, Bits<E>>,
}

impl<const A: usize, const C: usize, const K: usize, const E: usize> RadixSort<A, C, K, E> {
    /// The sorter for `key_bits`-bit keys with digits of at most `max_digit_bits`, split evenly
    /// as `RadixSorter` splits them.
    pub fn new(key_bits: u32, max_digit_bits: u32) -> RadixSort<A, C, K, E> {
        assert!(C == A + 1, "counts need one bit more than addresses");
        assert!(A >= MIN_ADDRESS, "the counters must hold every bin");
        assert!(E == K + VAL, "an entry is a key above a value");
        assert_eq!(VAL, 20, "the update's literal offsets assume 20-bit values");
        assert!(key_bits as usize <= K && K < 64 && max_digit_bits <= MAX_DIGIT);
        let model = RadixSorter::<u32>::new(max_digit_bits);
        let d = model.digit_bits(key_bits);
        let passes = model.passes(key_bits);
        assert!((1..=MAX_PASSES as u32).contains(&passes));
        RadixSort {
            clock: Default::default(),
            start: Default::default(),
            in_valid: Default::default(),
            in_key: Default::default(),
            in_val: Default::default(),
            go: Default::default(),
            done: Default::default(),
            rd_addr: Default::default(),
            rd_key: Default::default(),
            rd_val: Default::default(),
            mask: Constant::new(((1u64 << d) - 1).into()),
            last_bin: Constant::new(((1u64 << d) - 1).into()),
            one_pass: Constant::new(passes == 1),
            penultimate: Constant::new(u64::from((passes + 6) % 8).into()),
            offsets: std::array::from_fn(|p| {
                Constant::new((VAL as u64 + p as u64 * u64::from(d)).into())
            }),
            passc: std::array::from_fn(|p| Constant::new((p as u64).into())),
            phase: Default::default(),
            ram: Default::default(),
            bin_table: BinTable::new(d),
            src: Default::default(),
            count: Default::default(),
            second_last: Default::default(),
            single: Default::default(),
            nonempty: Default::default(),
            pass: Default::default(),
            final_pass: Default::default(),
            idx: Default::default(),
            reading: Default::default(),
            last_read: Default::default(),
            ticks: Default::default(),
            l_valid: Default::default(),
            l_entry: Default::default(),
            r_valid: Default::default(),
            e: Default::default(),
            v: Default::default(),
            t_valid: Default::default(),
            t_bin: Default::default(),
            c_valid: Default::default(),
            c_bin: Default::default(),
            entry: Default::default(),
            this_digit: Default::default(),
            next_digit: Default::default(),
            new_entry: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize, const K: usize, const E: usize> Logic
    for RadixSort<A, C, K, E>
{
    #[hdl_gen]
    fn update(&mut self) {
        // Clocks; every register holds unless told otherwise.
        dff_setup!(
            self,
            clock,
            phase,
            src,
            count,
            second_last,
            single,
            nonempty,
            pass,
            final_pass,
            idx,
            reading,
            last_read,
            ticks,
            l_valid,
            l_entry,
            r_valid,
            t_valid,
            t_bin,
            c_valid,
            c_bin
        );
        self.bin_table.clock.next = self.clock.val();
        // The RAM's output (the pass's source), registered; then its way to the write.
        self.entry.next = self.ram[0].read_data.val();
        if self.src.q.val() {
            self.entry.next = self.ram[1].read_data.val();
        }
        for k in 0..5 {
            self.e[k].clock.next = self.clock.val();
            self.v[k].clock.next = self.clock.val();
        }
        self.e[0].d.next = self.entry.val();
        self.v[0].d.next = self.r_valid.q.val();
        for k in 1..5 {
            self.e[k].d.next = self.e[k - 1].q.val();
            self.v[k].d.next = self.v[k - 1].q.val();
        }
        self.r_valid.d.next = self.reading.q.val();
        // The key sits above the value (VAL = 20 bits; rust-hdl writes a named constant here
        // into the Verilog as a name, so the literal is spelled out).
        self.rd_key.next = self.entry.val().get_bits::<K>(20);
        self.rd_val.next = self.entry.val().get_bits::<VAL>(0);
        self.done.next = self.phase.q.val() == Phase::Finished;
        // The registered entry's digit for this pass and for the next: a multiplexer by the
        // pass over fixed slices, not a shifter.
        self.this_digit.next = 0.into();
        self.next_digit.next = 0.into();
        for p in 0..8 {
            if self.pass.q.val() == self.passc[p].val() {
                self.this_digit.next = self.e[0].q.val() >> self.offsets[p].val();
                self.next_digit.next = self.e[0].q.val() >> self.offsets[p + 1].val();
            }
        }
        self.t_valid.d.next = self.v[0].q.val();
        self.t_bin.d.next = self.this_digit.val().get_bits::<8>(0) & self.mask.val();
        self.c_valid.d.next = self.v[0].q.val() & !self.final_pass.q.val();
        self.c_bin.d.next = self.next_digit.val().get_bits::<8>(0) & self.mask.val();
        // Loads: registered, written the next clock; the first digit is counted.
        self.new_entry.next =
            (bit_cast::<E, K>(self.in_key.val()) << 20_u64) | bit_cast::<E, VAL>(self.in_val.val());
        self.l_entry.d.next = self.new_entry.val();
        self.l_valid.d.next = self.in_valid.val() & (self.phase.q.val() == Phase::Load);
        if self.phase.q.val() == Phase::Load {
            self.c_valid.d.next = self.in_valid.val();
            self.c_bin.d.next = self.in_key.val().get_bits::<8>(0) & self.mask.val();
        }
        self.bin_table.clear.next = self.start.val();
        self.bin_table.count_valid.next = self.c_valid.q.val();
        self.bin_table.count_bin.next = self.c_bin.q.val();
        self.bin_table.take_valid.next = self.t_valid.q.val();
        self.bin_table.take_bin.next = self.t_bin.q.val();
        self.bin_table.step.next = self.phase.q.val() == Phase::Prefix;
        // Reads: the result in the source RAM by `rd_addr`, or the pass's next entry. Writes:
        // a loaded entry to RAM 0, or an entry to its bin's next slot in the other RAM.
        for i in 0..2 {
            self.ram[i].read_clock.next = self.clock.val();
            self.ram[i].write_clock.next = self.clock.val();
            self.ram[i].read_address.next = self.rd_addr.val();
            if self.phase.q.val() == Phase::Scatter {
                self.ram[i].read_address.next = bit_cast::<A, C>(self.idx.q.val());
            }
            self.ram[i].write_enable.next = false;
            self.ram[i].write_address.next = bit_cast::<A, C>(self.bin_table.take_ptr.val());
            self.ram[i].write_data.next = self.e[4].q.val();
        }
        if self.v[4].q.val() {
            if self.src.q.val() {
                self.ram[0].write_enable.next = true;
            } else {
                self.ram[1].write_enable.next = true;
            }
        }
        if self.l_valid.q.val() {
            self.ram[0].write_enable.next = true;
            self.ram[0].write_address.next = bit_cast::<A, C>(self.count.q.val());
            self.ram[0].write_data.next = self.l_entry.q.val();
            self.count.d.next = self.count.q.val() + 1;
        }
        match self.phase.q.val() {
            Phase::Load => {
                if self.go.val() {
                    self.phase.d.next = Phase::Settle;
                    self.ticks.d.next = 0.into();
                }
            }
            Phase::Settle => {
                // The count is final by the second clock (the last load is written the clock
                // after it arrives): what the scatter's end test needs.
                self.ticks.d.next = self.ticks.q.val() + 1;
                if self.ticks.q.val() == 1 {
                    self.phase.d.next = Phase::Prefix;
                    self.idx.d.next = 0.into();
                    self.second_last.d.next = self.count.q.val() - 2;
                    self.single.d.next = self.count.q.val() == 1;
                    self.nonempty.d.next = self.count.q.val() != 0;
                    self.final_pass.d.next = self.one_pass.val();
                }
            }
            Phase::Prefix => {
                self.idx.d.next = self.idx.q.val() + 1;
                if self.idx.q.val() == self.last_bin.val() {
                    self.phase.d.next = Phase::Scatter;
                    self.idx.d.next = 0.into();
                    self.reading.d.next = self.nonempty.q.val();
                    self.last_read.d.next = self.single.q.val();
                    self.ticks.d.next = 0.into();
                }
            }
            Phase::Scatter => {
                if self.reading.q.val() {
                    // Read entry idx; whether the next read is the last one, a clock ahead.
                    self.idx.d.next = self.idx.q.val() + 1;
                    self.last_read.d.next = self.idx.q.val() == self.second_last.q.val();
                    if self.last_read.q.val() {
                        self.reading.d.next = false;
                    }
                } else {
                    // The last entries' way to their writes; the last is written on the sixth
                    // clock, and the pass ends.
                    self.ticks.d.next = self.ticks.q.val() + 1;
                    if self.ticks.q.val() == 5 {
                        self.pass.d.next = self.pass.q.val() + 1;
                        self.src.d.next = !self.src.q.val();
                        self.final_pass.d.next = self.pass.q.val() == self.penultimate.val();
                        self.idx.d.next = 0.into();
                        self.phase.d.next = Phase::Prefix;
                        if self.final_pass.q.val() {
                            self.phase.d.next = Phase::Finished;
                        }
                    }
                }
            }
            Phase::Finished => {}
        }
        if self.start.val() {
            self.phase.d.next = Phase::Load;
            self.count.d.next = 0.into();
            self.src.d.next = false;
            self.pass.d.next = 0.into();
            self.reading.d.next = false;
            self.l_valid.d.next = false;
            self.r_valid.d.next = false;
            self.t_valid.d.next = false;
            self.c_valid.d.next = false;
            for k in 0..5 {
                self.v[k].d.next = false;
            }
        }
    }
}
