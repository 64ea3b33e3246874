//! Stable LSD radix sort of (key, value) entries in block RAM, as `obb_model::radix::RadixSorter`
//! sorts them (a stable sort has one result). Ping-pong RAMs; per pass a prefix sum over the
//! digit's bins turns the histogram into write pointers, then every entry is read and written
//! to its bin's next slot while the next digit's histogram is counted.
//!
//! Protocol: pulse `start` (clears the count and the histogram), stream the entries on
//! `in_valid`/`in_key`/`in_val` one per clock (the first digit's histogram is counted as they
//! arrive), then pulse `go`. `done` rises when the entries are sorted; `rd_addr` then reads
//! entry i of the result (`rd_key`, `rd_val`) one clock later.
//!
//! Cycles from `go`: per pass `2^d` (the prefix sum) plus `n + 1` (reads, with the write of
//! each entry one clock behind its read): the model's `n + 2^d + LAT_SORT_PASS`.

use obb_model::radix::RadixSorter;
use rust_hdl::prelude::*;

/// Key bits of the core's sorts (sweep keys, or improved-sap's end point keys of up to 24
/// bits). The sort itself takes any key width K (the grid's cell keys take up to 63 bits).
pub const KEY: usize = 24;
/// Value bits (box indices).
pub const VAL: usize = 20;
/// Entry bits of the core's sorts: key above value.
pub const ENTRY: usize = KEY + VAL;
/// Digit bits at most: the histogram and the pointers are registers, one per bin.
pub const MAX_DIGIT: u32 = 8;
const BINS: usize = 1 << MAX_DIGIT;
/// Address bits at least: the counters (one bit wider) also step through the bins.
pub const MIN_ADDRESS: usize = MAX_DIGIT as usize;

/// The core's sort: 24-bit keys.
pub type KeySort<const A: usize, const C: usize> = RadixSort<A, C, KEY, ENTRY>;

#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum Phase {
    Load,
    Prefix,
    Scatter,
    Finished,
}

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
    digit: Constant<Bits<8>>,
    mask: Constant<Bits<K>>,
    last_bin: Constant<Bits<C>>,
    passes: Constant<Bits<8>>,
    bins: [Constant<Bits<K>>; BINS],
    binc: [Constant<Bits<C>>; BINS],
    // State.
    phase: DFF<Phase>,
    ram: [RAM<Bits<E>, A>; 2],
    /// RAM the current pass reads (0 or 1); the other is written.
    src: DFF<Bit>,
    count: DFF<Bits<C>>,
    pass: DFF<Bits<8>>,
    shift: DFF<Bits<8>>,
    idx: DFF<Bits<C>>,
    sum: DFF<Bits<C>>,
    hist: [DFF<Bits<C>>; BINS],
    ptr: [DFF<Bits<C>>; BINS],
    /// The entry read last clock is being written (scatter).
    busy: DFF<Bit>,
    // Combinational.
    entry: Signal<Local, Bits<E>>,
    key: Signal<Local, Bits<K>>,
    dig: Signal<Local, Bits<K>>,
    next_dig: Signal<Local, Bits<K>>,
    in_dig: Signal<Local, Bits<K>>,
    waddr: Signal<Local, Bits<C>>,
    new_entry: Signal<Local, Bits<E>>,
    scatter: Signal<Local, Bit>,
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
            digit: Constant::new(u64::from(d).into()),
            mask: Constant::new(((1u64 << d) - 1).into()),
            last_bin: Constant::new(((1u64 << d) - 1).into()),
            passes: Constant::new(u64::from(model.passes(key_bits)).into()),
            bins: std::array::from_fn(|b| Constant::new((b as u64).into())),
            binc: std::array::from_fn(|b| Constant::new((b as u64).into())),
            phase: Default::default(),
            ram: Default::default(),
            src: Default::default(),
            count: Default::default(),
            pass: Default::default(),
            shift: Default::default(),
            idx: Default::default(),
            sum: Default::default(),
            hist: std::array::from_fn(|_| Default::default()),
            ptr: std::array::from_fn(|_| Default::default()),
            busy: Default::default(),
            entry: Default::default(),
            key: Default::default(),
            dig: Default::default(),
            next_dig: Default::default(),
            in_dig: Default::default(),
            waddr: Default::default(),
            new_entry: Default::default(),
            scatter: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize, const K: usize, const E: usize> Logic
    for RadixSort<A, C, K, E>
{
    #[hdl_gen]
    fn update(&mut self) {
        // Clocks; every register holds unless told otherwise.
        dff_setup!(self, clock, phase, src, count, pass, shift, idx, sum, busy);
        for b in 0..256 {
            self.hist[b].clock.next = self.clock.val();
            self.hist[b].d.next = self.hist[b].q.val();
            self.ptr[b].clock.next = self.clock.val();
            self.ptr[b].d.next = self.ptr[b].q.val();
        }
        // The entry read last clock, its digit for this pass and for the next.
        self.entry.next = self.ram[0].read_data.val();
        if self.src.q.val() {
            self.entry.next = self.ram[1].read_data.val();
        }
        // The key sits above the value (VAL = 20 bits; rust-hdl writes a named constant here
        // into the Verilog as a name, so the literal is spelled out).
        self.key.next = self.entry.val().get_bits::<K>(20);
        self.dig.next = (self.key.val() >> self.shift.q.val()) & self.mask.val();
        self.next_dig.next =
            (self.key.val() >> (self.shift.q.val() + self.digit.val())) & self.mask.val();
        self.in_dig.next = self.in_key.val() & self.mask.val();
        self.new_entry.next =
            (bit_cast::<E, K>(self.in_key.val()) << 20_u64) | bit_cast::<E, VAL>(self.in_val.val());
        // Reads: the result in the source RAM by `rd_addr`, or the pass's next entry.
        self.ram[0].read_address.next = self.rd_addr.val();
        self.ram[1].read_address.next = self.rd_addr.val();
        self.rd_key.next = self.key.val();
        self.rd_val.next = self.entry.val().get_bits::<VAL>(0);
        self.done.next = self.phase.q.val() == Phase::Finished;
        self.scatter.next = (self.phase.q.val() == Phase::Scatter) & self.busy.q.val();
        // The write pointer of the entry's bin.
        self.waddr.next = 0.into();
        for b in 0..256 {
            if self.dig.val() == self.bins[b].val() {
                self.waddr.next = self.ptr[b].q.val();
            }
        }
        // Each value above is computed before it is used (rust-hdl rejects, as a logic loop,
        // a local read before it is written in the same update).
        for i in 0..2 {
            self.ram[i].read_clock.next = self.clock.val();
            self.ram[i].write_clock.next = self.clock.val();
            self.ram[i].write_enable.next = false;
            self.ram[i].write_address.next = bit_cast::<A, C>(self.waddr.val());
            self.ram[i].write_data.next = self.entry.val();
        }
        match self.phase.q.val() {
            Phase::Load => {
                self.ram[0].write_address.next = bit_cast::<A, C>(self.count.q.val());
                self.ram[0].write_data.next = self.new_entry.val();
                if self.in_valid.val() {
                    self.ram[0].write_enable.next = true;
                    self.count.d.next = self.count.q.val() + 1;
                    for b in 0..256 {
                        if self.in_dig.val() == self.bins[b].val() {
                            self.hist[b].d.next = self.hist[b].q.val() + 1;
                        }
                    }
                }
                if self.go.val() {
                    self.phase.d.next = Phase::Prefix;
                    self.idx.d.next = 0.into();
                    self.sum.d.next = 0.into();
                }
            }
            Phase::Prefix => {
                // Bin idx: its pointer is the running sum; its count restarts for the next
                // digit.
                for b in 0..256 {
                    if self.idx.q.val() == self.binc[b].val() {
                        self.ptr[b].d.next = self.sum.q.val();
                        self.hist[b].d.next = 0.into();
                        self.sum.d.next = self.sum.q.val() + self.hist[b].q.val();
                    }
                }
                self.idx.d.next = self.idx.q.val() + 1;
                if self.idx.q.val() == self.last_bin.val() {
                    self.phase.d.next = Phase::Scatter;
                    self.idx.d.next = 0.into();
                }
            }
            Phase::Scatter => {
                // Read entry idx; write the entry read last clock to its bin's next slot.
                self.ram[0].read_address.next = bit_cast::<A, C>(self.idx.q.val());
                self.ram[1].read_address.next = bit_cast::<A, C>(self.idx.q.val());
                self.busy.d.next = false;
                if self.idx.q.val() != self.count.q.val() {
                    self.idx.d.next = self.idx.q.val() + 1;
                    self.busy.d.next = true;
                }
                if self.idx.q.val() == self.count.q.val() {
                    // The last entry is written this clock: the pass ends.
                    self.pass.d.next = self.pass.q.val() + 1;
                    self.shift.d.next = self.shift.q.val() + self.digit.val();
                    self.src.d.next = !self.src.q.val();
                    self.idx.d.next = 0.into();
                    self.sum.d.next = 0.into();
                    self.phase.d.next = Phase::Prefix;
                    if self.pass.q.val() + 1 == self.passes.val() {
                        self.phase.d.next = Phase::Finished;
                    }
                }
            }
            Phase::Finished => {}
        }
        if self.scatter.val() {
            if self.src.q.val() {
                self.ram[0].write_enable.next = true;
            } else {
                self.ram[1].write_enable.next = true;
            }
            for b in 0..256 {
                if self.dig.val() == self.bins[b].val() {
                    self.ptr[b].d.next = self.ptr[b].q.val() + 1;
                }
                if self.next_dig.val() == self.bins[b].val() {
                    self.hist[b].d.next = self.hist[b].q.val() + 1;
                }
            }
        }
        if self.start.val() {
            self.phase.d.next = Phase::Load;
            self.count.d.next = 0.into();
            self.src.d.next = false;
            self.pass.d.next = 0.into();
            self.shift.d.next = 0.into();
            self.busy.d.next = false;
            for b in 0..256 {
                self.hist[b].d.next = 0.into();
            }
        }
    }
}
