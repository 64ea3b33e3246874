//! The broad phases of the core, on the integer sort keys, each emitting its candidate pairs in
//! the exact order the hardware will: `brute`, the single-axis `sweep`, the paper's three-axis
//! `improved-sap` (Algorithm 2) and the `grid` on power-of-two cells. `brute`, `sweep` and
//! `grid` emit a pair only if the mask allows it and its keys overlap on all three axes (the
//! AABB table check); `improved-sap`, as the paper writes it, emits every pair it meets that
//! the mask allows. The SAT stage checks the keys again and runs the 15 axes, so every mode
//! reports the same pairs, and only the work differs.

use super::config::BroadPhase;
use super::cycles::sort_cycles;
use super::frame::ModelFrame;
use crate::groups::GroupMask;
use crate::radix::{bits_for, RadixSorter};

/// A box covering more grid cells than this is not entered in the grid but paired with every
/// box after the cell scan (as in the CPU grid).
pub const GRID_MAX_CELLS: u64 = 64;
/// Grid cell edge as a multiple of the median key extent (rounded to a power of two).
const GRID_CELL_PER_MEDIAN: u64 = 3;
/// The three start flags below the cell in a grid key.
const FLAG_BITS: u32 = 3;

/// The work of one broad phase on one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BroadWork {
    /// Grid cell entries written (one per clock), and large boxes listed.
    pub entered: u64,
    /// Radix passes, summed over the sorts.
    pub passes: u64,
    /// Keys moved by the radix passes: each sort's length times its passes, summed.
    pub moves: u64,
    /// Clocks of the sorts (`cycles::sort_cycles`), summed.
    pub sort_cycles: u64,
    /// Index pairs the broad phase visits (one per clock per lane).
    pub visited: u64,
    /// Clocks of the walk (`walk_cycles`).
    pub walk: u64,
    /// Pairs sent to the SAT stage.
    pub emitted: u64,
}

/// Runs the broad phase `mode` on `frame`, calling `emit(i, j)` for each pair it sends to the
/// SAT stage, in order. Returns its work.
pub fn run(
    frame: &ModelFrame,
    mode: BroadPhase,
    mask: &GroupMask,
    mut emit: impl FnMut(usize, usize),
) -> BroadWork {
    let mut w = BroadWork::default();
    // The paper's Algorithm 2 checks no other axis; the other modes check all three.
    let check_keys = mode != BroadPhase::ImprovedSap;
    let wanted = |i: usize, j: usize| {
        mask.allows(frame.obbs[i].group, frame.obbs[j].group)
            && (!check_keys || frame.keys_overlap(i, j))
    };
    let mut send = |w: &mut BroadWork, i: usize, j: usize| {
        if wanted(i, j) {
            w.emitted += 1;
            emit(i, j);
        }
    };
    let n = frame.obbs.len();
    let mut radix = RadixSorter::<u32>::new(frame.cfg.radix_digit_bits);
    match mode {
        BroadPhase::Brute => {
            for i in 0..n {
                for j in i + 1..n {
                    w.visited += 1;
                    send(&mut w, i, j);
                }
            }
        }
        BroadPhase::Sweep => {
            // Stable sort of the boxes by min key on x; each walks its successors while their
            // min key is within its own max key.
            let mut keys: Vec<u64> = frame.keys.iter().map(|k| k.0[0]).collect();
            let mut order: Vec<u32> = (0..n as u32).collect();
            sort(
                &mut radix,
                &mut keys,
                &mut order,
                frame.cfg.key_bits,
                &mut w,
            );
            for p in 0..n {
                let i = order[p] as usize;
                for &j in &order[p + 1..] {
                    let j = j as usize;
                    if frame.keys[j].0[0] > frame.keys[i].1[0] {
                        break;
                    }
                    w.visited += 1;
                    send(&mut w, i, j);
                }
            }
        }
        BroadPhase::ImprovedSap => {
            // Per axis, the 2n endpoints (box 0 min, box 0 max, box 1 min, ...) sorted stably by
            // (key, min before max); from each min, every box met before its own max. Fewer
            // than two boxes have no pair: nothing is sorted.
            for axis in (0..3).filter(|_| n >= 2) {
                let mut keys = Vec::with_capacity(2 * n);
                let mut ends = Vec::with_capacity(2 * n);
                for (i, k) in frame.keys.iter().enumerate() {
                    keys.push(k.0[axis] << 1);
                    ends.push((i as u32) << 1);
                    keys.push(k.1[axis] << 1 | 1);
                    ends.push((i as u32) << 1 | 1);
                }
                sort(
                    &mut radix,
                    &mut keys,
                    &mut ends,
                    frame.cfg.key_bits + 1,
                    &mut w,
                );
                for (p, &e) in ends.iter().enumerate() {
                    if e & 1 == 1 {
                        continue;
                    }
                    let i = (e >> 1) as usize;
                    for &other in &ends[p + 1..] {
                        let j = (other >> 1) as usize;
                        if j == i {
                            break;
                        }
                        w.visited += 1;
                        send(&mut w, i, j);
                    }
                }
            }
        }
        BroadPhase::Grid => grid(frame, &mut radix, &mut w, &mut send),
    }
    w.walk = walk_cycles(mode, n as u64, &w, frame.cfg.lanes);
    w
}

/// Clocks the broad phase's walk takes besides its sorts (`obb_rtl::walker`, `obb_rtl::sweep`).
/// - `brute` visits one pair per clock.
/// - `sweep` (two boxes or more) spends per outer box except the last four clocks (reading its
///   first successor, the block RAM's output, the entry's register, the restart after the
///   entry that ends it) plus one per visit; the entry beyond its max key, or the end of the
///   entries, ends it and the reads behind it are dropped. Four clocks start the walk at entry
///   0, which becomes the first outer box. `4n + visited` (`obb_rtl::sweep`).
/// - `improved-sap` (two boxes or more) spends per axis 2n clocks loading the end points into
///   the sort and one reading the first sorted one; then one clock per max end point, and per
///   min end point one clock, one per visit and one for the box's own max: `5n + 1` per axis
///   plus the visits, and one clock starting each of the second and third axes.
/// - `grid` is not built yet: its visits spread over the lanes stand in for it.
pub fn walk_cycles(mode: BroadPhase, n: u64, w: &BroadWork, lanes: u32) -> u64 {
    match mode {
        BroadPhase::Brute => w.visited,
        BroadPhase::Sweep if n < 2 => 0,
        BroadPhase::Sweep => 4 * n + w.visited,
        BroadPhase::ImprovedSap if n < 2 => 0,
        BroadPhase::ImprovedSap => 3 * (5 * n + 1) + 2 + w.visited,
        BroadPhase::Grid => w.visited.div_ceil(u64::from(lanes)),
    }
}

/// Sorts `keys` (with `vals`) on `bits` bits and counts the work.
fn sort(
    radix: &mut RadixSorter<u32>,
    keys: &mut Vec<u64>,
    vals: &mut Vec<u32>,
    bits: u32,
    w: &mut BroadWork,
) {
    radix.sort(keys, vals, bits);
    let passes = radix.passes(bits);
    w.passes += u64::from(passes);
    w.moves += u64::from(passes) * keys.len() as u64;
    w.sort_cycles += sort_cycles(keys.len() as u64, passes, radix.digit_bits(bits));
}

/// Most bits of a cell coordinate per axis: a cell key (three coordinates and the start flags)
/// must fit 64 bits.
const GRID_AXIS_BITS_MAX: u32 = (64 - FLAG_BITS) / 3;

/// log2 of the grid's cell edge in key units: `GRID_CELL_PER_MEDIAN` times the median key
/// extent (mean over the axes), rounded to the nearest power of two; no finer than a cell key
/// of 64 bits allows (wide keys and tiny boxes would otherwise overflow it).
pub fn grid_cell_log2(frame: &ModelFrame) -> u32 {
    let mut extents: Vec<u64> = frame
        .keys
        .iter()
        .map(|(lo, hi)| (0..3).map(|x| hi[x] - lo[x]).sum::<u64>() / 3)
        .collect();
    if extents.is_empty() {
        return frame.cfg.key_bits.saturating_sub(GRID_AXIS_BITS_MAX);
    }
    let mid = extents.len() / 2;
    let median = *extents.select_nth_unstable(mid).1;
    let edge = (median * GRID_CELL_PER_MEDIAN).max(1);
    // Nearest power of two: round log2 of the edge.
    let low = bits_for(edge) - 1;
    let up = u32::from(edge - (1 << low) > (1 << low) / 2);
    (low + up)
        .max(frame.cfg.key_bits.saturating_sub(GRID_AXIS_BITS_MAX))
        .min(frame.cfg.key_bits)
}

/// The grid: each box (unless large) enters every cell its keys cover, with three flags saying
/// on which axes its range starts there; the entries are radix-sorted by (cell, flags); in each
/// cell every pair of entries is visited in sorted order and emitted when the cell is the pair's
/// home (the flags of the two cover all three axes). Then each large box, in index order, is
/// paired with every box (two large boxes once).
fn grid(
    frame: &ModelFrame,
    radix: &mut RadixSorter<u32>,
    w: &mut BroadWork,
    send: &mut impl FnMut(&mut BroadWork, usize, usize),
) {
    let g = grid_cell_log2(frame);
    let axis_bits = frame.cfg.key_bits - g;
    let mut keys = Vec::new();
    let mut entries = Vec::new();
    let mut large = Vec::new();
    for (i, (lo, hi)) in frame.keys.iter().enumerate() {
        let c0 = lo.map(|k| k >> g);
        let c1 = hi.map(|k| k >> g);
        if (0..3).map(|x| c1[x] - c0[x] + 1).product::<u64>() > GRID_MAX_CELLS {
            large.push(i);
            continue;
        }
        for z in c0[2]..=c1[2] {
            for y in c0[1]..=c1[1] {
                for x in c0[0]..=c1[0] {
                    let cell = (z << (2 * axis_bits)) | (y << axis_bits) | x;
                    let flags = u64::from(x == c0[0])
                        | u64::from(y == c0[1]) << 1
                        | u64::from(z == c0[2]) << 2;
                    keys.push(cell << FLAG_BITS | flags);
                    entries.push(i as u32);
                }
            }
        }
    }
    w.entered = (keys.len() + large.len()) as u64;
    sort(radix, &mut keys, &mut entries, 3 * axis_bits + FLAG_BITS, w);
    let mut start = 0;
    while start < keys.len() {
        let cell = keys[start] >> FLAG_BITS;
        let end = start + keys[start..].partition_point(|k| k >> FLAG_BITS == cell);
        for p in start..end {
            for q in p + 1..end {
                w.visited += 1;
                if (keys[p] | keys[q]) & 0b111 == 0b111 {
                    send(w, entries[p] as usize, entries[q] as usize);
                }
            }
        }
        start = end;
    }
    let mut is_large = vec![false; frame.obbs.len()];
    for &l in &large {
        is_large[l] = true;
    }
    for &l in &large {
        for (j, &j_large) in is_large.iter().enumerate() {
            if j == l || (j_large && j < l) {
                continue;
            }
            w.visited += 1;
            send(w, l, j);
        }
    }
}
