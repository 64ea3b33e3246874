//! The cycle model of one frame: what the core's stages cost, as a function of N, the broad
//! phase's work and the configuration. It is the specification the hardware's cycle count is
//! checked against; the latencies are the pipeline depths it must have.

use super::work::BroadWork;

/// Pipeline depth of the projection stage: input registers, `2|r|+1`, three DSP stages, sums,
/// end points, keys (`obb_rtl::projection`, checked equal by its test).
pub const LAT_PROJECT: u64 = 8;
/// Clocks of one radix pass besides its keys and its prefix sum: the last entry's way from its
/// read to its write, through the registered stages and the bin table's pointer read
/// (`obb_rtl::radix::PASS`).
pub const LAT_SORT_PASS: u64 = 6;
/// Clocks of a sort besides its passes: the clock that takes `go`, and the last entry's count
/// reaching the histogram (`obb_rtl::radix::START`).
pub const LAT_SORT_START: u64 = 3;

/// Clocks of one radix sort of `n` keys in `passes` passes of `digit_bits`-bit digits: each
/// pass a prefix sum over the `2^digit_bits` bins, then one key per clock (the histogram of the
/// next digit is counted meanwhile, the first one during the load).
pub fn sort_cycles(n: u64, passes: u32, digit_bits: u32) -> u64 {
    u64::from(passes) * ((1u64 << digit_bits) + n + LAT_SORT_PASS) + LAT_SORT_START
}
/// Clocks from a visit of the broad phase to its SAT test on the SAT's inputs: the key table
/// read and its registered output, the key and group check, the geometry read and its
/// registered output (`obb_rtl::core`: no logic follows a block RAM's output in its clock).
pub const LAT_BROAD: u64 = 5;
/// Pipeline depth of the SAT stage (products, minors, radius sums, compares, OR of 15 axes):
/// the center difference, two rounds of dot products of 5 clocks each (cascaded DSP48E1s with
/// every pipeline register), the rounding, `|minor|`, and the four-clock decision (two of
/// two-operand sums, the 15 comparisons, their OR).
pub const LAT_SAT: u64 = 22;
/// The clock after the last projection output, when its keys are in the key table.
pub const LAT_KEY_WRITE: u64 = 1;

/// Grid: clocks from a box's keys leaving the projection to its record in the record queue:
/// the window's cells registered, their hashes, their banks and buckets, the list heads read,
/// the box entered and the lists to walk decided, and written to the record queue
/// (`grid_clocks`).
pub const LAT_RECORD: u64 = 6;
/// Grid: clocks from a box's keys to its first possible visit: its record, then the enumerator
/// loads it and writes its first list to the list queue, from which the walker takes it.
pub const LAT_PROBE: u64 = LAT_RECORD + 3;
/// Grid: boxes accepted and not yet retired (probed without visits, or walked): the record
/// queue between the probe and the walker holds them all, so the load waits instead.
pub const GRID_CREDITS: usize = 32;
/// Grid: the test queue's stored entries at which the walker pauses.
pub const GRID_TEST_STALL: usize = 32;
/// Grid: clocks from a visit to its SAT test's first possible issue: the keys read and
/// registered, compared, the compares' results registered and written to the test queue,
/// loaded on its output register.
pub const LAT_GRID_CHECK: u64 = 5;
/// Grid: clocks from a SAT test's issue to the SAT's inputs: its geometry read and registered.
pub const GRID_ISSUE_TO_SAT: u64 = 2;

/// Cycles per stage of one frame, from the first clock the core accepts a box to the last SAT
/// verdict (the core's `cycles` counter).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCycles {
    /// Boxes streamed in at one per clock, then the projection pipeline drains and its last
    /// keys are written (an empty frame: its end marker and one clock).
    pub load: u64,
    /// The radix sorts (`sort_cycles`).
    pub sort: u64,
    /// The broad phase's walk (`broad::walk_cycles`): at most one visit per clock; the SAT and
    /// the output stream take one pair per clock alongside. The grid walks during the load:
    /// here only what is left after it.
    pub walk: u64,
    /// The last visit's way through the key check and the SAT (the grid: also the clear of its
    /// list heads).
    pub drain: u64,
    /// The frame's clocks, the sum of the stages (the core's `cycles`).
    pub total: u64,
}

/// The modelled cycles of a frame of `n` boxes whose broad phase did `work`.
pub fn frame_cycles(n: u64, work: &BroadWork) -> FrameCycles {
    let load = match work.grid {
        Some(g) => g.load,
        None if n == 0 => 1 + LAT_KEY_WRITE,
        None => n + LAT_PROJECT + LAT_KEY_WRITE,
    };
    let sort = work.sort_cycles;
    let walk = work.walk;
    let drain = work.grid.map_or(LAT_BROAD + LAT_SAT, |g| g.drain);
    FrameCycles {
        load,
        sort,
        walk,
        drain,
        total: load + sort + walk + drain,
    }
}
