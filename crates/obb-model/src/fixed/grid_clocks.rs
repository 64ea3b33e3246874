//! The grid's clock model: the load, the probe and the walk overlap, so the frame's clocks come
//! from playing the stages clock by clock, as the core runs them (docs/numerics.md, "Cycle
//! model"). The rules, each a register or a queue of the grid core:
//!
//! - **Accept.** Box k is accepted on the first clock after box k-1's at which fewer than
//!   `GRID_CREDITS` boxes are accepted and not retired (counted from the clock before: the
//!   core's `obb_ready` is a register). Its keys leave the projection `LAT_PROJECT` clocks later.
//! - **Probe.** `LAT_PROBE` clocks after its keys, the box's list heads are read and it is
//!   entered; a box with no visit (or a large one) retires then. A box with visits hands the
//!   walker a record.
//! - **Walk.** The walker takes the records in box order and makes one visit per clock, from
//!   the clock its record is probed; a box retires on the clock of its last visit. It pauses on
//!   a clock when the candidate queue held `GRID_CAND_STALL` or more entries on the clock before.
//! - **Check.** A visit at clock V whose keys overlap enters the candidate queue at V + 2 and may
//!   be issued from V + `LAT_GRID_CHECK`.
//! - **Issue.** The oldest candidate is issued to the SAT on a clock when no box is accepted (the
//!   geometry tables' port A writes the arriving box); its geometry is read and registered
//!   (`LAT_BROAD - LAT_GRID_CHECK` clocks), then the SAT.
//! - **Slow path.** When every box has been accepted and has retired, each large box in turn
//!   spends `GRID_LARGE_START` clocks reading its keys; then per round of its window
//!   `LAT_PROBE` clocks (cells, banks, heads, first list) and its visits one per clock; then,
//!   if a large box follows, `LAT_PROBE` clocks and a visit per later large box.
//! - **End.** The last verdict comes `LAT_BROAD + LAT_SAT` clocks after the last probe, visit
//!   or (less `LAT_GRID_CHECK`) issue.

use super::cycles::{
    GRID_CAND_STALL, GRID_CREDITS, GRID_LARGE_START, LAT_GRID_CHECK, LAT_KEY_WRITE, LAT_PROBE,
    LAT_PROJECT,
};
use super::grid::GridWalk;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

/// The grid's clocks, from the first load clock: the load ends when the last keys are in the
/// key table; the walk, when the last probe, visit or issue is done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridClocks {
    pub load: u64,
    pub walk: u64,
}

/// Plays the grid core clock by clock on the visits `walk` met.
pub fn grid_clocks(walk: &GridWalk) -> GridClocks {
    let n = walk.visits.len();
    if n == 0 {
        return GridClocks {
            load: 1 + LAT_KEY_WRITE,
            walk: 0,
        };
    }
    let probed = |accept: u64| accept + LAT_PROJECT + LAT_PROBE;
    // A large box has no visits of its own: its slow path comes after the load.
    let has_record = |k: usize| walk.visits[k].1 > 0;
    let records: Vec<usize> = (0..n).filter(|&k| has_record(k)).collect();
    // The slow path as one sequence of phases: clocks of start-up, then visits.
    let mut slow: VecDeque<(u64, usize)> = VecDeque::new();
    for (k, w) in walk.large.iter().enumerate() {
        slow.push_back((GRID_LARGE_START, 0));
        slow.extend(w.rounds.iter().map(|&v| (LAT_PROBE, v)));
        if k + 1 < walk.large.len() {
            slow.push_back((LAT_PROBE, w.partners));
        }
    }
    let slow_first = walk.visits.iter().map(|v| v.0 + v.1).max().unwrap_or(0);
    let mut slow_visit = slow_first;
    let mut accepted = Vec::with_capacity(n);
    let mut retire: BinaryHeap<Reverse<u64>> = BinaryHeap::new();
    let mut retired = 0usize;
    let mut last_event = 0u64;
    // The walker: the record it is on and the visit within it.
    let (mut record, mut pos) = (0usize, 0usize);
    // Candidates: visit clocks not yet counted as written, and not yet issued.
    let mut in_check: VecDeque<u64> = VecDeque::new();
    let mut pending: VecDeque<u64> = VecDeque::new();
    let (mut written, mut issued) = (0usize, 0usize);
    let mut t = 0u64;
    loop {
        t += 1;
        while retire.peek().is_some_and(|r| r.0 < t) {
            retire.pop();
            retired += 1;
        }
        while in_check.front().is_some_and(|&v| v + 2 < t) {
            in_check.pop_front();
            written += 1;
        }
        let queued = written - issued;
        // Accept.
        let accept = accepted.len() < n && accepted.len() - retired < GRID_CREDITS;
        if accept {
            let k = accepted.len();
            accepted.push(t);
            if !has_record(k) {
                retire.push(Reverse(probed(t)));
                last_event = last_event.max(probed(t));
            }
        }
        // Issue.
        if !accept && pending.front().is_some_and(|&v| v + LAT_GRID_CHECK <= t) {
            pending.pop_front();
            issued += 1;
            last_event = last_event.max(t - LAT_GRID_CHECK);
        }
        // Walk.
        let stall = queued >= GRID_CAND_STALL;
        let mut visit = None;
        if record < records.len() {
            let k = records[record];
            if !stall && k < accepted.len() && probed(accepted[k]) <= t {
                let (first, count) = walk.visits[k];
                visit = Some(first + pos);
                pos += 1;
                if pos == count {
                    retire.push(Reverse(t));
                    record += 1;
                    pos = 0;
                }
            }
        } else if accepted.len() == n && retired == n {
            if let Some((start, visits)) = slow.front_mut() {
                last_event = last_event.max(t);
                if *start > 0 {
                    *start -= 1;
                } else if *visits > 0 && !stall {
                    visit = Some(slow_visit);
                    slow_visit += 1;
                    *visits -= 1;
                }
                if *start == 0 && *visits == 0 {
                    slow.pop_front();
                }
            }
        }
        if let Some(v) = visit {
            last_event = last_event.max(t);
            if walk.passes[v] {
                in_check.push_back(t);
                pending.push_back(t);
            }
        }
        let walked = record == records.len() && slow.is_empty();
        if accepted.len() == n && walked && retired == n && pending.is_empty() {
            break;
        }
    }
    let load = accepted[n - 1] + LAT_PROJECT + LAT_KEY_WRITE;
    GridClocks {
        load,
        walk: last_event - load,
    }
}
