//! The grid's clock model: the load, the probe and the walk overlap, so the frame's clocks come
//! from playing the stages clock by clock, as the grid block (`obb_rtl::grid`) runs them
//! (docs/numerics.md, "Cycle model"). Clocks count from 1, the first clock a box may be
//! accepted; "at clock t" means the clock whose edge ends it, so a register written at t is
//! read from t + 1. The rules, each a register or a queue of the block:
//!
//! - **Accept.** A box is accepted at clock t when boxes are left and fewer than
//!   `GRID_CREDITS` boxes were accepted before t and not retired before t. Its keys leave the
//!   projection `LAT_PROJECT` clocks later (clock K).
//! - **Probe.** The window's cells, their banks and buckets take three clocks; at K + 3 the list
//!   heads are read and the box is entered; at K + 4 the lists it must walk are registered and
//!   written to the record queue, or, when it has none (or is large), it retires. Its record is
//!   the walker's from K + 5 = accept + `LAT_PROJECT` + `LAT_PROBE`.
//! - **Walk.** The walker takes the records in box order and makes one visit per clock, from
//!   list to list and from record to record without a gap; a record retires on the clock after
//!   its last visit, when the walker reads that the list has ended. It pauses on a clock when
//!   the candidate queue stores `GRID_CAND_STALL` entries or more (its output register not
//!   counted).
//! - **Check.** A visit at V is read from the key table at V + 1, compared at V + 2 and, when the
//!   keys overlap, written to the candidate queue (`obb_rtl::pair_fifo`): stored from V + 3, on
//!   its output register from V + 4 at the earliest (`LAT_GRID_CHECK`).
//! - **Issue.** The candidate on the output register is issued on a clock when no box is accepted
//!   (the geometry tables' port A writes the arriving box); the output register takes the next
//!   stored entry on a clock it is empty or issued. An issued candidate is on the SAT's inputs
//!   `GRID_ISSUE_TO_SAT` clocks later.
//! - **Slow path.** When every box has been accepted and has retired, each large box in turn
//!   spends `GRID_LARGE_START` clocks reading its keys; then per round of its window
//!   `LAT_PROBE` clocks (cells, banks, heads, first list) and its visits one per clock; then,
//!   if a large box follows, `LAT_PROBE` clocks and a visit per later large box.
//! - **End.** The walk is over on the clock after the last retirement (or the slow path's last
//!   clock); the block sees it on the next. From the clock after that, every list head is
//!   cleared for the next frame, one bucket of every bank a clock (`2^grid_hash_bits` clocks),
//!   while the last candidates leave; the frame ends with the later of the clear and the last
//!   verdict.

use super::cycles::{
    GRID_CAND_STALL, GRID_CREDITS, GRID_ISSUE_TO_SAT, GRID_LARGE_START, LAT_KEY_WRITE, LAT_PROBE,
    LAT_PROJECT, LAT_SAT,
};
use super::grid::GridWalk;
use std::collections::VecDeque;

/// The grid's clocks, from the first load clock: the load ends when the last keys are in the
/// key table; the walk, when every box has retired and the slow path is done; the drain is
/// the rest (the clear of the list heads, the last verdicts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridClocks {
    pub load: u64,
    pub walk: u64,
    pub drain: u64,
}

/// What the grid block does on which clock: the schedule the RTL is checked against.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GridSchedule {
    /// Per box, the clock it is accepted.
    pub accepts: Vec<u64>,
    /// Per visit of `GridWalk::pairs`, in order, the clock it is made.
    pub visits: Vec<u64>,
    /// Per candidate (a visit that passed the key check), in order, the clock it is issued.
    pub issues: Vec<u64>,
    /// The clock the walk is over (the block's `walked` rises on the next).
    pub walked: u64,
    pub clocks: GridClocks,
}

/// The grid core's candidate queue (`obb_rtl::pair_fifo`): entries stored and the output
/// register, clock by clock.
#[derive(Default)]
struct CandidateQueue {
    /// Visit clocks of the candidates written and not yet on the output register.
    stored: VecDeque<u64>,
    out: Option<u64>,
}

/// Plays the grid block clock by clock on the visits `walk` met.
pub fn grid_schedule(walk: &GridWalk) -> GridSchedule {
    let n = walk.visits.len();
    let mut s = GridSchedule {
        accepts: Vec::with_capacity(n),
        visits: Vec::with_capacity(walk.passes.len()),
        ..GridSchedule::default()
    };
    let keys_out = |accept: u64| accept + LAT_PROJECT;
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
    // Retirements by clock, at the probe and by the walker (each in order), and the credits'
    // count (accepted and not retired before t).
    let mut retire_probe: VecDeque<u64> = VecDeque::new();
    let mut retire_walker: VecDeque<u64> = VecDeque::new();
    let mut inflight = 0usize;
    let mut retired = 0usize;
    // The walker: the record it is on and the visit within it.
    let (mut record, mut pos) = (0usize, 0usize);
    let mut queue = CandidateQueue::default();
    // Visit clocks in the key check, and whether they pass.
    let mut in_check: VecDeque<(u64, bool)> = VecDeque::new();
    let mut last_issue = 0u64;
    let mut t = 0u64;
    loop {
        t += 1;
        // Retirements of the clock before.
        for q in [&mut retire_probe, &mut retire_walker] {
            while q.front().is_some_and(|&r| r < t) {
                q.pop_front();
                inflight -= 1;
                retired += 1;
            }
        }
        // Accept.
        let accept = s.accepts.len() < n && inflight < GRID_CREDITS;
        if accept {
            let k = s.accepts.len();
            s.accepts.push(t);
            inflight += 1;
            if !has_record(k) {
                retire_probe.push_back(keys_out(t) + 4);
            }
        }
        // The candidate queue: issue from the output register, load it, store the write.
        let stall = queue.stored.len() >= GRID_CAND_STALL;
        let issue = !accept && queue.out.is_some();
        if issue {
            queue.out = None;
            s.issues.push(t);
            last_issue = t;
        }
        let load = queue
            .out
            .is_none()
            .then(|| queue.stored.pop_front())
            .flatten();
        let write = in_check
            .front()
            .is_some_and(|&(v, _)| v + 2 == t)
            .then(|| in_check.pop_front().unwrap())
            .filter(|&(_, pass)| pass);
        if let Some(v) = load {
            queue.out = Some(v);
        }
        if let Some((v, _)) = write {
            queue.stored.push_back(v);
        }
        // Walk.
        let mut visit = None;
        if record < records.len() {
            let k = records[record];
            let ready = k < s.accepts.len() && keys_out(s.accepts[k]) + LAT_PROBE <= t;
            if !stall && ready {
                let (first, count) = walk.visits[k];
                visit = Some(first + pos);
                pos += 1;
                if pos == count {
                    retire_walker.push_back(t + 1);
                    record += 1;
                    pos = 0;
                }
            }
        } else if s.accepts.len() == n && retired == n {
            if let Some((start, visits)) = slow.front_mut() {
                if *start > 0 {
                    *start -= 1;
                } else if *visits > 0 && !stall {
                    visit = Some(slow_visit);
                    slow_visit += 1;
                    *visits -= 1;
                }
                if *start == 0 && *visits == 0 {
                    slow.pop_front();
                    s.walked = t;
                }
            }
        }
        if let Some(v) = visit {
            s.visits.push(t);
            in_check.push_back((t, walk.passes[v]));
        }
        // (A frame of no box: its end marker comes at clock 1, and is seen from clock 2.)
        let marked = n > 0 || t > 1;
        if s.accepts.len() == n && retired == n && marked && s.walked == 0 && walk.large.is_empty()
        {
            s.walked = t;
        }
        let drained = in_check.is_empty() && queue.stored.is_empty() && queue.out.is_none();
        if s.walked > 0 && slow.is_empty() && drained {
            break;
        }
    }
    let load = s.accepts.last().map_or(1, |&a| keys_out(a)) + LAT_KEY_WRITE;
    let clear = 1u64 << walk.hash_bits;
    let verdict = if s.issues.is_empty() {
        0
    } else {
        last_issue + GRID_ISSUE_TO_SAT + LAT_SAT
    };
    let end = (s.walked + 1 + clear).max(verdict).max(load);
    s.clocks = GridClocks {
        load,
        walk: s.walked.max(load) - load,
        drain: end - s.walked.max(load),
    };
    s
}

/// The grid's clocks for the visits `walk` met.
pub fn grid_clocks(walk: &GridWalk) -> GridClocks {
    grid_schedule(walk).clocks
}
