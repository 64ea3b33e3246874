//! The cycle model of one frame: what the core's stages cost, as a function of N, the broad
//! phase's work and the configuration. It is the specification the hardware's cycle count is
//! checked against (issue 4); the latencies are the pipeline depths it must have.

use super::broad::BroadWork;
use super::config::HwConfig;

/// Pipeline depth of the projection stage: input registers, `2|r|+1`, three DSP stages, sums,
/// end points, keys (`obb_rtl::projection`, checked equal by its test).
pub const LAT_PROJECT: u64 = 8;
/// Clocks of one radix pass besides its keys and its prefix sum: the write of the last entry,
/// one clock behind its read (`obb_rtl::radix`).
pub const LAT_SORT_PASS: u64 = 1;
/// Clocks of a sort besides its passes: the clock that takes `go`.
pub const LAT_SORT_START: u64 = 1;

/// Clocks of one radix sort of `n` keys in `passes` passes of `digit_bits`-bit digits: each
/// pass a prefix sum over the `2^digit_bits` bins, then one key per clock (the histogram of the
/// next digit is counted meanwhile, the first one during the load).
pub fn sort_cycles(n: u64, passes: u32, digit_bits: u32) -> u64 {
    u64::from(passes) * ((1u64 << digit_bits) + n + LAT_SORT_PASS) + LAT_SORT_START
}
/// Pipeline depth of the broad-phase unit (key table read, compare, mask).
pub const LAT_BROAD: u64 = 4;
/// Pipeline depth of the SAT stage (products, minors, radius sums, compares, OR of 15 axes).
pub const LAT_SAT: u64 = 14;

/// Cycles per stage of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCycles {
    /// Boxes streamed in at one per clock through the projection pipeline.
    pub load: u64,
    /// Grid cell entries written at one per clock.
    pub enter: u64,
    /// The radix sorts (`sort_cycles`).
    pub sort: u64,
    /// The broad phase visits `lanes` index pairs per clock; the SAT stage and the output
    /// stream (one pair per clock) run alongside, so the slower of the two sets the pace.
    pub pairs: u64,
    /// The SAT pipeline drains after the last pair.
    pub drain: u64,
    pub total: u64,
}

/// The modelled cycles of a frame of `n` boxes whose broad phase did `work` and which reports
/// `pairs` pairs.
pub fn frame_cycles(cfg: &HwConfig, n: u64, work: &BroadWork, pairs: u64) -> FrameCycles {
    let load = n + LAT_PROJECT;
    let enter = work.entered;
    let sort = work.sort_cycles;
    let visit = work.visited.div_ceil(u64::from(cfg.lanes)) + LAT_BROAD;
    let pairs = visit.max(pairs);
    let drain = LAT_SAT;
    FrameCycles {
        load,
        enter,
        sort,
        pairs,
        drain,
        total: load + enter + sort + pairs + drain,
    }
}
