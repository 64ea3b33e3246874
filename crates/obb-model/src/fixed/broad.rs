//! The broad phases of the core, on the integer sort keys, each emitting its SAT tests in
//! the exact order the hardware will: `brute`, the single-axis `sweep`, the paper's three-axis
//! `improved-sap` (Algorithm 2) and the `grid`, a spatial hash built during the load
//! (`grid.rs`). `brute`, `sweep` and
//! `grid` emit a pair only if the mask allows it and its keys overlap on all three axes (the
//! AABB table check); `improved-sap`, as the paper writes it, emits every pair it meets that
//! the mask allows. The SAT stage checks the keys again and runs the 15 axes, so every mode
//! reports the same pairs, and only the work differs.

use super::config::BroadPhase;
use super::cycles::sort_cycles;
use super::frame::ModelFrame;
use super::grid::{self, GridWalk};
use super::grid_clocks::grid_schedule;
pub use super::work::BroadWork;
use crate::groups::GroupMask;
use crate::radix::RadixSorter;

/// Runs the broad phase `mode` on `frame`, calling `emit(i, j)` for each pair it sends to the
/// SAT stage, in order. Returns its work.
pub fn run(
    frame: &ModelFrame,
    mode: BroadPhase,
    mask: &GroupMask,
    emit: impl FnMut(usize, usize),
) -> BroadWork {
    run_keeping(frame, mode, mask, emit).0
}

/// `run`, keeping the grid's walk (visit by visit, the grid block's reference).
pub fn run_keeping(
    frame: &ModelFrame,
    mode: BroadPhase,
    mask: &GroupMask,
    mut emit: impl FnMut(usize, usize),
) -> (BroadWork, Option<GridWalk>) {
    let mut w = BroadWork::default();
    let mut kept = None;
    // The paper's Algorithm 2 checks no other axis; the other modes check all three.
    let check_keys = mode != BroadPhase::ImprovedSap;
    let wanted = |i: usize, j: usize| {
        mask.allows(frame.obbs[i].group, frame.obbs[j].group)
            && (!check_keys || frame.keys_overlap(i, j))
    };
    let mut send = |w: &mut BroadWork, i: usize, j: usize| {
        if wanted(i, j) {
            w.sat_tests += 1;
            emit(i, j);
        }
    };
    let n = frame.obbs.len();
    let mut radix = RadixSorter::<u32>::new(frame.cfg.radix_digit_bits);
    match mode {
        BroadPhase::Brute => {
            for i in 0..n {
                for j in i + 1..n {
                    w.visits += 1;
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
                    w.visits += 1;
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
                        w.visits += 1;
                        send(&mut w, i, j);
                    }
                }
            }
        }
        BroadPhase::Grid => {
            // The lanes' SAT tests reach the SAT in the order they are issued.
            let mut sent = Vec::new();
            let walk = grid::walk(frame, mask, &mut w, &mut |w, i, j| {
                if wanted(i, j) {
                    w.sat_tests += 1;
                    sent.push((i, j));
                }
            });
            let schedule = grid_schedule(&walk);
            let mut order: Vec<usize> = (0..sent.len()).collect();
            order.sort_unstable_by_key(|&c| schedule.issues[c]);
            for c in order {
                emit(sent[c].0, sent[c].1);
            }
            w.grid = Some(schedule.clocks);
            kept = Some(walk);
        }
    }
    w.walk = walk_cycles(mode, n as u64, &w);
    (w, kept)
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
/// - `grid` overlaps the load: `grid_clocks` plays it clock by clock.
pub fn walk_cycles(mode: BroadPhase, n: u64, w: &BroadWork) -> u64 {
    match mode {
        BroadPhase::Brute => w.visits,
        BroadPhase::Sweep if n < 2 => 0,
        BroadPhase::Sweep => 4 * n + w.visits,
        BroadPhase::ImprovedSap if n < 2 => 0,
        BroadPhase::ImprovedSap => 3 * (5 * n + 1) + 2 + w.visits,
        BroadPhase::Grid => w.grid.map_or(0, |g| g.walk),
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
