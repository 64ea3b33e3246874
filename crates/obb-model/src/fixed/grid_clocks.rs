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
//!   heads are read; at K + 4 the box is entered and the lists it must walk are decided; at
//!   K + 5 they are written to the record queue, or, when it has none (or is large), it
//!   retires. Its record is in the queue from K + 6 = accept + `LAT_PROJECT` + `LAT_RECORD`.
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
//!   the candidate queue stores `GRID_CAND_STALL` entries or more (its output register not
//!   counted); a list it takes on such a clock leaves the list queue then.
//! - **Check.** A visit at V is read from the key table at V + 1, compared at V + 2 and, when the
//!   keys overlap, written to the candidate queue (`obb_rtl::pair_fifo`): stored from V + 3, on
//!   its output register from V + 4 at the earliest (`LAT_GRID_CHECK`).
//! - **Issue.** The candidate on the output register is issued on a clock when no box is accepted
//!   (the geometry tables' port A writes the arriving box); the output register takes the next
//!   stored entry on a clock it is empty or issued. An issued candidate is on the SAT's inputs
//!   `GRID_ISSUE_TO_SAT` clocks later.
//! - **Slow path.** A sequencer works when every box has been accepted and nothing is in
//!   flight (accepted or injected, not retired): call that clock *idle*. Per large box, in the
//!   chain's order: an idle clock fetches it, the next puts its address on port B (its keys
//!   and its successor, the next large box, are read), the next registers them, the next plans
//!   its window (or, too wide, ends the slow path); then each round is *launched* on an idle
//!   clock and injected on the next as a box whose keys span the round's cells, probed and
//!   walked as an arriving box is (its keys at the injection clock K, its record in the queue
//!   from K + `LAT_RECORD`, retiring at K + 5 when it has no list); then, if a large box
//!   follows, a record of one list, the rest of the chain, is launched the same way.
//! - **End.** The walk is over on the first idle clock with no large box left to fetch (or
//!   after a window too wide). From the clock after that, every list head is
//!   cleared for the next frame, one bucket of every bank a clock (`2^grid_hash_bits` clocks),
//!   while the last candidates leave; the frame ends with the later of the clear and the last
//!   verdict.

use super::cycles::{
    GRID_CAND_STALL, GRID_CREDITS, GRID_ISSUE_TO_SAT, LAT_KEY_WRITE, LAT_PROJECT, LAT_RECORD,
    LAT_SAT,
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
    /// Per large box fetched by the slow path, in order: the clock its address is on port B (its
    /// keys are read there), its index.
    pub fetches: Vec<(u64, usize)>,
    /// The clock the walk is over (the block's `walked` is high from it).
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

/// A record in the record queue: the clock the enumerator may load it, its lists (a range of
/// `GridWalk::lists`).
struct Record {
    ready: u64,
    lists: std::ops::Range<usize>,
}

/// The enumerator's record: its lists left, and whether the next is chosen (a clock's choice
/// is written on a later clock).
struct Enumerator {
    lists: std::ops::Range<usize>,
    chosen: bool,
}

/// The list queue's entries between the enumerator and the walker: a list's visits, and whether
/// it is its record's last.
const LIST_QUEUE: usize = 4;

/// The slow path's sequencer: what it does on its next idle clock (or its next clock).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Slow {
    Fetch,
    Address,
    Read,
    Plan,
    Round(usize),
    Partner,
    Over,
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
    // Boxes and injected rounds enter the probe at K: a record from K + LAT_RECORD, or a
    // retirement at K + 5. A record's lists are the next of `walk.lists` that hold its visits.
    let mut records: VecDeque<Record> = VecDeque::new();
    let mut retire_probe: VecDeque<u64> = VecDeque::new();
    let mut retire_walker: VecDeque<u64> = VecDeque::new();
    let mut next_list = 0usize;
    let mut probe =
        |k: u64, count: usize, records: &mut VecDeque<Record>, retire_probe: &mut VecDeque<u64>| {
            if count == 0 {
                retire_probe.push_back(k + LAT_RECORD - 1);
            } else {
                let first = next_list;
                let mut visits = 0;
                while visits < count {
                    visits += walk.lists[next_list];
                    next_list += 1;
                }
                debug_assert_eq!(visits, count, "a record's visits are whole lists");
                records.push_back(Record {
                    ready: k + LAT_RECORD,
                    lists: first..next_list,
                });
            }
        };
    // In flight: accepted or injected, and not retired before t.
    let mut inflight = 0usize;
    // The slow path: its state, the large box (in `walk.large`) and its next visit.
    let mut slow = Slow::Fetch;
    let mut large = 0usize;
    // The enumerator: the lists of its record left; the list queue (visits, last of its
    // record); the walker: its next visit, the visits left in its list (a held one included),
    // whether that list is its record's last.
    let mut enumerator: Option<Enumerator> = None;
    let mut list_queue: VecDeque<(usize, bool)> = VecDeque::new();
    let mut next_visit = 0usize;
    let mut left = 0usize;
    let mut last_list = false;
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
            }
        }
        // (A frame of no box: its end marker comes at clock 1, and is seen from clock 2.)
        let marked = n > 0 || t > 1;
        let idle = s.accepts.len() == n && inflight == 0 && marked;
        // The slow path.
        let more = large < walk.large.len();
        if idle && s.walked == 0 && (slow == Slow::Over || (slow == Slow::Fetch && !more)) {
            s.walked = t;
        }
        let mut inject =
            |count: usize, records: &mut VecDeque<Record>, retire_probe: &mut VecDeque<u64>| {
                inflight += 1;
                probe(t + 1, count, records, retire_probe);
            };
        slow = match slow {
            Slow::Fetch if idle && more => {
                s.fetches.push((t + 1, walk.large[large].index));
                Slow::Address
            }
            Slow::Fetch if idle => Slow::Over,
            Slow::Address => Slow::Read,
            Slow::Read => Slow::Plan,
            Slow::Plan if walk.large[large].rounds.is_empty() => Slow::Over,
            Slow::Plan => Slow::Round(0),
            Slow::Round(r) if idle => {
                let l = &walk.large[large];
                inject(l.rounds[r], &mut records, &mut retire_probe);
                if r + 1 < l.rounds.len() {
                    Slow::Round(r + 1)
                } else if l.partners > 0 {
                    Slow::Partner
                } else {
                    large += 1;
                    Slow::Fetch
                }
            }
            Slow::Partner if idle => {
                inject(walk.large[large].partners, &mut records, &mut retire_probe);
                large += 1;
                Slow::Fetch
            }
            other => other,
        };
        // Accept.
        let accept = s.accepts.len() < n && inflight < GRID_CREDITS;
        if accept {
            let k = s.accepts.len();
            s.accepts.push(t);
            inflight += 1;
            probe(keys_out(t), walk.visits[k], &mut records, &mut retire_probe);
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
        // Enumerate: a list chosen on a clock before is written when at most LIST_QUEUE - 2
        // lists are queued (not counting this clock's); on a clock it writes none, the
        // enumerator chooses its record's next list. It loads the next record on a clock it
        // holds none: its last list written, it is free from the next clock.
        let mut written = None;
        let mut wrote_last = false;
        let free = enumerator.is_none();
        if let Some(e) = enumerator.as_mut() {
            if e.chosen && list_queue.len() <= LIST_QUEUE - 2 {
                let l = e.lists.next().expect("a record has lists");
                wrote_last = e.lists.start == e.lists.end;
                written = Some((walk.lists[l], wrote_last));
                e.chosen = false;
            } else {
                e.chosen = true;
            }
        }
        if wrote_last {
            enumerator = None;
        }
        if free {
            enumerator = records
                .front()
                .is_some_and(|r| r.ready <= t)
                .then(|| Enumerator {
                    lists: records.pop_front().unwrap().lists,
                    chosen: false,
                });
        }
        // Walk: with no list left to go on, the walker takes the next queued (written before
        // t), or, its record's last list done, retires the record; one visit per clock unless
        // the candidate queue stalls it.
        if left == 0 {
            if last_list {
                retire_walker.push_back(t);
                last_list = false;
            }
            if let Some((visits, last)) = list_queue.pop_front() {
                left = visits;
                last_list = last;
            }
        }
        if left > 0 && !stall {
            left -= 1;
            s.visits.push(t);
            in_check.push_back((t, walk.passes[next_visit]));
            next_visit += 1;
        }
        list_queue.extend(written);
        let drained = in_check.is_empty() && queue.stored.is_empty() && queue.out.is_none();
        if s.walked > 0 && drained {
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
