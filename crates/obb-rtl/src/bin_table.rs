//! The radix sort's bins: per bin a count (the histogram of a digit) and a write pointer, in
//! registers, laid out so that no path passes more than 3 LUT levels. A 256-way multiplexer
//! indexed by a data-dependent digit, or a prefix sum that reads bin `idx`, is a deep tree of
//! LUTs (24 levels in the first sort); here nothing is indexed in one clock:
//!
//! - `count`: the bin's one-hot decode is registered, and the next clock each count adds its
//!   bit (two clocks from `count_valid` to the count).
//! - `step` (the prefix sum, one bin per clock for `2^d` clocks): every count moves one bin down
//!   (bin 0's into the running sum, zero into the last), and every pointer moves one bin down
//!   with the sum entering the last. After `2^d` steps pointer b is the sum of the counts of the
//!   bins below b, and the counts are zero, ready for the next digit. `sum` is zero whenever
//!   the table is not stepping.
//! - `take` (the scatter): the decode is registered, then each pointer adds its bit while a
//!   16-way multiplexer per group of 16 bins reads the pointer of the taken bin's low digit
//!   bits (registered), then a multiplexer over the groups by its high bits (registered).
//!   `take_ptr` is the bin's pointer before the take, [`TAKE_LATENCY`] clocks after it: every
//!   earlier take has added its bit by the clock the pointer is read.
//! - `clear`: zeroes the counts and drops the decodes in flight (a frame that ended early
//!   leaves nothing behind). The pointers need no clearing: the prefix sum writes every one.
//!
//! Bins beyond `2^d` do not exist. A Rust simulation model plus hand-written Verilog,
//! co-simulated in `tests/leaves.rs`; `tests/radix.rs` checks the sort built on it.

use rust_hdl::prelude::*;

/// Clocks from `take_valid` to `take_ptr`.
pub const TAKE_LATENCY: u64 = 3;
/// Clocks from `count_valid` to the count (a `step` may start this many clocks after).
pub const COUNT_LATENCY: u64 = 2;
/// Bins per group of the first read stage (one LUT6 level of 4:1 multiplexers, two of 16:1).
const GROUP_BITS: u32 = 4;

#[derive(LogicBlock)]
pub struct BinTable<const C: usize> {
    pub clock: Signal<In, Clock>,
    pub clear: Signal<In, Bit>,
    pub count_valid: Signal<In, Bit>,
    pub count_bin: Signal<In, Bits<8>>,
    pub step: Signal<In, Bit>,
    pub take_valid: Signal<In, Bit>,
    pub take_bin: Signal<In, Bits<8>>,
    pub take_ptr: Signal<Out, Bits<C>>,
    // Digit bits (the model's state follows; rust-hdl skips fields named with `_`).
    _digit: u32,
    _m: Model,
}

/// The registers of the Verilog, bit for bit.
#[derive(Clone, Debug, Default)]
struct Model {
    hist: Vec<u64>,
    ptr: Vec<u64>,
    sum: u64,
    hot_count: Option<usize>,
    hot_take: Option<usize>,
    // The taken bin's low and high bits, the groups' reads, the high bits one clock on.
    lo: usize,
    hi: usize,
    part: Vec<u64>,
    hi2: usize,
}

impl<const C: usize> BinTable<C> {
    /// The table for `digit_bits`-bit digits (1 to 8).
    pub fn new(digit_bits: u32) -> Self {
        assert!((1..=8).contains(&digit_bits), "digits of 1 to 8 bits");
        assert!(C < 64);
        let (_, hi_bits) = Self::split(digit_bits);
        BinTable {
            clock: Default::default(),
            clear: Default::default(),
            count_valid: Default::default(),
            count_bin: Default::default(),
            step: Default::default(),
            take_valid: Default::default(),
            take_bin: Default::default(),
            take_ptr: Default::default(),
            _digit: digit_bits,
            _m: Model {
                hist: vec![0; 1 << digit_bits],
                ptr: vec![0; 1 << digit_bits],
                part: vec![0; 1 << hi_bits],
                ..Default::default()
            },
        }
    }

    /// The digit's low bits (which pick a bin within a group) and its high bits (the group).
    fn split(digit_bits: u32) -> (u32, u32) {
        let lo = digit_bits.min(GROUP_BITS);
        (lo, digit_bits - lo)
    }

    fn bins(&self) -> usize {
        1 << self._digit
    }
}

impl<const C: usize> Logic for BinTable<C> {
    fn update(&mut self) {
        if !self.clock.pos_edge() {
            return;
        }
        let wrap = |x: u64| x & ((1u64 << C) - 1);
        let bins = self.bins();
        let (lo_bits, _) = Self::split(self._digit);
        let m = &mut self._m;
        let old = m.clone();
        let bin = |b: Bits<8>| b.index() & (bins - 1);
        // Read stages: the groups by the registered low bits, then the group by the high bits.
        self.take_ptr.next = old.part[old.hi2].into();
        m.hi2 = old.hi;
        for (j, p) in m.part.iter_mut().enumerate() {
            *p = old.ptr[(j << lo_bits) | old.lo];
        }
        let taken = bin(self.take_bin.val());
        m.lo = taken & ((1 << lo_bits) - 1);
        m.hi = taken >> lo_bits;
        let clear = self.clear.val();
        m.hot_count = (self.count_valid.val() & !clear).then(|| bin(self.count_bin.val()));
        m.hot_take = (self.take_valid.val() & !clear).then_some(taken);
        if self.step.val() {
            m.sum = wrap(old.sum + old.hist[0]);
            m.hist.rotate_left(1);
            m.hist[bins - 1] = 0;
            m.ptr.rotate_left(1);
            m.ptr[bins - 1] = old.sum;
        } else {
            m.sum = 0;
            if let Some(b) = old.hot_count {
                m.hist[b] = wrap(old.hist[b] + 1);
            }
            if let Some(b) = old.hot_take {
                m.ptr[b] = wrap(old.ptr[b] + 1);
            }
        }
        if clear {
            m.hist.iter_mut().for_each(|h| *h = 0);
        }
    }

    fn connect(&mut self) {
        self.take_ptr.connect();
    }

    fn hdl(&self) -> Verilog {
        let (lo, hi) = Self::split(self._digit);
        let bins = self.bins();
        // Flat vectors, not arrays, so that yosys keeps them as registers rather than inferring
        // a memory with 256 write ports. Every register starts at zero, as the model's do.
        let (hi_regs, hi_stage) = if hi == 0 {
            (String::new(), "   take_ptr <= part;\n".to_string())
        } else {
            (
                format!("reg [{h}:0] hi = 0;\nreg [{h}:0] hi2 = 0;\n", h = hi - 1),
                format!(
                    "   hi <= take_bin[{top}:{lo}];\n   hi2 <= hi;\n   \
                     take_ptr <= part[hi2*{c} +: {c}];\n",
                    top = self._digit - 1,
                    c = C
                ),
            )
        };
        Verilog::Custom(format!(
            "\
localparam BINS = {bins};
localparam W = {bins} * {c};
reg [W-1:0] hist = 0;
reg [W-1:0] ptr = 0;
reg [{c1}:0] sum = 0;
reg [BINS-1:0] hot_count = 0;
reg [BINS-1:0] hot_take = 0;
reg [{lo1}:0] lo = 0;
{hi_regs}reg [{parts}*{c}-1:0] part = 0;
integer b;
integer j;
initial take_ptr = 0;
always @(posedge clock) begin
   for (b = 0; b < BINS; b = b + 1) begin
      hot_count[b] <= count_valid && !clear && count_bin[{d1}:0] == b;
      hot_take[b] <= take_valid && !clear && take_bin[{d1}:0] == b;
   end
   lo <= take_bin[{lo1}:0];
   for (j = 0; j < {parts}; j = j + 1) begin
      part[j*{c} +: {c}] <= ptr[(j*{group} + lo)*{c} +: {c}];
   end
{hi_stage}   if (step) begin
      sum <= sum + hist[{c1}:0];
      hist <= {{{{{c}{{1'b0}}}}, hist[W-1:{c}]}};
      ptr <= {{sum, ptr[W-1:{c}]}};
   end else begin
      sum <= 0;
      for (b = 0; b < BINS; b = b + 1) begin
         hist[b*{c} +: {c}] <= hist[b*{c} +: {c}] + hot_count[b];
         ptr[b*{c} +: {c}] <= ptr[b*{c} +: {c}] + hot_take[b];
      end
   end
   if (clear) begin
      hist <= 0;
   end
end
",
            c = C,
            c1 = C - 1,
            d1 = self._digit - 1,
            lo1 = lo - 1,
            parts = 1 << hi,
            group = 1 << lo,
        ))
    }
}
