//! The grid's clock model: the load, the probe and the walk overlap, so the frame's clocks come
//! from playing the stages clock by clock, as the grid block (`obb_rtl::grid`) runs them
//! (docs/numerics.md, "Cycle model"). Clocks count from 1, the first clock a box may be
//! accepted; "at clock t" means the clock whose edge ends it, so a register written at t is
//! read from t + 1. The rules, each a register or a queue of the block:
//!
//! - **Accept.** A box is accepted at clock t when boxes are left and the credit is set: on
//!   every lane, fewer than `GRID_CREDITS - 1` boxes were accepted before t - 1 and not retired
//!   before t - 1 (a register, so one more, accepted at t - 1, still finds room; the first
//!   clock has the credit). Its keys leave the projection `LAT_PROJECT` clocks later (clock K).
//! - **Probe.** The window's cells, their banks and buckets take three clocks; at K + 3 the list
//!   heads are read; at K + 4 the box is entered and the lists it must walk are decided; at
//!   K + 5 they are written to the record queue, or, when it has none (or is large), it
//!   retires at K + 6 (the retirement is registered). Its record is in the queue from
//!   K + 6 = accept + `LAT_PROJECT` + `LAT_RECORD`.
//! - **Enumerate.** The enumerator takes the records in box order and writes their lists to the
//!   list queue (`LIST_QUEUE` entries), each over two clocks: on a clock it writes none it
//!   chooses its record's next list; a chosen list is written on a clock when at most
//!   `LIST_QUEUE - 2` are queued, not counting that clock's. It loads a record on a clock it
//!   holds none (from the clock after it writes its record's last list); it chooses the
//!   record's first list the clock after, writes it the clock after that, and the walker may
//!   take it the clock after that (`LAT_PROBE`).
//! - **Walk.** The walker takes the lists in order and makes one visit per clock, from list to
//!   list without a gap while lists are queued; a record retires on the clock after its last
//!   visit, when the walker reads that its last list has ended. It pauses on a clock when
//!   the test queue stores `GRID_TEST_STALL` entries or more (its output register not
//!   counted); a list it takes on such a clock leaves the list queue then.
//! - **Check.** A visit at V is read from the key table at V + 1, compared at V + 2, the
//!   compares' results registered at V + 3 and, when the keys overlap, written to the
//!   test queue (`obb_rtl::pair_fifo`): stored from V + 4, on its output register from V + 5 at the
//!   earliest (`LAT_GRID_CHECK`).
//! - **Issue.** The SAT test on the output register is issued on a clock when no box is accepted
//!   (the geometry tables' port A writes the arriving box); the output register takes the next
//!   stored entry on a clock it is empty or issued. An issued SAT test is on the SAT's inputs
//!   `GRID_ISSUE_TO_SAT` clocks later.
//! - **Slow path.** A sequencer works on *idle* clocks: a clock is idle when on the clock
//!   before every box had been accepted, nothing was in flight (accepted or injected, not
//!   retired) and nothing was launched (the flag is a register). Per large box, in the
//!   chain's order: an idle clock fetches it, the next puts its address on port B (its keys
//!   and its successor, the next large box, are read), the next registers them, the next
//!   computes its window's limit, the next plans its window (or, too wide, ends the slow
//!   path); then each round is *launched* on an idle clock and injected on the next as a box
//!   whose keys span the round's cells, probed and walked as an arriving box is (its keys at
//!   the injection clock K, its record in the queue from K + `LAT_RECORD`, retiring at K + 6
//!   when it has no list); then, if a large box follows, a record of one list, the rest of
//!   the chain, is launched the same way.
//! - **Lanes.** With several, each lane has its own record queue, enumerator, list queue,
//!   walker, key check and test queue, on its lane's lists, by the rules above. A box (or
//!   injected record) is in flight on every lane from its accept (injection) until that lane
//!   retires it; a box is accepted when the credit is set on every lane, and a clock is idle
//!   when no lane had one in flight on the clock before. On a clock with no accept, the lowest
//!   lane with a SAT test on its output register issues it.
//! - **Update frame** (`resident_groups`): before the first accept, every list head is
//!   cleared, one bucket of every bank a clock (clocks 1 to `2^grid_hash_bits`); the credit is
//!   set from the clock after. The clear after the walk then clears only the lists of the
//!   groups that are not resident.
//! - **End.** The walk is over on the first idle clock with no large box left to fetch (or
//!   after a window too wide). From the clock after that, every list head is
//!   cleared for the next frame, one bucket of every bank a clock (`2^grid_hash_bits` clocks),
//!   while the last SAT tests leave; the frame ends with the later of the clear and the last
//!   verdict.

use super::cycles::{
    GRID_CREDITS, GRID_ISSUE_TO_SAT, GRID_TEST_STALL, LAT_KEY_WRITE, LAT_PROJECT, LAT_RECORD,
    LAT_SAT,
};
use super::grid::GridWalk;
pub use super::work::GridClocks;
use std::collections::VecDeque;

/// What the grid block does on which clock: the schedule the RTL is checked against.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GridSchedule {
    /// Per box, the clock it is accepted.
    pub accepts: Vec<u64>,
    /// Per visit of `GridWalk::pairs`, in order, the clock it is made.
    pub visits: Vec<u64>,
    /// Per SAT test (a visit that passed the key check), in the walk's order, the clock it is
    /// issued (with several lanes not in that order).
    pub issues: Vec<u64>,
    /// Per large box fetched by the slow path, in order: the clock its address is on port B (its
    /// keys are read there), its index.
    pub fetches: Vec<(u64, usize)>,
    /// The clock the walk is over (the block's `walked` is high from it).
    pub walked: u64,
    /// The frame's clocks as the grid spends them.
    pub clocks: GridClocks,
}

/// The grid core's test queue (`obb_rtl::pair_fifo`), one a lane: SAT tests (their
/// index among the walk's) stored and on the output register, clock by clock.
#[derive(Default)]
struct TestQueue {
    stored: VecDeque<usize>,
    out: Option<usize>,
}

/// A record in a lane's record queue: the clock the enumerator may load it, its lists (a range
/// of `GridWalk::lists`) and its first visit (in `GridWalk::pairs`).
struct Record {
    ready: u64,
    lists: std::ops::Range<usize>,
    visit: usize,
}

/// The enumerator's record: its lists left, the first visit of the next, and whether the next
/// is chosen (a clock's choice is written on a later clock).
struct Enumerator {
    lists: std::ops::Range<usize>,
    visit: usize,
    chosen: bool,
}

/// A list in the list queue: its visits, its first visit, whether it is its record's last.
#[derive(Clone, Copy)]
struct Queued {
    visits: usize,
    first: usize,
    last: bool,
}

/// The list queue's entries between a lane's enumerator and its walker.
const LIST_QUEUE: usize = 4;

/// One walker lane: its records in flight, its record queue, enumerator, list queue, walker,
/// key check and test queue.
#[derive(Default)]
struct Lane {
    records: VecDeque<Record>,
    // Retirements, by the probe (a record with no list on this lane) and by the walker.
    retire_probe: VecDeque<u64>,
    retire_walker: VecDeque<u64>,
    // Boxes and injected records accepted and not retired on this lane before t.
    inflight: usize,
    enumerator: Option<Enumerator>,
    list_queue: VecDeque<Queued>,
    // The walker's next visit, the visits left in its list (a held one included), whether
    // that list is its record's last.
    next_visit: usize,
    left: usize,
    last_list: bool,
    // Visits in the key check: clock and visit.
    in_check: VecDeque<(u64, usize)>,
    queue: TestQueue,
}

impl Lane {
    /// Retirements of the clocks before `t`.
    fn retire(&mut self, t: u64) {
        for q in [&mut self.retire_probe, &mut self.retire_walker] {
            while q.front().is_some_and(|&r| r < t) {
                q.pop_front();
                self.inflight -= 1;
            }
        }
    }

    /// Enumerate at `t`: a list chosen on a clock before is written when at most
    /// `LIST_QUEUE - 2` lists are queued (not counting this clock's); on a clock it writes
    /// none, the enumerator chooses its record's next list. It loads the next record on a clock
    /// it holds none: its last list written, it is free from the next clock. Returns the list
    /// written, which is queued at the end of the clock.
    fn enumerate(&mut self, t: u64, lists: &[usize]) -> Option<Queued> {
        let mut written = None;
        let free = self.enumerator.is_none();
        if let Some(e) = self.enumerator.as_mut() {
            if e.chosen && self.list_queue.len() <= LIST_QUEUE - 2 {
                let l = e.lists.next().expect("a record has lists");
                let last = e.lists.is_empty();
                written = Some(Queued {
                    visits: lists[l],
                    first: e.visit,
                    last,
                });
                e.visit += lists[l];
                e.chosen = false;
                if last {
                    self.enumerator = None;
                }
            } else {
                e.chosen = true;
            }
        }
        if free {
            self.enumerator = self.records.front().is_some_and(|r| r.ready <= t).then(|| {
                let r = self.records.pop_front().unwrap();
                Enumerator {
                    lists: r.lists,
                    visit: r.visit,
                    chosen: false,
                }
            });
        }
        written
    }

    /// Walk at `t`: with no list left to go on, the walker takes the next queued (written
    /// before t), or, its record's last list done, retires the record; one visit per clock
    /// unless the test queue stalls it. Returns the visit made.
    fn walk(&mut self, t: u64, stall: bool) -> Option<usize> {
        if self.left == 0 {
            if self.last_list {
                self.retire_walker.push_back(t);
                self.last_list = false;
            }
            if let Some(q) = self.list_queue.pop_front() {
                self.left = q.visits;
                self.next_visit = q.first;
                self.last_list = q.last;
            }
        }
        (self.left > 0 && !stall).then(|| {
            self.left -= 1;
            self.in_check.push_back((t, self.next_visit));
            self.next_visit += 1;
            self.next_visit - 1
        })
    }

    fn drained(&self) -> bool {
        self.in_check.is_empty() && self.queue.stored.is_empty() && self.queue.out.is_none()
    }
}

/// The slow path's sequencer: what it does on its next idle clock (or its next clock).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Slow {
    Fetch,
    Address,
    Read,
    Limit,
    Plan,
    Round(usize),
    Partner,
    Over,
}

/// Plays the grid block clock by clock on the visits `walk` met.
pub fn grid_schedule(walk: &GridWalk) -> GridSchedule {
    let n = walk.visits.len() / walk.lanes.max(1);
    let mut s = GridSchedule {
        accepts: Vec::with_capacity(n),
        visits: vec![0; walk.passes.len()],
        ..GridSchedule::default()
    };
    // Per visit that passes, its SAT test's index; `issues` is filled by SAT test.
    let mut test_of = Vec::with_capacity(walk.passes.len());
    let mut tests = 0usize;
    for &pass in &walk.passes {
        test_of.push(tests);
        tests += usize::from(pass);
    }
    s.issues = vec![0; tests];
    let keys_out = |accept: u64| accept + LAT_PROJECT;
    let mut lanes: Vec<Lane> = (0..walk.lanes).map(|_| Lane::default()).collect();
    // Boxes and injected records enter the probe at K: on each lane a record from
    // K + LAT_RECORD, or a retirement at K + 6 when it has no list there. A record's lists on a
    // lane are the next of `walk.lists` that hold its visits there.
    let (mut next_list, mut next_visit) = (0usize, 0usize);
    let mut probe = |k: u64, counts: &[usize], lanes: &mut [Lane]| {
        for (lane, &count) in lanes.iter_mut().zip(counts) {
            lane.inflight += 1;
            if count == 0 {
                lane.retire_probe.push_back(k + LAT_RECORD);
                continue;
            }
            let (first, visit) = (next_list, next_visit);
            let mut visits = 0;
            while visits < count {
                visits += walk.lists[next_list];
                next_list += 1;
            }
            debug_assert_eq!(visits, count, "a record's visits are whole lists");
            next_visit += count;
            lane.records.push_back(Record {
                ready: k + LAT_RECORD,
                lists: first..next_list,
                visit,
            });
        }
    };
    // The slow path: its state, the large box (in `walk.large`).
    let mut slow = Slow::Fetch;
    let mut large = 0usize;
    let mut last_issue = 0u64;
    let mut t = 0u64;
    // The credit and the idle flag are registers, set from the clock before's counts (so that
    // no path runs from the counts to the load and the slow path in one clock).
    let (mut credit, mut idle) = (true, false);
    // An update frame clears the list heads on its first clocks.
    let clear = 1u64 << walk.hash_bits;
    let cleared_first = if walk.clear_first { clear } else { 0 };
    loop {
        t += 1;
        for lane in &mut lanes {
            lane.retire(t);
        }
        // (A frame of no box: its end marker comes at clock 1, and is seen from clock 2.)
        let marked = n > 0 || t > 1;
        // The registers' next values, from this clock's counts: a credit when one more box
        // leaves room; idle when every box is accepted, nothing is in flight and nothing is
        // launched on this clock.
        let credit_next = lanes.iter().all(|l| l.inflight + 1 < GRID_CREDITS);
        let mut idle_next =
            s.accepts.len() == n && lanes.iter().all(|lane| lane.inflight == 0) && marked;
        // The slow path.
        let more = large < walk.large.len();
        if idle && s.walked == 0 && (slow == Slow::Over || (slow == Slow::Fetch && !more)) {
            s.walked = t;
        }
        slow = match slow {
            Slow::Fetch if idle && more => {
                s.fetches.push((t + 1, walk.large[large].index));
                Slow::Address
            }
            Slow::Fetch if idle => Slow::Over,
            Slow::Address => Slow::Read,
            Slow::Read => Slow::Limit,
            Slow::Limit => Slow::Plan,
            Slow::Plan if walk.large[large].rounds.is_empty() => Slow::Over,
            Slow::Plan => Slow::Round(0),
            Slow::Round(r) if idle => {
                let l = &walk.large[large];
                let counts = &l.rounds[r * walk.lanes..(r + 1) * walk.lanes];
                probe(t + 1, counts, &mut lanes);
                idle_next = false;
                if (r + 1) * walk.lanes < l.rounds.len() {
                    Slow::Round(r + 1)
                } else if l.partners.iter().any(|&p| p > 0) {
                    Slow::Partner
                } else {
                    large += 1;
                    Slow::Fetch
                }
            }
            Slow::Partner if idle => {
                probe(t + 1, &walk.large[large].partners, &mut lanes);
                idle_next = false;
                large += 1;
                Slow::Fetch
            }
            other => other,
        };
        // Accept: the credit is set (and the list heads are clear).
        let accept = s.accepts.len() < n && credit && t > cleared_first;
        if accept {
            let k = s.accepts.len();
            s.accepts.push(t);
            let counts = &walk.visits[k * walk.lanes..(k + 1) * walk.lanes];
            probe(keys_out(t), counts, &mut lanes);
        }
        // The test queues: on a clock with no accept the lowest lane with a SAT test on
        // its output register issues it; each loads its output register from its stored
        // entries when it is empty or issued, and stores the key check's write.
        let mut issuer = (!accept)
            .then(|| lanes.iter().position(|l| l.queue.out.is_some()))
            .flatten();
        for (k, lane) in lanes.iter_mut().enumerate() {
            let stall = lane.queue.stored.len() >= GRID_TEST_STALL;
            if issuer == Some(k) {
                let c = lane.queue.out.take().expect("the issuer holds a SAT test");
                s.issues[c] = t;
                last_issue = t;
                issuer = None;
            }
            if lane.queue.out.is_none() {
                lane.queue.out = lane.queue.stored.pop_front();
            }
            if lane.in_check.front().is_some_and(|&(v, _)| v + 3 == t) {
                let (_, v) = lane.in_check.pop_front().unwrap();
                if walk.passes[v] {
                    lane.queue.stored.push_back(test_of[v]);
                }
            }
            let written = lane.enumerate(t, &walk.lists);
            if let Some(v) = lane.walk(t, stall) {
                s.visits[v] = t;
            }
            lane.list_queue.extend(written);
        }
        (credit, idle) = (credit_next, idle_next);
        if s.walked > 0 && lanes.iter().all(Lane::drained) {
            break;
        }
    }
    let load = s.accepts.last().map_or(1, |&a| keys_out(a)) + LAT_KEY_WRITE;
    let verdict = if tests == 0 {
        0
    } else {
        last_issue + GRID_ISSUE_TO_SAT + LAT_SAT
    };
    // (The clear after the walk waits for the one before the load.)
    let end = (s.walked.max(cleared_first + 1) + 1 + clear)
        .max(verdict)
        .max(load);
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
