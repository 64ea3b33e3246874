//! `obb_core`: the whole collision-detection core for one frame. The OBBs stream in (one per
//! clock), each is projected to its keys and margin and kept in the box tables; the broad
//! phase (`sweep` over the radix-sorted min x keys, or `walker`: brute, improved-sap) visits
//! index pairs; each visit's keys are checked on all three axes and its groups against the
//! mask (the `grid` sends pairs already checked); SAT tests go through the 15-axis SAT; colliding pairs leave on a valid/ready stream through a FIFO. The
//! pairs, the counters and the clock count equal `obb_model::fixed::ModelFrame::run`'s
//! (docs/hardware.md has the ports, the protocol and the cycle budget).
//!
//! | clock | stage |
//! | --- | --- |
//! | V | the walker's visit (i, j); the key table is read for i (port A) and j (port B) |
//! | V+1 | the keys, margins and groups registered |
//! | V+2 | keys overlap on x, y, z and the mask allows the groups: a SAT test (a < b) |
//! | V+3 | the geometry table is read for a (port A) and b (port B) |
//! | V+4 | the geometry registered |
//! | V+5 .. V+27 | the SAT pipeline; a hit enters the output FIFO |
//!
//! Every block RAM output goes straight into a register (the RAMB36E1's output register,
//! DO_REG, is not inferred by yosys): 2.45 ns from the clock, no logic after it.

use crate::box_load::BoxLoad;
use crate::geometry_fetch::GeometryFetch;
use crate::grid::GridPhase;
use crate::key_check::{KeyCheck, MASK};
use crate::pair_fifo::{self, PairFifo};
use crate::pipe::Pipe;
use crate::projection::{self, Projection, CENTER, HALF, MARGIN, ROT};
use crate::radix::{KeySort, KEY, VAL};
use crate::sat::{self, Sat};
use crate::sweep::{self, SweepWalker};
use crate::table_ram::TableRam;
use crate::walker::{self, WalkMode, Walker};
use obb_model::fixed::config::GROUP_BITS;
use obb_model::fixed::cycles::{GRID_ISSUE_TO_SAT, LAT_BROAD, LAT_SAT};
use obb_model::fixed::{BroadPhase, HwConfig};
use rust_hdl::prelude::*;

/// Width of the status counters.
pub const COUNT: usize = 40;
/// Width of a box index on the pair stream.
pub const INDEX: usize = VAL;
const GROUP: usize = GROUP_BITS as usize;
/// A pair in the output FIFO: a above b.
const PAIR: usize = 2 * INDEX;
/// Entries of the pair FIFO, and the fill at which the broad phase stalls: the pairs in flight
/// behind it still fit: the clock that registers the stall, the visits a walker makes after it
/// (`sweep::RUN_ON`, `walker::RUN_ON`), and those in the key check, the geometry read and the
/// SAT (`LAT_BROAD + sat::LATENCY`); the grid issues no SAT test on a stalled clock, and has
/// its issue, geometry read and SAT in flight (`GRID_ISSUE_TO_SAT + sat::LATENCY`).
pub const FIFO_DEPTH: u64 = pair_fifo::DEPTH;
pub const FIFO_STALL: u64 = 32;
const _: () = assert!(sat::LATENCY == LAT_SAT);
/// Clocks from the key check's verdict (`KeyCheck::test_valid`) to the SAT's inputs: the
/// geometry read (`g_*`) and registered (`h_*`).
const CHECK_TO_SAT: usize = 3;
// The model's visit-to-SAT latency: the keys read and registered, then the above.
const _: () = assert!(LAT_BROAD == 2 + CHECK_TO_SAT as u64);
const _: () = assert!(FIFO_STALL + 1 + sweep::RUN_ON + LAT_BROAD + sat::LATENCY <= FIFO_DEPTH);
const _: () = assert!(FIFO_STALL + 1 + walker::RUN_ON + LAT_BROAD + sat::LATENCY <= FIFO_DEPTH);
const _: () = assert!(FIFO_STALL + 1 + GRID_ISSUE_TO_SAT + sat::LATENCY <= FIFO_DEPTH);
/// Clocks after the walker's last visit until its SAT verdict is in the FIFO.
const DRAIN: u64 = LAT_BROAD + sat::LATENCY - 1;
/// Grid: clocks after a SAT test's issue until its SAT verdict is in the FIFO.
const GRID_DRAIN: u64 = GRID_ISSUE_TO_SAT + sat::LATENCY - 1;

/// Address bits of the per-box tables and the sort for `cfg`: `capacity` entries, twice that
/// with improved-sap (which sorts two end points per box); at least `radix::MIN_ADDRESS`,
/// for the sort's counters also count its bins.
pub fn address_bits(cfg: &HwConfig) -> usize {
    let entries = match cfg.broad_phase {
        BroadPhase::ImprovedSap => 2 * cfg.capacity,
        _ => cfg.capacity,
    };
    (entries.next_power_of_two().trailing_zeros() as usize).max(crate::radix::MIN_ADDRESS)
}

/// Key bits of the radix sort: end point keys take one bit more (min before max).
pub fn sort_key_bits(cfg: &HwConfig) -> u32 {
    match cfg.broad_phase {
        BroadPhase::ImprovedSap => cfg.key_bits + 1,
        _ => cfg.key_bits,
    }
}

#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum CoreState {
    Idle,
    /// Boxes accepted on the input stream.
    Load,
    /// The last keys leave the projection pipeline.
    Project,
    /// Sweep: the radix sort of the min x keys.
    Sort,
    Walk,
    /// The last visits pass the SAT.
    Drain,
    Done,
}

#[derive(LogicBlock)]
pub struct ObbCore<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Pulse: clear the counters and begin a frame (boxes are accepted from the next clock).
    /// During a frame (up to the first clock of its `done`) it aborts that frame: from this
    /// clock no box is taken and no pair of it is offered, and the new frame begins once the old
    /// one has run out (docs/hardware.md, "Abort").
    pub frame_start: Signal<In, Bit>,
    /// With `frame_start` (grid, `resident_groups`): an update frame, which loads every box, the
    /// resident groups' first, and keeps those. Low: a haptic frame, which streams only the
    /// other groups' boxes (indices from the resident count on) and reports no pair of two
    /// resident groups. Ignored without resident groups.
    pub frame_update: Signal<In, Bit>,
    /// The OBB stream: a box is on the `obb_*` inputs; it is taken on a clock with `obb_ready`.
    pub obb_valid: Signal<In, Bit>,
    /// The core takes the box on the inputs this clock (while it loads and has room).
    pub obb_ready: Signal<Out, Bit>,
    /// Ends the frame: with its last box, or alone for an empty frame.
    pub obb_last: Signal<In, Bit>,
    /// The box's center, offset binary, in LSBs.
    pub obb_center: [Signal<In, Bits<CENTER>>; 3],
    /// The box's half-lengths, rounded up, in LSBs.
    pub obb_half: [Signal<In, Bits<HALF>>; 3],
    /// The box's axes, `obb_axes[3k + x]` entry x of axis k, Q1.f.
    pub obb_axes: [Signal<In, Signed<ROT>>; 9],
    /// The box's group.
    pub obb_group: Signal<In, Bits<GROUP>>,
    /// A pair is on `pair_a`, `pair_b`, held until taken (`pair_ready`).
    pub pair_valid: Signal<Out, Bit>,
    /// The receiver takes the pair this clock.
    pub pair_ready: Signal<In, Bit>,
    /// The pair's lower box index (its place in the load).
    pub pair_a: Signal<Out, Bits<INDEX>>,
    /// The pair's higher box index.
    pub pair_b: Signal<Out, Bits<INDEX>>,
    /// The frame is computed and every pair has left; held until the next `frame_start`.
    pub done: Signal<Out, Bit>,
    /// A frame is under way (from `frame_start` until `done`), or an aborted one runs out.
    pub busy: Signal<Out, Bit>,
    /// Sticky for the frame: more boxes than `capacity` arrived, or (grid) a large box's window
    /// spans more than `MAX_WINDOW` cells on an axis: the frame is incomplete. From then on it
    /// reports and counts nothing; with the grid, which reports pairs while boxes arrive, pairs
    /// sent before are true pairs.
    pub capacity_exceeded: Signal<Out, Bit>,
    /// Sticky for the frame: a pair (or, with the grid, a SAT test) was lost to a full queue.
    /// Never: the broad phase stalls with room for everything in flight; the tests assert it.
    pub pair_overflow: Signal<Out, Bit>,
    /// Clocks from the first load clock to the last SAT verdict.
    pub cycles: Signal<Out, Bits<COUNT>>,
    /// Visits: index pairs the broad phase looked at (the glossary's *visit*).
    pub visits: Signal<Out, Bits<COUNT>>,
    /// SAT tests: pairs whose keys overlap, sent to the SAT.
    pub sat_tests: Signal<Out, Bits<COUNT>>,
    /// Pairs reported on the pair stream.
    pub pairs: Signal<Out, Bits<COUNT>>,
    // Configuration.
    sweep: Constant<Bit>,
    /// The grid: it walks while the boxes arrive, and its SAT tests come key-checked.
    grid_mode: Constant<Bit>,
    /// Improved-sap: the walker drives the radix sort, and the keys are checked only at the
    /// SAT's output (the paper's Algorithm 2 sends every pair it meets).
    sap: Constant<Bit>,
    mask: Constant<Bits<MASK>>,
    drain: Constant<Bits<8>>,
    grid_drain: Constant<Bits<8>>,
    // Stages. The broad phase's blocks are there only when configured (each list holds one
    // block or none): the radix sort for sweep and improved-sap, the sweep's walker, the other
    // walker for brute and improved-sap, the grid.
    projection: Projection,
    radix: Vec<KeySort<A, C>>,
    sweep_walker: Vec<SweepWalker<A, C>>,
    walker: Vec<Walker<A, C>>,
    grid: Vec<GridPhase<A, C>>,
    _radixes: usize,
    _sweeps: usize,
    _walkers: usize,
    _grids: usize,
    // The key tables (`kmin`, `kmax` axis x of table t at `3 t + x`; `margin`, `group`): one
    // set for the sweep and the walkers; none with the grid, which keeps its own by lane.
    _key_tables: usize,
    sat: Sat,
    fifo: PairFifo<PAIR>,
    // Box tables: geometry written on load, keys, margin and group when projected.
    center: [TableRam<Bits<CENTER>, A>; 3],
    half: [TableRam<Bits<HALF>, A>; 3],
    axes: [TableRam<Signed<ROT>, A>; 9],
    kmin: Vec<TableRam<Bits<CENTER>, A>>,
    kmax: Vec<TableRam<Bits<CENTER>, A>>,
    margin: Vec<TableRam<Bits<MARGIN>, A>>,
    group: Vec<TableRam<Bits<GROUP>, A>>,
    /// The group alongside the projection pipeline.
    gdelay: Pipe<Bits<GROUP>, { projection::LATENCY as usize }>,
    // Control.
    state: DFF<CoreState>,
    /// The FIFO's `almost_full`, registered: the walker's stall.
    stall: DFF<Bit>,
    projected: DFF<Bits<C>>,
    over: DFF<Bit>,
    countdown: DFF<Bits<8>>,
    /// A frame is under way or has pairs to leave: a `frame_start` now aborts it.
    live: DFF<Bit>,
    /// An aborted frame runs out (silently, as one over capacity); then `restart_go` pulses and
    /// the new frame begins, an update frame if `restart_update`.
    restart: DFF<Bit>,
    restart_go: DFF<Bit>,
    restart_update: DFF<Bit>,
    /// Grid: clocks until the last issued SAT test's verdict is in the FIFO; none (registered,
    /// so that the walk's end is not a compare deep).
    pending: DFF<Bits<8>>,
    pending_none: DFF<Bit>,
    /// The frame began on the clock before: the radix sort's start. (Its first entry comes
    /// after the projection; registered, so that the begin's decision does not lengthen the
    /// sort's control paths.)
    began: DFF<Bit>,
    n_cycles: DFF<Bits<COUNT>>,
    n_visits: DFF<Bits<COUNT>>,
    n_tests: DFF<Bits<COUNT>>,
    n_pairs: DFF<Bits<COUNT>>,
    /// The load: which box is taken, at which index, and when the load ends.
    load: BoxLoad<A, C>,
    /// The key check (V+1 .. V+3): a visit's keys registered and compared, the SAT test.
    check: KeyCheck<A>,
    /// The geometry fetch (V+3 .. V+5): a SAT test's boxes read and registered, the SAT's
    /// inputs.
    fetch: GeometryFetch<A>,
    // The pair's indices alongside the SAT.
    tag_a: Pipe<Bits<A>, { sat::LATENCY as usize }>,
    tag_b: Pipe<Bits<A>, { sat::LATENCY as usize }>,
    /// The SAT test's keys overlap on all three axes (always, but with improved-sap), from the
    /// key check to the SAT's verdict.
    k_overlap: Pipe<Bit, { CHECK_TO_SAT + sat::LATENCY as usize }>,
    // Combinational.
    // The broad phase: the walk starts; the visit (i, j) and the key table's addresses; the
    // walk is over. From the sweep walker or the other one, as configured.
    walk_start: Signal<Local, Bit>,
    visit: Signal<Local, Bit>,
    vi: Signal<Local, Bits<A>>,
    vj: Signal<Local, Bits<A>>,
    a_addr: Signal<Local, Bits<A>>,
    b_addr: Signal<Local, Bits<A>>,
    walked: Signal<Local, Bit>,
    // The radix sort's inputs and outputs (zero without one).
    sort_in_valid: Signal<Local, Bit>,
    sort_in_key: Signal<Local, Bits<KEY>>,
    sort_in_val: Signal<Local, Bits<VAL>>,
    sort_start: Signal<Local, Bit>,
    sort_go: Signal<Local, Bit>,
    sort_done: Signal<Local, Bit>,
    sort_rd_addr: Signal<Local, Bits<A>>,
    sorted_key: Signal<Local, Bits<KEY>>,
    sorted_val: Signal<Local, Bits<VAL>>,
    /// The grid's outputs (idle without it).
    grid_credit: Signal<Local, Bit>,
    grid_test_valid: Signal<Local, Bit>,
    grid_test_a: Signal<Local, Bits<A>>,
    grid_test_b: Signal<Local, Bits<A>>,
    grid_test_ma: Signal<Local, Bits<MARGIN>>,
    grid_test_mb: Signal<Local, Bits<MARGIN>>,
    grid_finished: Signal<Local, Bit>,
    grid_too_wide: Signal<Local, Bit>,
    /// The grid's visits of two clocks before, counted (its register).
    grid_visits: Signal<Local, Bits<4>>,
    /// The projected box's table address.
    projected_at: Signal<Local, Bits<A>>,
    /// Grid: its SAT test goes to the geometry read this clock.
    issue: Signal<Local, Bit>,
    hit: Signal<Local, Bit>,
}

impl<const A: usize, const C: usize> ObbCore<A, C> {
    /// The core for configuration `cfg`, which must be valid and supported
    /// (`generate::check_supported`): brute or sweep, one lane, capacity within 2^A.
    pub fn new(cfg: &HwConfig) -> ObbCore<A, C> {
        assert!(C == A + 1, "counts need one bit more than addresses");
        let mode = match cfg.broad_phase {
            BroadPhase::ImprovedSap => WalkMode::ImprovedSap,
            _ => WalkMode::Brute,
        };
        // One block if the broad phase is one of `modes`, else none.
        let uses = |modes: &[BroadPhase]| usize::from(modes.contains(&cfg.broad_phase));
        let radixes = uses(&[BroadPhase::Sweep, BroadPhase::ImprovedSap]);
        let sweeps = uses(&[BroadPhase::Sweep]);
        let walkers = uses(&[BroadPhase::Brute, BroadPhase::ImprovedSap]);
        let grids = uses(&[BroadPhase::Grid]);
        let grid = cfg.broad_phase == BroadPhase::Grid;
        assert!(
            address_bits(cfg) <= A,
            "capacity fits the tables and the sort"
        );
        let mut mask = Bits::<MASK>::default();
        for g in 0..1u32 << GROUP {
            for h in 0..1u32 << GROUP {
                if cfg.groups.allows(g, h) {
                    mask = mask.replace_bit((g << GROUP | h) as usize, true);
                }
            }
        }
        ObbCore {
            clock: Default::default(),
            frame_start: Default::default(),
            frame_update: Default::default(),
            obb_valid: Default::default(),
            obb_ready: Default::default(),
            obb_last: Default::default(),
            obb_center: Default::default(),
            obb_half: Default::default(),
            obb_axes: Default::default(),
            obb_group: Default::default(),
            pair_valid: Default::default(),
            pair_ready: Default::default(),
            pair_a: Default::default(),
            pair_b: Default::default(),
            done: Default::default(),
            busy: Default::default(),
            pair_overflow: Default::default(),
            capacity_exceeded: Default::default(),
            cycles: Default::default(),
            visits: Default::default(),
            sat_tests: Default::default(),
            pairs: Default::default(),
            sweep: Constant::new(cfg.broad_phase == BroadPhase::Sweep),
            grid_mode: Constant::new(grid),
            sap: Constant::new(mode == WalkMode::ImprovedSap),
            mask: Constant::new(mask),
            drain: Constant::new(DRAIN.into()),
            grid_drain: Constant::new(GRID_DRAIN.into()),
            projection: Projection::new(cfg),
            radix: (0..radixes)
                .map(|_| KeySort::new(sort_key_bits(cfg), cfg.radix_digit_bits))
                .collect(),
            sweep_walker: (0..sweeps).map(|_| SweepWalker::default()).collect(),
            walker: (0..walkers).map(|_| Walker::new(mode)).collect(),
            grid: (0..grids).map(|_| GridPhase::new(cfg)).collect(),
            _radixes: radixes,
            _sweeps: sweeps,
            _walkers: walkers,
            _grids: grids,
            _key_tables: 1 - grids,
            sat: Sat::new(cfg),
            fifo: PairFifo::new(FIFO_STALL),
            center: Default::default(),
            half: Default::default(),
            axes: Default::default(),
            kmin: (0..3 * (1 - grids)).map(|_| Default::default()).collect(),
            kmax: (0..3 * (1 - grids)).map(|_| Default::default()).collect(),
            margin: (0..1 - grids).map(|_| Default::default()).collect(),
            group: (0..1 - grids).map(|_| Default::default()).collect(),
            gdelay: Default::default(),
            state: Default::default(),
            stall: Default::default(),
            projected: Default::default(),
            over: Default::default(),
            countdown: Default::default(),
            live: Default::default(),
            restart: Default::default(),
            restart_go: Default::default(),
            restart_update: Default::default(),
            pending: Default::default(),
            pending_none: Default::default(),
            began: Default::default(),
            n_cycles: Default::default(),
            n_visits: Default::default(),
            n_tests: Default::default(),
            n_pairs: Default::default(),
            load: BoxLoad::new(cfg),
            check: Default::default(),
            fetch: Default::default(),
            tag_a: Default::default(),
            tag_b: Default::default(),
            k_overlap: Default::default(),
            walk_start: Default::default(),
            visit: Default::default(),
            vi: Default::default(),
            vj: Default::default(),
            a_addr: Default::default(),
            b_addr: Default::default(),
            walked: Default::default(),
            sort_in_valid: Default::default(),
            sort_in_key: Default::default(),
            sort_in_val: Default::default(),
            sort_start: Default::default(),
            sort_go: Default::default(),
            sort_done: Default::default(),
            sort_rd_addr: Default::default(),
            sorted_key: Default::default(),
            sorted_val: Default::default(),
            grid_credit: Default::default(),
            grid_test_valid: Default::default(),
            grid_test_a: Default::default(),
            grid_test_b: Default::default(),
            grid_test_ma: Default::default(),
            grid_test_mb: Default::default(),
            grid_finished: Default::default(),
            grid_too_wide: Default::default(),
            grid_visits: Default::default(),
            projected_at: Default::default(),
            issue: Default::default(),
            hit: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for ObbCore<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            state,
            stall,
            projected,
            over,
            countdown,
            live,
            restart,
            restart_go,
            restart_update,
            n_cycles,
            n_visits,
            n_tests,
            n_pairs,
            pending,
            pending_none,
            began
        );
        clock!(self, clock, projection, load, check, fetch, sat, fifo);
        for k in 0..self._radixes {
            self.radix[k].clock.next = self.clock.val();
        }
        for k in 0..self._sweeps {
            self.sweep_walker[k].clock.next = self.clock.val();
        }
        for k in 0..self._walkers {
            self.walker[k].clock.next = self.clock.val();
        }
        for k in 0..self._grids {
            self.grid[k].clock.next = self.clock.val();
        }
        for x in 0..3 {
            self.center[x].clock.next = self.clock.val();
            self.half[x].clock.next = self.clock.val();
        }
        for t in 0..self._key_tables {
            for x in 0..3 {
                self.kmin[3 * t + x].clock.next = self.clock.val();
                self.kmax[3 * t + x].clock.next = self.clock.val();
            }
            self.margin[t].clock.next = self.clock.val();
            self.group[t].clock.next = self.clock.val();
        }
        for k in 0..9 {
            self.axes[k].clock.next = self.clock.val();
        }
        self.gdelay.clock.next = self.clock.val();
        self.k_overlap.clock.next = self.clock.val();
        self.tag_a.clock.next = self.clock.val();
        self.tag_b.clock.next = self.clock.val();

        // Load: a box is accepted while loading, stored at its index and projected. The grid
        // takes a box only with a record free for it (a box over capacity is taken and
        // dropped).
        // The blocks' outputs, or their idle values without them.
        self.grid_credit.next = false;
        self.grid_test_valid.next = false;
        self.grid_test_a.next = 0.into();
        self.grid_test_b.next = 0.into();
        self.grid_test_ma.next = 0.into();
        self.grid_test_mb.next = 0.into();
        self.grid_finished.next = false;
        self.grid_too_wide.next = false;
        self.grid_visits.next = 0.into();
        self.visit.next = false;
        self.vi.next = 0.into();
        self.vj.next = 0.into();
        self.a_addr.next = 0.into();
        self.b_addr.next = 0.into();
        self.walked.next = false;
        self.sort_done.next = false;
        self.sorted_key.next = 0.into();
        self.sorted_val.next = 0.into();
        self.sort_rd_addr.next = 0.into();
        self.sort_start.next = self.began.q.val();
        self.sort_go.next = false;
        self.sort_in_valid.next = false;
        self.sort_in_key.next = 0.into();
        self.sort_in_val.next = 0.into();
        for k in 0..self._radixes {
            self.sort_done.next = self.radix[k].done.val();
            self.sorted_key.next = self.radix[k].rd_key.val();
            self.sorted_val.next = self.radix[k].rd_val.val();
        }
        for k in 0..self._grids {
            self.grid_credit.next = self.grid[k].credit.val();
            self.grid_test_valid.next = self.grid[k].test_valid.val();
            self.grid_test_a.next = self.grid[k].test_a.val();
            self.grid_test_b.next = self.grid[k].test_b.val();
            self.grid_test_ma.next = self.grid[k].test_ma.val();
            self.grid_test_mb.next = self.grid[k].test_mb.val();
            self.grid_finished.next = self.grid[k].finished.val();
            self.grid_too_wide.next = self.grid[k].too_wide.val();
            self.grid_visits.next = self.grid[k].visits.val();
        }
        for k in 0..self._sweeps {
            self.sort_rd_addr.next = self.sweep_walker[k].rd_addr.val();
            self.visit.next = self.sweep_walker[k].visit.val();
            self.vi.next = self.sweep_walker[k].vi.val();
            self.vj.next = self.sweep_walker[k].vj.val();
            self.a_addr.next = self.sweep_walker[k].a_addr.val();
            self.b_addr.next = self.sweep_walker[k].b_addr.val();
            self.walked.next = self.sweep_walker[k].finished.val();
        }
        for k in 0..self._walkers {
            self.sort_rd_addr.next = self.walker[k].rd_addr.val();
            self.visit.next = self.walker[k].visit.val();
            self.vi.next = self.walker[k].vi.val();
            self.vj.next = self.walker[k].vj.val();
            self.a_addr.next = self.walker[k].a_addr.val();
            self.b_addr.next = self.walker[k].b_addr.val();
            self.walked.next = self.walker[k].finished.val();
            // Improved-sap: the walker drives the sort.
            if self.sap.val() {
                self.sort_start.next = self.began.q.val() | self.walker[k].sort_start.val();
                self.sort_go.next = self.walker[k].sort_go.val();
                self.sort_in_valid.next = self.walker[k].sort_valid.val();
                self.sort_in_key.next = self.walker[k].sort_key.val();
                self.sort_in_val.next = self.walker[k].sort_val.val();
            }
        }

        self.load.frame_start.next = self.frame_start.val();
        self.load.frame_update.next = self.frame_update.val();
        self.load.live.next = self.live.q.val();
        self.load.restart_go.next = self.restart_go.q.val();
        self.load.restart_update.next = self.restart_update.q.val();
        self.load.obb_valid.next = self.obb_valid.val();
        self.load.obb_last.next = self.obb_last.val();
        self.load.obb_group.next = self.obb_group.val();
        self.load.credit.next = self.grid_credit.val() | !self.grid_mode.val();
        self.obb_ready.next = self.load.obb_ready.val();
        for x in 0..3 {
            self.center[x].write_enable.next = self.load.accept.val();
            self.center[x].write_address.next = self.load.index.val();
            self.center[x].write_data.next = self.obb_center[x].val();
            self.half[x].write_enable.next = self.load.accept.val();
            self.half[x].write_address.next = self.load.index.val();
            self.half[x].write_data.next = self.obb_half[x].val();
            self.projection.center[x].next = self.obb_center[x].val();
            self.projection.half[x].next = self.obb_half[x].val();
        }
        for k in 0..9 {
            self.axes[k].write_enable.next = self.load.accept.val();
            self.axes[k].write_address.next = self.load.index.val();
            self.axes[k].write_data.next = self.obb_axes[k].val();
            self.projection.axes[k].next = self.obb_axes[k].val();
        }
        self.projection.valid_in.next = self.load.accept.val();
        self.gdelay.d.next = self.obb_group.val();
        if self.load.refused.val() {
            self.over.d.next = true;
        }

        // Projected: keys, margin and group stored at the box's index; sweep sorts min x.
        self.projected_at.next = bit_cast::<A, C>(self.projected.q.val());
        for t in 0..self._key_tables {
            for x in 0..3 {
                self.kmin[3 * t + x].write_enable.next = self.projection.valid_out.val();
                self.kmin[3 * t + x].write_address.next = self.projected_at.val();
                self.kmin[3 * t + x].write_data.next = self.projection.key_min[x].val();
                self.kmax[3 * t + x].write_enable.next = self.projection.valid_out.val();
                self.kmax[3 * t + x].write_address.next = self.projected_at.val();
                self.kmax[3 * t + x].write_data.next = self.projection.key_max[x].val();
            }
            self.margin[t].write_enable.next = self.projection.valid_out.val();
            self.margin[t].write_address.next = self.projected_at.val();
            self.margin[t].write_data.next = self.projection.margin.val();
            self.group[t].write_enable.next = self.projection.valid_out.val();
            self.group[t].write_address.next = self.projected_at.val();
            self.group[t].write_data.next = self.gdelay.q.val();
        }
        if self.sweep.val() {
            self.sort_in_valid.next = self.projection.valid_out.val();
            self.sort_in_key.next = bit_cast::<KEY, CENTER>(self.projection.key_min[0].val());
            self.sort_in_val.next = bit_cast::<VAL, C>(self.projected.q.val());
        }
        if self.projection.valid_out.val() {
            self.projected.d.next = self.projected.q.val() + 1;
        }
        // The grid probes each box as its keys arrive, and keeps its own copy of the keys
        // (banked by lane).
        for k in 0..self._grids {
            self.grid[k].start.next = self.load.frame_begin.val();
            self.grid[k].update.next = self.load.update.val();
            self.grid[k].accept.next = self.load.accept.val();
            self.grid[k].loaded.next = !self.load.loading.val() & !self.load.frame_begin.val();
            self.grid[k].key_valid.next = self.projection.valid_out.val();
            self.grid[k].key_index.next = bit_cast::<A, C>(self.projected.q.val());
            self.grid[k].key_min_x.next = self.projection.key_min[0].val();
            self.grid[k].key_min_y.next = self.projection.key_min[1].val();
            self.grid[k].key_min_z.next = self.projection.key_min[2].val();
            self.grid[k].key_max_x.next = self.projection.key_max[0].val();
            self.grid[k].key_max_y.next = self.projection.key_max[1].val();
            self.grid[k].key_max_z.next = self.projection.key_max[2].val();
            self.grid[k].key_margin.next = self.projection.margin.val();
            self.grid[k].key_group.next = self.gdelay.q.val();
        }

        // The broad phase: a walker reads the sorted entries and the key table.
        self.stall.d.next = self.fifo.almost_full.val();
        self.walk_start.next = false;
        for k in 0..self._sweeps {
            self.sweep_walker[k].n.next = self.load.loaded.val();
            self.sweep_walker[k].stall.next = self.stall.q.val();
            self.sweep_walker[k].rd_key.next = self.sorted_key.val();
            self.sweep_walker[k].rd_val.next = self.sorted_val.val();
            self.sweep_walker[k].a_max.next = self.kmax[0].read_data_a.val();
        }
        for k in 0..self._walkers {
            self.walker[k].n.next = self.load.loaded.val();
            self.walker[k].stall.next = self.stall.q.val();
            self.walker[k].rd_val.next = self.sorted_val.val();
            self.walker[k].sort_done.next = self.sort_done.val();
            self.walker[k].a_min_x.next = self.kmin[0].read_data_a.val();
            self.walker[k].a_min_y.next = self.kmin[1].read_data_a.val();
            self.walker[k].a_min_z.next = self.kmin[2].read_data_a.val();
            self.walker[k].a_max_x.next = self.kmax[0].read_data_a.val();
            self.walker[k].a_max_y.next = self.kmax[1].read_data_a.val();
            self.walker[k].a_max_z.next = self.kmax[2].read_data_a.val();
        }
        for t in 0..self._key_tables {
            for x in 0..3 {
                self.kmin[3 * t + x].read_address_a.next = self.a_addr.val();
                self.kmin[3 * t + x].read_address_b.next = self.b_addr.val();
                self.kmax[3 * t + x].read_address_a.next = self.a_addr.val();
                self.kmax[3 * t + x].read_address_b.next = self.b_addr.val();
            }
            self.margin[t].read_address_a.next = self.a_addr.val();
            self.margin[t].read_address_b.next = self.b_addr.val();
            self.group[t].read_address_a.next = self.a_addr.val();
            self.group[t].read_address_b.next = self.b_addr.val();
        }

        // V+1 .. V+3: the key check; the key table's outputs (zero without one) go to it.
        self.check.visit.next = self.visit.val();
        self.check.i.next = self.vi.val();
        self.check.j.next = self.vj.val();
        for x in 0..3 {
            self.check.min_a[x].next = 0.into();
            self.check.min_b[x].next = 0.into();
            self.check.max_a[x].next = 0.into();
            self.check.max_b[x].next = 0.into();
        }
        self.check.margin_a.next = 0.into();
        self.check.margin_b.next = 0.into();
        self.check.group_a.next = 0.into();
        self.check.group_b.next = 0.into();
        for t in 0..self._key_tables {
            for x in 0..3 {
                self.check.min_a[x].next = self.kmin[3 * t + x].read_data_a.val();
                self.check.min_b[x].next = self.kmin[3 * t + x].read_data_b.val();
                self.check.max_a[x].next = self.kmax[3 * t + x].read_data_a.val();
                self.check.max_b[x].next = self.kmax[3 * t + x].read_data_b.val();
            }
            self.check.margin_a.next = self.margin[t].read_data_a.val();
            self.check.margin_b.next = self.margin[t].read_data_b.val();
            self.check.group_a.next = self.group[t].read_data_a.val();
            self.check.group_b.next = self.group[t].read_data_b.val();
        }
        self.check.mask.next = self.mask.val();
        self.check.unchecked.next = self.sap.val();
        self.check.idle.next = self.grid_mode.val();
        if self.check.visited.val() & !self.over.q.val() {
            self.n_visits.d.next = self.n_visits.q.val() + 1;
        }
        // The grid's lanes visit several boxes a clock; it counts them (registered).
        if self.grid_mode.val() & !self.over.q.val() {
            self.n_visits.d.next =
                self.n_visits.q.val() + bit_cast::<COUNT, 4>(self.grid_visits.val());
        }
        self.k_overlap.d.next = self.check.overlap.val();

        // V+3: the geometry of a and b is read. The grid's SAT test is read on a clock that
        // accepts no box (the box's write takes port A) and when the pair FIFO has room.
        self.issue.next =
            self.grid_test_valid.val() & !self.load.accept.val() & !self.stall.q.val();
        for k in 0..self._grids {
            self.grid[k].test_ready.next = self.issue.val();
        }
        self.fetch.test_valid.next = self.check.test_valid.val();
        self.fetch.test_a.next = self.check.test_a.val();
        self.fetch.test_b.next = self.check.test_b.val();
        self.fetch.test_ma.next = self.check.test_ma.val();
        self.fetch.test_mb.next = self.check.test_mb.val();
        if self.grid_mode.val() {
            self.fetch.test_valid.next = self.issue.val();
            self.fetch.test_a.next = self.grid_test_a.val();
            self.fetch.test_b.next = self.grid_test_b.val();
            self.fetch.test_ma.next = self.grid_test_ma.val();
            self.fetch.test_mb.next = self.grid_test_mb.val();
        }
        for x in 0..3 {
            self.center[x].read_address_a.next = self.fetch.addr_a.val();
            self.center[x].read_address_b.next = self.fetch.addr_b.val();
            self.half[x].read_address_a.next = self.fetch.addr_a.val();
            self.half[x].read_address_b.next = self.fetch.addr_b.val();
            self.fetch.read_center_a[x].next = self.center[x].read_data_a.val();
            self.fetch.read_center_b[x].next = self.center[x].read_data_b.val();
            self.fetch.read_half_a[x].next = self.half[x].read_data_a.val();
            self.fetch.read_half_b[x].next = self.half[x].read_data_b.val();
        }
        for k in 0..9 {
            self.axes[k].read_address_a.next = self.fetch.addr_a.val();
            self.axes[k].read_address_b.next = self.fetch.addr_b.val();
            self.fetch.read_axes_a[k].next = self.axes[k].read_data_a.val();
            self.fetch.read_axes_b[k].next = self.axes[k].read_data_b.val();
        }
        if self.fetch.fetching.val() & !self.over.q.val() {
            self.n_tests.d.next = self.n_tests.q.val() + 1;
        }

        // V+5: the SAT; the indices ride alongside.
        self.sat.valid_in.next = self.fetch.valid.val();
        for x in 0..3 {
            self.sat.center_a[x].next = self.fetch.center_a[x].val();
            self.sat.center_b[x].next = self.fetch.center_b[x].val();
            self.sat.half_a[x].next = self.fetch.half_a[x].val();
            self.sat.half_b[x].next = self.fetch.half_b[x].val();
        }
        for k in 0..9 {
            self.sat.axes_a[k].next = self.fetch.axes_a[k].val();
            self.sat.axes_b[k].next = self.fetch.axes_b[k].val();
        }
        self.sat.margin_a.next = self.fetch.ma.val();
        self.sat.margin_b.next = self.fetch.mb.val();
        self.tag_a.d.next = self.fetch.a.val();
        self.tag_b.d.next = self.fetch.b.val();

        // V+27: a hit enters the FIFO; the stream takes pairs from it.
        // (A frame over capacity reports and counts nothing from then on; the grid walks it to
        // its end, so that its lists are clear for the next frame.)
        self.hit.next = self.sat.valid_out.val()
            & self.sat.hit.val()
            & (self.k_overlap.q.val() | self.grid_mode.val())
            & !self.over.q.val();
        self.fifo.write.next = self.hit.val();
        self.fifo.data_in.next = (bit_cast::<PAIR, A>(self.tag_a.q.val()) << 20_u64)
            | bit_cast::<PAIR, A>(self.tag_b.q.val());
        if self.hit.val() {
            self.n_pairs.d.next = self.n_pairs.q.val() + 1;
        }
        // An aborted frame's pairs are not offered; they are drained.
        self.pair_valid.next =
            self.fifo.valid.val() & !self.restart.q.val() & !self.load.frame_abort.val();
        self.pair_a.next = self.fifo.data_out.val().get_bits::<INDEX>(20);
        self.pair_b.next = self.fifo.data_out.val().get_bits::<INDEX>(0);
        self.fifo.ready.next =
            (self.pair_ready.val() & !self.load.frame_abort.val()) | self.restart.q.val();
        self.fifo.clear.next = self.load.frame_begin.val();
        self.pair_overflow.next = self.fifo.overflow.val();
        for k in 0..self._grids {
            self.pair_overflow.next = self.fifo.overflow.val() | self.grid[k].queue_overflow.val();
        }

        // Control and status.
        self.busy.next = ((self.state.q.val() != CoreState::Idle)
            & (self.state.q.val() != CoreState::Done))
            | self.restart.q.val();
        // A hit written on the edge into Done already makes the FIFO not empty.
        self.done.next =
            (self.state.q.val() == CoreState::Done) & self.fifo.empty.val() & !self.restart.q.val();
        self.capacity_exceeded.next = self.over.q.val() & !self.restart.q.val();
        // A large box's window too wide for the grid's slow path: the frame is incomplete, as
        // one over capacity is.
        if self.grid_too_wide.val() {
            self.over.d.next = true;
        }
        self.cycles.next = self.n_cycles.q.val();
        self.visits.next = self.n_visits.q.val();
        self.sat_tests.next = self.n_tests.q.val();
        self.pairs.next = self.n_pairs.q.val();
        if self.busy.val() {
            self.n_cycles.d.next = self.n_cycles.q.val() + 1;
        }
        match self.state.q.val() {
            CoreState::Idle => {}
            CoreState::Load => {
                if self.load.ended.val() | self.load.frame_abort.val() {
                    self.state.d.next = CoreState::Project;
                }
            }
            CoreState::Project => {
                // Every box is in the key table: sort (sweep) or walk (brute); a frame over
                // capacity ends here with no pairs.
                if self.projected.q.val() == self.load.loaded.val() {
                    if self.grid_mode.val() {
                        // (The grid walks while boxes arrive.)
                        self.state.d.next = CoreState::Walk;
                    } else if self.over.q.val() {
                        self.state.d.next = CoreState::Done;
                    } else if self.sweep.val() {
                        // (Improved-sap sorts in the walker, axis by axis.)
                        self.sort_go.next = true;
                        self.state.d.next = CoreState::Sort;
                    } else {
                        self.walk_start.next = true;
                        self.state.d.next = CoreState::Walk;
                    }
                }
            }
            CoreState::Sort => {
                // (Only the sweep sorts here.)
                if self.sort_done.val() & self.sweep.val() {
                    self.walk_start.next = true;
                    self.state.d.next = CoreState::Walk;
                }
            }
            CoreState::Walk => {
                if self.grid_mode.val() {
                    if self.grid_finished.val() & self.pending_none.q.val() & !self.issue.val() {
                        self.state.d.next = CoreState::Done;
                    }
                } else if self.walked.val() {
                    self.countdown.d.next = self.drain.val();
                    self.state.d.next = CoreState::Drain;
                }
            }
            CoreState::Drain => {
                self.countdown.d.next = self.countdown.q.val() - 1;
                if self.countdown.q.val() == 1 {
                    self.state.d.next = CoreState::Done;
                }
            }
            CoreState::Done => {}
        }
        if self.issue.val() {
            self.pending.d.next = self.grid_drain.val();
        } else if self.pending.q.val() != 0 {
            self.pending.d.next = self.pending.q.val() - 1;
        }
        self.pending_none.d.next = !self.issue.val() & (self.pending.q.val() < 2);
        self.began.d.next = self.load.frame_begin.val();
        // (After the states that set them: a local is read where it is written in the Verilog.)
        for k in 0..self._sweeps {
            self.sweep_walker[k].start.next = self.walk_start.val();
        }
        for k in 0..self._walkers {
            self.walker[k].start.next = self.walk_start.val();
        }
        for k in 0..self._radixes {
            self.radix[k].start.next = self.sort_start.val();
            self.radix[k].go.next = self.sort_go.val();
            self.radix[k].in_valid.next = self.sort_in_valid.val();
            self.radix[k].in_key.next = self.sort_in_key.val();
            self.radix[k].in_val.next = self.sort_in_val.val();
            self.radix[k].rd_addr.next = self.sort_rd_addr.val();
        }
        // The frame is over when its pairs have left; an aborted one begins the new frame then.
        if (self.state.q.val() == CoreState::Done) & self.fifo.empty.val() {
            self.live.d.next = false;
        }
        self.restart_go.d.next = false;
        if self.load.frame_abort.val() {
            self.over.d.next = true;
            self.restart.d.next = true;
            self.restart_update.d.next = self.frame_update.val();
        }
        // (`restart` stays up through the clock of `restart_go`, so that `done` does not rise.)
        if self.restart.q.val()
            & !self.restart_go.q.val()
            & (self.state.q.val() == CoreState::Done)
            & self.fifo.empty.val()
        {
            self.restart_go.d.next = true;
        }
        if self.load.frame_begin.val() {
            self.live.d.next = true;
            self.restart.d.next = false;
            self.state.d.next = CoreState::Load;
            self.projected.d.next = self.load.first.val();
            self.over.d.next = false;
            self.pending.d.next = 0.into();
            self.pending_none.d.next = true;
            self.n_cycles.d.next = 0.into();
            self.n_visits.d.next = 0.into();
            self.n_tests.d.next = 0.into();
            self.n_pairs.d.next = 0.into();
        }
    }
}
