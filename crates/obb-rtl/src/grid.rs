//! `GridPhase`: the grid broad phase (`broad_phase = "grid"`), the spatial hash of
//! `obb_model::fixed::grid` built while the boxes arrive, on the clocks of
//! `obb_model::fixed::grid_clocks` (docs/hardware.md, "The grid").
//!
//! | clock | stage |
//! | --- | --- |
//! | K | a box's keys leave the projection (`key_valid`) |
//! | K+1 to K+3 | `GridCells`: the window's cells, and per bank (cell coordinates mod 3) its cell's bucket and fingerprint |
//! | K+3 | the list heads of every bank and group are read (distributed RAM, at once) and registered |
//! | K+4 | the lists to walk decided; the box is entered in its home cell's list (the entry the box before wrote at K+3 forwarded); its entry picked per bank |
//! | K+5 | its entry (second successor, ORed over the banks) written; the lists to walk written to the record queue, or the box retires (registered, counted at K+6) |
//! | K+6 | the enumerator may load the record |
//! | K+7 | it chooses the record's first list |
//! | K+8 | it writes it to the list queue |
//! | K+9 | the walker may take it |
//!
//! Lists are stored at `lpl k + 27 h + b` for lane k, bank b and group h, so that every index
//! the Verilog needs is an expression of loop variables (rust-hdl's Verilog writer evaluates an
//! index with the loop variables alone, so `lpl` is the variable of a loop of one pass). The
//! enumerator writes them bank by bank, group by group, as the model walks them.
//!
//! The successor table holds each box's *second* successor (the box two places after it in its
//! list), and its block RAM's output is registered: a visit at V reads the entry of the box it
//! visits, which names the box to visit at V+2. So a list is two chains walked in turn, and the
//! walker still makes one visit per clock, in the list's order, while no path runs from the
//! block RAM's output through logic (its clock-to-output is most of a 4 ns clock). The list
//! heads, the record queue and the list queue carry each list's first two boxes. The next
//! visit is the first of the list's boxes known and not visited (at most two, held in
//! registers while a stall lasts), or the arriving second successor, or, the list over, the
//! list queue's next list. A visit's keys are read on port B of the block's own key table
//! (written as the boxes' keys arrive; the walking box's keys ride in the list queue), compared
//! two clocks later, registered and, if they overlap, written to the test queue
//! (`PairFifo`), which the core drains on clocks it does not accept a box. At the end of the
//! walk every bucket is written empty, one a clock, so that the next frame finds the lists
//! clear.
//!
//! A box larger than a cell (*large*) is entered in no list: at K+3 it joins the chain of large
//! boxes (`lnext` and `lnext2`, its first two, latest first) and its successor entry takes the
//! chain's old second. The slow path runs when the load is over and nothing is in flight
//! (*idle*, a register set from the clock before's counts): a sequencer fetches each large box
//! of the chain (its keys on port B, its entry: the large box two places on), plans its window,
//! and injects its *rounds* into the probe as boxes whose keys span two or three cells per axis (kind *round*: they read
//! lists and enter none; the key check takes the large box's keys, and passes a box only if its
//! home cell is in the round, so a list read in two rounds gives its pairs once); then, when
//! large boxes follow, one record of one list, the rest of the chain (kind *partner*: the key
//! check applies the group mask). A window of more than `MAX_WINDOW` cells on an axis ends the
//! slow path and raises the sticky `too_wide`: the frame is incomplete.
//!
//! With `resident_groups`, an update frame (`update` with `start`) clears every list head
//! before its load, and the clear after its walk (and every walk's) writes only the lists of
//! the groups that are not resident; the chain of large boxes as the resident boxes (loaded
//! first) left it is kept (`res_lnext`), and a haptic frame starts its chain from it and takes
//! the haptic mask, which pairs no two resident groups (docs/hardware.md, "Resident groups").
//!
//! With `lanes` walker lanes (a power of two up to 8), box i is on lane `i mod lanes`, as in the
//! model. The probe (K to K+5) is shared: every bucket has a list per group and lane, a box
//! reads every lane's lists and enters its own lane's (list l of lane k at `lpl k + l`, `lpl`
//! = 27 per group), and at K+5 it writes a record of each lane's lists to walk to that lane's
//! record queue (or retires there). From the record queue on, each lane has its own
//! enumerator, list queue, walker, key check and test queue, and its own banks of the
//! per-box tables (successor, keys, margin, group: box i at `i >> log2 lanes`), written as the
//! box's keys arrive, so that every walker reads its own. The large boxes chain per lane; the
//! slow path takes lane 0's chain, then lane 1's, and a record of the rest of the chains has
//! one list on every lane: the lane's chain as left. A box is accepted when the credit is set (a
//! register: on the clock before, every lane had fewer than `GRID_CREDITS - 1` boxes in flight,
//! so that one accepted then still finds room); the lowest lane with a SAT test on its queue's
//! output issues it.

use crate::box_queue::{BoxQueue, KIND};
use crate::dist_ram::DistRam;
use crate::grid_cells::{vec, GridCells, BUCKET, FP};
use crate::pair_fifo::{self, PairFifo};
use crate::projection::{CENTER, MARGIN};
use crate::radix::VAL;
use crate::resize::Resize;
use crate::table_ram::TableRam;
use obb_model::fixed::config::{GROUP_BITS, MAX_LANES};
use obb_model::fixed::cycles::{GRID_CREDITS, GRID_TEST_STALL};
use obb_model::fixed::grid::{GridShape, BANKS, MAX_WINDOW};
use obb_model::fixed::HwConfig;
use rust_hdl::prelude::*;

/// A list's owner cell: valid, mixed, fingerprint.
const META: usize = FP + 2;
const GROUP: usize = GROUP_BITS as usize;
/// The group mask: bit `8 g + h` says whether groups g and h are paired.
const MASK: usize = 1 << (2 * GROUP);
/// Records (boxes waiting for the walker): the credits bound them.
const SLOT: usize = 5;
const _: () = assert!(GRID_CREDITS <= 1 << SLOT && GRID_CREDITS.is_power_of_two());
/// Width of a box index in the test queue (as on the core's pair stream).
const INDEX: usize = VAL;
/// A SAT test: a, b (a < b), their margins.
const TEST_WORD: usize = 2 * INDEX + 2 * MARGIN;
const COUNT: usize = SLOT + 2;
/// The list queue between the enumerator and the walker: 4 entries (`LIST_QUEUE` of the model).
const LQ: usize = 2;

/// The slow path's sequencer: what it does on its next idle clock (or its next clock).
#[derive(Copy, Clone, Debug, PartialEq, LogicState)]
pub enum SlowState {
    /// Fetch the next large box (or, none left, be over).
    Fetch,
    /// Its address on the key tables' and the successor table's port B.
    Address,
    /// Register its keys, group, margin.
    Read,
    /// Its window's limit from its first cell; its entry, the chain's box two on, is read.
    Limit,
    /// Its window's first and last cells, the first round; too wide: over.
    Plan,
    /// Inject the round at `rr` (next clock), step to the next.
    Round,
    /// Inject the record of the rest of the chain (next clock).
    Partner,
    Over,
}
// The walker sees the queue's count registered: when it stalls, up to three visits are still in
// the key check, and the queue has room for them.
const _: () = assert!(GRID_TEST_STALL as u64 + 3 < pair_fifo::DEPTH);

#[derive(LogicBlock)]
pub struct GridPhase<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Pulse: a new frame (the list heads were cleared at the end of the last, but the
    /// resident groups').
    pub start: Signal<In, Bit>,
    /// With `start`, the frame is an update frame (`resident_groups`): it clears every list
    /// head before its first box, and loads the resident groups. Without, with resident groups,
    /// a haptic frame: the resident lists and chain of large boxes stay, and the mask leaves
    /// out the pairs of two resident groups. (Without resident groups, ignored.)
    pub update: Signal<In, Bit>,
    /// A box is accepted this clock (the core's load).
    pub accept: Signal<In, Bit>,
    /// Every box of the frame has been accepted.
    pub loaded: Signal<In, Bit>,
    /// The credit (a register): on the clock before, every lane had fewer than
    /// `GRID_CREDITS - 1` boxes accepted and not retired. The core may accept.
    pub credit: Signal<Out, Bit>,
    /// A box's keys, margin and group from the projection are on the `key_*` inputs.
    pub key_valid: Signal<In, Bit>,
    /// The box's index.
    pub key_index: Signal<In, Bits<A>>,
    // The keys come axis by axis, not as arrays: the core holds the block in a list, and
    // rust-hdl emits an array port of a listed block wrongly.
    /// The box's min key on x.
    pub key_min_x: Signal<In, Bits<CENTER>>,
    /// The box's min key on y.
    pub key_min_y: Signal<In, Bits<CENTER>>,
    /// The box's min key on z.
    pub key_min_z: Signal<In, Bits<CENTER>>,
    /// The box's max key on x.
    pub key_max_x: Signal<In, Bits<CENTER>>,
    /// The box's max key on y.
    pub key_max_y: Signal<In, Bits<CENTER>>,
    /// The box's max key on z.
    pub key_max_z: Signal<In, Bits<CENTER>>,
    /// The box's projection margin.
    pub key_margin: Signal<In, Bits<MARGIN>>,
    /// The box's group.
    pub key_group: Signal<In, Bits<GROUP>>,
    /// The visits made this clock: bit k, lane k visits (for the tests: the core counts
    /// `visits`). Lane k's boxes are in `visit_i{k/2}` and `visit_j{k/2}` from bit
    /// `32 (k mod 2)`.
    pub visit: Signal<Out, Bits<8>>,
    /// Lanes 0 and 1: the walking box i of their visits (32 bits a lane).
    pub visit_i0: Signal<Out, Bits<64>>,
    /// Lanes 2 and 3: the walking box i of their visits (32 bits a lane).
    pub visit_i1: Signal<Out, Bits<64>>,
    /// Lanes 4 and 5: the walking box i of their visits (32 bits a lane).
    pub visit_i2: Signal<Out, Bits<64>>,
    /// Lanes 6 and 7: the walking box i of their visits (32 bits a lane).
    pub visit_i3: Signal<Out, Bits<64>>,
    /// Lanes 0 and 1: the visited box j of their visits (32 bits a lane).
    pub visit_j0: Signal<Out, Bits<64>>,
    /// Lanes 2 and 3: the visited box j of their visits (32 bits a lane).
    pub visit_j1: Signal<Out, Bits<64>>,
    /// Lanes 4 and 5: the visited box j of their visits (32 bits a lane).
    pub visit_j2: Signal<Out, Bits<64>>,
    /// Lanes 6 and 7: the visited box j of their visits (32 bits a lane).
    pub visit_j3: Signal<Out, Bits<64>>,
    /// The visits made two clocks before, counted (registered).
    pub visits: Signal<Out, Bits<4>>,
    /// The SAT test stream (first word fall-through): a SAT test is on the `test_*` outputs.
    pub test_valid: Signal<Out, Bit>,
    /// The core takes the SAT test this clock.
    pub test_ready: Signal<In, Bit>,
    /// The SAT test's lower box index.
    pub test_a: Signal<Out, Bits<A>>,
    /// The SAT test's higher box index.
    pub test_b: Signal<Out, Bits<A>>,
    /// The projection margin of box `test_a`.
    pub test_ma: Signal<Out, Bits<MARGIN>>,
    /// The projection margin of box `test_b`.
    pub test_mb: Signal<Out, Bits<MARGIN>>,
    /// Every box has retired and the slow path is done: the walk is over (the list heads are
    /// being cleared).
    pub walked: Signal<Out, Bit>,
    /// The list heads are clear, the test queue is empty: the grid's frame is over.
    pub finished: Signal<Out, Bit>,
    /// Sticky for the frame: a large box's window spans more than `MAX_WINDOW` cells on an
    /// axis; the slow path stopped, the frame is incomplete.
    pub too_wide: Signal<Out, Bit>,
    /// Sticky for the frame: a lane's SAT test queue was written full (a test lost); never, as
    /// the lanes stall at `GRID_TEST_STALL` with room for the tests in flight.
    pub queue_overflow: Signal<Out, Bit>,
    /// The lanes' queue overflows, ORed.
    lanes_overflow: Signal<Local, Bit>,
    // Configuration.
    // Groups with lists (`grid_groups`); walker lanes; lists per lane (27 per group) and in
    // all.
    _groups: usize,
    _lanes: usize,
    _lpl: usize,
    _lpl_end: usize,
    _lists: usize,
    // A box's lane: its index's low bits (`lane_mask`), one lane's value; its address in its
    // lane's banks of the per-box tables: the index shifted right.
    lane_mask: Constant<Bits<C>>,
    lane_id: Vec<Constant<Bits<C>>>,
    key_lane_mask: Constant<Bits<A>>,
    key_lane_id: Vec<Constant<Bits<A>>>,
    lane_shift: Constant<Bits<8>>,
    // Per lane: its bit in `visit`, its place in `visit_i0` and the others.
    lane_bit: Vec<Constant<Bits<8>>>,
    lane_at: Vec<Constant<Bits<8>>>,
    last_bucket: Constant<Bits<BUCKET>>,
    // The group mask of an update (or any) frame, and of a haptic frame.
    mask: Constant<Bits<MASK>>,
    haptic_mask: Constant<Bits<MASK>>,
    // Resident groups (`resident_groups`): bit g for group g; any at all; per group with
    // lists, whether it is not resident (its lists are cleared after every frame).
    resident_set: Constant<Bits<8>>,
    has_resident: Constant<Bit>,
    group_streamed: Vec<Constant<Bit>>,
    /// The bits of `inflight` at or above `GRID_CREDITS` (a power of two): none set, a credit
    /// is left. (A mask, not a compare: a compare is a carry chain in synthesis.)
    credits_used: Constant<Bits<COUNT>>,
    // A successor's or a record head's flag bit (`2^A`); the bits below it.
    top: Constant<Bits<C>>,
    index_mask: Constant<Bits<C>>,
    /// Per list (stored at `27 h + b`): its group h.
    list_group: Vec<Constant<Bits<GROUP>>>,
    /// The bits of a box's group that name its list: all of them, or none with one list for
    /// every group (`grid_group_lists = false`).
    group_keep: Constant<Bits<GROUP>>,
    // log2 of the cell edge; the widest span of a large box in cells (`MAX_WINDOW - 2`).
    cell_bits: Constant<Bits<8>>,
    max_span: Constant<Bits<CENTER>>,
    /// The SAT test's fields' places in the queue's word.
    at_a: Constant<Bits<8>>,
    at_b: Constant<Bits<8>>,
    at_ma: Constant<Bits<8>>,
    /// K+1 to K+3: the window's cells, banks, buckets, fingerprints.
    cells: GridCells,

    // The box alongside: K+1.
    s1_valid: DFF<Bit>,
    s1_index: DFF<Bits<C>>,
    s1_min: [DFF<Bits<CENTER>>; 3],
    s1_max: [DFF<Bits<CENTER>>; 3],
    s1_margin: DFF<Bits<MARGIN>>,
    s1_group: DFF<Bits<GROUP>>,
    s1_kind: DFF<Bits<KIND>>,
    // K+2.
    s2_valid: DFF<Bit>,
    s2_index: DFF<Bits<C>>,
    s2_min: [DFF<Bits<CENTER>>; 3],
    s2_max: [DFF<Bits<CENTER>>; 3],
    s2_margin: DFF<Bits<MARGIN>>,
    s2_group: DFF<Bits<GROUP>>,
    s2_kind: DFF<Bits<KIND>>,
    // K+3.
    s3_valid: DFF<Bit>,
    s3_index: DFF<Bits<C>>,
    s3_min: [DFF<Bits<CENTER>>; 3],
    s3_max: [DFF<Bits<CENTER>>; 3],
    s3_margin: DFF<Bits<MARGIN>>,
    s3_group: DFF<Bits<GROUP>>,
    s3_kind: DFF<Bits<KIND>>,
    /// The mask's bits for the box's group: bit h pairs it with group h.
    s3_allowed: DFF<Bits<MASK>>,
    /// Per lane: the box is on it (one-hot), at K+3, K+4, K+5.
    s3_lane: Vec<DFF<Bit>>,
    s4_lane: Vec<DFF<Bit>>,
    s5_lane: Vec<DFF<Bit>>,
    // K+4: the box; per list its first two boxes and owner as read, walk it if the owner allows, enter
    // it; per bank the bucket and the fingerprint.
    s4_valid: DFF<Bit>,
    s4_index: DFF<Bits<C>>,
    s4_min: [DFF<Bits<CENTER>>; 3],
    s4_max: [DFF<Bits<CENTER>>; 3],
    s4_margin: DFF<Bits<MARGIN>>,
    s4_kind: DFF<Bits<KIND>>,
    s4_meta: Vec<DFF<Bits<META>>>,
    s4_old: Vec<DFF<Bits<C>>>,
    s4_old2: Vec<DFF<Bits<C>>>,
    s4_walk: Vec<DFF<Bit>>,
    s4_enter: Vec<DFF<Bit>>,
    s4_bucket: [DFF<Bits<BUCKET>>; 27],
    s4_fp: [DFF<Bits<FP>>; 27],
    /// Per list: the box before wrote its entry in the bucket this box read (K+3), which the
    /// read missed: it is forwarded. (Registered: at K+4 it only picks.)
    s4_fwd: Vec<DFF<Bit>>,
    s4_home_fp: DFF<Bits<FP>>,
    s4_large: DFF<Bit>,
    s4_lprev: DFF<Bits<C>>,
    // K+5.
    s5_valid: DFF<Bit>,
    s5_index: DFF<Bits<C>>,
    s5_min: [DFF<Bits<CENTER>>; 3],
    s5_max: [DFF<Bits<CENTER>>; 3],
    s5_margin: DFF<Bits<MARGIN>>,
    s5_kind: DFF<Bits<KIND>>,
    s5_live: Vec<DFF<Bit>>,
    s5_head: Vec<DFF<Bits<C>>>,
    s5_head2: Vec<DFF<Bits<C>>>,
    /// Per bank: the old second of the list the box entered there, if that list held a box
    /// (zero in every other bank): the box's entry. Picked among the bank's lists at K+4, so
    /// that K+5 only ORs the banks (one pick of all 81 lists at K+5 took three levels of wide
    /// LUTs before the successor table).
    s5_entry: Vec<DFF<Bits<C>>>,
    /// Per list: the owner the box wrote (forwarded to the next box).
    s5_meta_w: Vec<DFF<Bits<META>>>,
    // A large box arrived: the chain's old second is its entry (zero for any other box).
    s5_large: DFF<Bit>,
    s5_lprev: DFF<Bits<C>>,
    // Memories.
    // Per list: the owner (valid, mixed, fingerprint) and the latest box, by bucket.
    meta: Vec<DistRam<Bits<META>, BUCKET>>,
    head: Vec<DistRam<Bits<C>, BUCKET>>,
    /// Per list: the box after the latest (its second), by bucket.
    head2: Vec<DistRam<Bits<C>, BUCKET>>,
    // Per lane, the bank of the per-box tables of the lane's boxes (box i at `i >> lane_shift`):
    // each box's second successor on its list (the top bit: there is one); its keys (axis x of
    // lane k at `3 k + x`), margin and group, written as the box's keys arrive and read by the
    // lane's walker.
    succ: Vec<TableRam<Bits<C>, C>>,
    kt_min: Vec<TableRam<Bits<CENTER>, C>>,
    kt_max: Vec<TableRam<Bits<CENTER>, C>>,
    kt_margin: Vec<TableRam<Bits<MARGIN>, C>>,
    kt_group: Vec<TableRam<Bits<GROUP>, C>>,
    // From here on, a lane's own (per lane `k`; per list of lane k at `lpl k + 27 h + b`; per
    // lane and axis at `3 k + x`).
    /// The record queue: per list its head (top bit: walk it), and the box's index, keys, margin.
    rec: Vec<DistRam<Bits<C>, SLOT>>,
    /// Per list: its second box (top bit: there is one).
    rec2: Vec<DistRam<Bits<C>, SLOT>>,
    rec_box: Vec<BoxQueue<SLOT, C>>,
    wp: Vec<DFF<Bits<SLOT>>>,
    rp: Vec<DFF<Bits<SLOT>>>,
    count: Vec<DFF<Bits<COUNT>>>,
    inflight: Vec<DFF<Bits<COUNT>>>,
    // The enumerator: it holds a record; its lists left, their heads; the box's index, keys,
    // margin, kind.
    e_busy: Vec<DFF<Bit>>,
    e_rem: Vec<DFF<Bit>>,
    e_head: Vec<DFF<Bits<C>>>,
    e_head2: Vec<DFF<Bits<C>>>,
    /// The list chosen on a clock before, to write next: one-hot.
    e_chosen: Vec<DFF<Bit>>,
    e_sel: Vec<DFF<Bit>>,
    e_index: Vec<DFF<Bits<C>>>,
    e_min: Vec<DFF<Bits<CENTER>>>,
    e_max: Vec<DFF<Bits<CENTER>>>,
    e_margin: Vec<DFF<Bits<MARGIN>>>,
    e_kind: Vec<DFF<Bits<KIND>>>,
    // The list queue: per entry a list's head, its box, whether it is its record's last. The
    // heads are flip-flops (`DistRam::registers`): the walker's next visit is picked from
    // them, and synthesis maps that pick for its depth only when it sees the read as logic.
    lq_head: Vec<DistRam<Bits<C>, LQ>>,
    lq_head2: Vec<DistRam<Bits<C>, LQ>>,
    lq_box: Vec<BoxQueue<LQ, C>>,
    lq_last: Vec<DistRam<Bit, LQ>>,
    lq_wp: Vec<DFF<Bits<LQ>>>,
    lq_rp: Vec<DFF<Bits<LQ>>>,
    /// Its fill as a thermometer code (`3 k + m`): more than m lists are queued (at most three:
    /// the enumerator writes at two or fewer). Each bit's next value is one LUT of the walker's
    /// take.
    lq_fill: Vec<DFF<Bit>>,
    // The walker: the list's box, whether the list is its record's last.
    cur_valid: Vec<DFF<Bit>>,
    cur_last: Vec<DFF<Bit>>,
    cur_index: Vec<DFF<Bits<C>>>,
    cur_min: Vec<DFF<Bits<CENTER>>>,
    cur_max: Vec<DFF<Bits<CENTER>>>,
    cur_margin: Vec<DFF<Bits<MARGIN>>>,
    cur_kind: Vec<DFF<Bits<KIND>>>,
    // The successor table's output, registered: the second successor of the box read two
    // clocks before. A visit one clock before (`r1`) reads it; `arrive_q`: a visit two clocks
    // before read it and it names a box (its flag), registered with it so that the walker's
    // decisions start at registers (one LUT follows the block RAM's output).
    succ_q: Vec<DFF<Bits<C>>>,
    r1: Vec<DFF<Bit>>,
    arrive_q: Vec<DFF<Bit>>,
    // The list's next boxes known and not yet visited, in order (at most two: the successor
    // of a box arrives only after the box before it was visited).
    q0v: Vec<DFF<Bit>>,
    q0: Vec<DFF<Bits<C>>>,
    q1v: Vec<DFF<Bit>>,
    q1: Vec<DFF<Bits<C>>>,
    // The key check: the visit (V+1), the keys of both boxes (V+2), the verdict (V+3).
    v1_valid: Vec<DFF<Bit>>,
    v1_i: Vec<DFF<Bits<C>>>,
    v1_j: Vec<DFF<Bits<C>>>,
    v1_min: Vec<DFF<Bits<CENTER>>>,
    v1_max: Vec<DFF<Bits<CENTER>>>,
    v1_margin: Vec<DFF<Bits<MARGIN>>>,
    v1_kind: Vec<DFF<Bits<KIND>>>,
    v2_valid: Vec<DFF<Bit>>,
    v2_i: Vec<DFF<Bits<C>>>,
    v2_j: Vec<DFF<Bits<C>>>,
    v2_min_i: Vec<DFF<Bits<CENTER>>>,
    v2_max_i: Vec<DFF<Bits<CENTER>>>,
    v2_min_j: Vec<DFF<Bits<CENTER>>>,
    v2_max_j: Vec<DFF<Bits<CENTER>>>,
    v2_margin_i: Vec<DFF<Bits<MARGIN>>>,
    v2_margin_j: Vec<DFF<Bits<MARGIN>>>,
    v2_kind: Vec<DFF<Bits<KIND>>>,
    // A round passes a visited box whose home cell, its first cell j plus one, lies within
    // the round's first and last cells. All three are compared less one, so that no adder
    // stands behind the key table's block RAM (j is its key shifted) nor before the
    // compares: the round's first cell less one (zero for cell zero: every home is at least
    // one), its last cell less one (its largest key shifted), j; the visited box's group.
    v2_wl: Vec<DFF<Bits<CENTER>>>,
    v2_wh: Vec<DFF<Bits<CENTER>>>,
    v2_jc: Vec<DFF<Bits<CENTER>>>,
    v2_group_j: Vec<DFF<Bits<GROUP>>>,
    // V+3: the key check's terms, registered (the visit is valid, the keys overlap, the visited
    // box's home is in the round or need not be, the mask pairs the groups or need not), and
    // the SAT test: only one LUT follows the compares' carry chains, and the verdict (`pass`,
    // their AND) is a LUT ahead of the queue's count, which the write picks.
    v3_valid: Vec<DFF<Bit>>,
    v3_overlap: Vec<DFF<Bit>>,
    v3_home: Vec<DFF<Bit>>,
    v3_anywhere: Vec<DFF<Bit>>,
    v3_mask: Vec<DFF<Bit>>,
    v3_word: Vec<DFF<Bits<TEST_WORD>>>,
    fifo: Vec<PairFifo<TEST_WORD>>,
    // End of frame.
    clearing: DFF<Bit>,
    cleared: DFF<Bit>,
    clear_at: DFF<Bits<BUCKET>>,
    // The slow path: the chain's next large box (top bit: there is one), the box on the path,
    // its keys, margin and group, its window's first cells and its cells less one, the round's
    // first cells and the window's cells after them (less one).
    slow: DFF<SlowState>,
    // Per lane (one-hot): the slow path's box is on it. The large boxes chain per lane
    // (`lnext`, `lnext2`); the slow path takes lane 0's chain, then lane 1's, and so on.
    slane: Vec<DFF<Bit>>,
    lnext: Vec<DFF<Bits<C>>>,
    lnext2: Vec<DFF<Bits<C>>>,
    lcur: DFF<Bits<C>>,
    lk_min: [DFF<Bits<CENTER>>; 3],
    // Its first cell plus the widest span (`Limit`, from `lk_min`: taken from the key tables'
    // reads through the lane's selection and the adder in one clock, it would be the
    // eight-lane core's slowest path): the window is too wide when its last cell is beyond (one
    // carry chain in `Plan`, not a difference and a compare).
    lk_lim: [DFF<Bits<CENTER>>; 3],
    lk_max: [DFF<Bits<CENTER>>; 3],
    lmargin: DFF<Bits<MARGIN>>,
    lgroup: DFF<Bits<GROUP>>,
    wlo: [DFF<Bits<CENTER>>; 3],
    wspan: [DFF<Bits<CENTER>>; 3],
    rr: [DFF<Bits<CENTER>>; 3],
    rleft: [DFF<Bits<CENTER>>; 3],
    wide: DFF<Bit>,
    /// The fetched box's address is on port B (`lcur`, through the walker's address multiplexer).
    fetch_q: DFF<Bit>,
    // The injected record (at K), its kind and its keys: registered, so that the probe's
    // first stage takes them through one multiplexer.
    inj: DFF<Bit>,
    inj_kind: DFF<Bits<KIND>>,
    inj_min: [DFF<Bits<CENTER>>; 3],
    inj_max: [DFF<Bits<CENTER>>; 3],
    // The visits made a clock before, counted, registered: so that the core's counter adds a
    // register, not the count (with eight lanes the two in one clock are 4 LUT levels and two
    // carry chains).
    visits_q: DFF<Bits<4>>,
    // Combinational.
    // The ports' keys as arrays: the arriving box's; per lane, the box read on its banks'
    // port B.
    key_min: [Signal<Local, Bits<CENTER>>; 3],
    key_max: [Signal<Local, Bits<CENTER>>; 3],
    rd_min: Vec<Signal<Local, Bits<CENTER>>>,
    rd_max: Vec<Signal<Local, Bits<CENTER>>>,
    rd_margin: Vec<Signal<Local, Bits<MARGIN>>>,
    rd_group: Vec<Signal<Local, Bits<GROUP>>>,
    // The slow path's lane's reads: each lane's masked by `slane` (one-hot), ORed.
    sel_min: [Signal<Local, Bits<CENTER>>; 3],
    sel_max: [Signal<Local, Bits<CENTER>>; 3],
    sel_margin: Signal<Local, Bits<MARGIN>>,
    sel_group: Signal<Local, Bits<GROUP>>,
    // The arriving box: per lane, it is on it; its address in its lane's banks.
    key_lane: Vec<Signal<Local, Bit>>,
    key_addr: Signal<Local, Bits<C>>,
    // Per lane: the address its walker reads (its `next_box`, shifted); the box's at K+5.
    rd_address: Vec<Signal<Local, Bits<C>>>,
    succ_addr: Signal<Local, Bits<C>>,
    allowed: Signal<Local, Bits<MASK>>,
    /// Per list: the box's mask bits shifted to the list's group.
    allow: Vec<Signal<Local, Bits<MASK>>>,
    /// K+4, per list: the entry the box before wrote is this box's (same bucket, written); the
    /// owner and the head the box sees; walk it; its owner after the entry.
    fwd: Vec<Signal<Local, Bit>>,
    /// K+3, per bank: its bucket is the one the box ahead (at K+4) writes.
    same: [Signal<Local, Bit>; 27],
    // K+4, per list, from the owner as read (`2 l`) and as forwarded (`2 l + 1`), side by side
    // so that the compares start at registers and the forwarding only picks: the owner, walk
    // the list, the owner after the entry.
    meta_src: Vec<Signal<Local, Bits<META>>>,
    live_src: Vec<Signal<Local, Bit>>,
    meta_new_src: Vec<Signal<Local, Bits<META>>>,
    meta_eff: Vec<Signal<Local, Bits<META>>>,
    old_eff: Vec<Signal<Local, Bits<C>>>,
    old_eff2: Vec<Signal<Local, Bits<C>>>,
    live: Vec<Signal<Local, Bit>>,
    meta_new: Vec<Signal<Local, Bits<META>>>,
    /// K+4: per list its old second if the box entered it (zero elsewhere: it entered one at
    /// most), their OR: the box's entry; the box has lists to walk. (Pure ORs, balanced by
    /// synthesis into trees.)
    succ_acc: Signal<Local, Bits<C>>,
    // K+4: per list, its old second if the box enters it and it holds a box; per bank, their OR.
    entry_pick: Vec<Signal<Local, Bits<C>>>,
    entry_acc: Vec<Signal<Local, Bits<C>>>,
    any_live: Vec<Signal<Local, Bit>>,
    // The enumerator's choice, in the walker's order (bank, then group): per list, a list of a
    // lower group is left in its bank (`group_prior`); a list is left in a bank before b
    // (`bank_prior[b]`, from the registered flags of the chunks of three banks before b's and of
    // the banks before b in its chunk); the list is the first left. Pure ANDs and ORs, which
    // synthesis balances into trees (written as `if`s, they became multiplexer chains).
    // (Per lane and bank at `27 k + b`, per chunk at `9 k + c`; `chunk_prior` at `10 k + c`.)
    bank_any: Vec<Signal<Local, Bit>>,
    group_prior: Vec<Signal<Local, Bit>>,
    chunk_prior: Vec<Signal<Local, Bit>>,
    bank_prior: Vec<Signal<Local, Bit>>,
    // Per bank and per chunk, a list is left in it, registered: the lists left but the chosen,
    // or the loaded record's lists.
    bank_next: Vec<Signal<Local, Bit>>,
    bank_load: Vec<Signal<Local, Bit>>,
    bank_left: Vec<DFF<Bit>>,
    chunk_next: Vec<Signal<Local, Bit>>,
    chunk_load: Vec<Signal<Local, Bit>>,
    chunk_left: Vec<DFF<Bit>>,
    e_first: Vec<Signal<Local, Bit>>,
    // A list is written to the list queue: its head (each list's masked by the one-hot choice,
    // then ORed); a list other than the chosen is left (none: it is the record's last).
    e_push: Vec<Signal<Local, Bit>>,
    e_pick: Vec<Signal<Local, Bits<C>>>,
    e_out: Vec<Signal<Local, Bits<C>>>,
    e_pick2: Vec<Signal<Local, Bits<C>>>,
    e_out2: Vec<Signal<Local, Bits<C>>>,
    e_more: Vec<Signal<Local, Bit>>,
    /// A record is loaded.
    e_load: Vec<Signal<Local, Bit>>,
    // The walker.
    // A box of the list arrives on the registered successor; a box is known to visit; the
    // box after it (and whether there is one).
    arrive: Vec<Signal<Local, Bit>>,
    avail: Vec<Signal<Local, Bit>>,
    after: Vec<Signal<Local, Bits<C>>>,
    after_v: Vec<Signal<Local, Bit>>,
    need: Vec<Signal<Local, Bit>>,
    retire_rec: Vec<Signal<Local, Bit>>,
    take: Vec<Signal<Local, Bit>>,
    rd_live: Vec<Signal<Local, Bit>>,
    // Credits and records: this clock's changes.
    // Each count's next value is selected among its neighbours, computed from the register
    // alone, so that the late enables only pick: an adder after them was a carry chain behind
    // the walker's and the enumerator's decisions. The selection is an AND-OR of masks (all
    // ones where the enable picks): a multiplexer of sums is folded back by synthesis into
    // one adder of a selected operand, the carry chain again.
    inflight_up: Signal<Local, Bit>,
    inflight_inc: Vec<Signal<Local, Bits<COUNT>>>,
    inflight_dec: Vec<Signal<Local, Bits<COUNT>>>,
    inflight_dec2: Vec<Signal<Local, Bits<COUNT>>>,
    // Masks of the early changes (the load's or the slow path's box, a probe's retirement):
    // they cancel, one more, one less. The values without and with a record's retirement,
    // which comes late from the walker's decision and only picks one of them.
    inflight_m: Vec<Signal<Local, Bits<COUNT>>>,
    inflight_n0: Vec<Signal<Local, Bits<COUNT>>>,
    inflight_n1: Vec<Signal<Local, Bits<COUNT>>>,
    count_inc: Vec<Signal<Local, Bits<COUNT>>>,
    count_dec: Vec<Signal<Local, Bits<COUNT>>>,
    // Masks: keep, one more, one less.
    count_m: Vec<Signal<Local, Bits<COUNT>>>,
    ones: Constant<Bits<COUNT>>,
    test_word: Vec<Signal<Local, Bits<TEST_WORD>>>,
    unpack_a: Signal<Local, Bits<TEST_WORD>>,
    unpack_b: Signal<Local, Bits<TEST_WORD>>,
    unpack_ma: Signal<Local, Bits<TEST_WORD>>,
    next_box: Vec<Signal<Local, Bits<C>>>,
    // The box's index with the flag bit, a list head: at K+3 (a large box joins the chain), at
    // K+4 (it enters a list), at K+5 (forwarded).
    entry: Signal<Local, Bits<C>>,
    entry4: Signal<Local, Bits<C>>,
    entry5: Signal<Local, Bits<C>>,
    next_ok: Vec<Signal<Local, Bit>>,
    go: Vec<Signal<Local, Bit>>,
    stall: Vec<Signal<Local, Bit>>,
    retire_probe: Vec<Signal<Local, Bit>>,
    /// The probe's retirement, registered (K+6): the count then follows from registers, not
    /// from the OR of the box's lists.
    retire_probe_q: Vec<DFF<Bit>>,
    rec_write: Vec<Signal<Local, Bit>>,
    overlap: Vec<Signal<Local, Bit>>,
    swap: Vec<Signal<Local, Bit>>,
    test_lo: Vec<Signal<Local, Bits<C>>>,
    test_hi: Vec<Signal<Local, Bits<C>>>,
    /// The SAT test's fields widened to the queue's word (`Resize`: no `bit_cast` in a loop).
    pack_lo: Vec<Resize<TEST_WORD, C>>,
    pack_hi: Vec<Resize<TEST_WORD, C>>,
    pack_mlo: Vec<Resize<TEST_WORD, MARGIN>>,
    pack_mhi: Vec<Resize<TEST_WORD, MARGIN>>,
    margin_lo: Vec<Signal<Local, Bits<MARGIN>>>,
    margin_hi: Vec<Signal<Local, Bits<MARGIN>>>,
    done_walk: Signal<Local, Bit>,
    // The slow path: nothing in flight after the load on the clock before, nothing launched
    // (a register, so that the counts and the sequencer are not one path), and its next
    // value; this clock fetches a large box, injects a record (and of which kind, with which
    // keys).
    idle: DFF<Bit>,
    idle_next: Signal<Local, Bit>,
    fetch: Signal<Local, Bit>,
    inject: Signal<Local, Bit>,
    inject_kind: Signal<Local, Bits<KIND>>,
    inject_min: [Signal<Local, Bits<CENTER>>; 3],
    inject_max: [Signal<Local, Bits<CENTER>>; 3],
    // Per axis: the cells left, the round's included, less two (`rleft`, kept by steps: a
    // difference would be a carry chain before the compares; less two, so that the plan's
    // difference needs no increment); the round has three cells; it is the
    // axis's last; the round's first cell plus 1, 2, 3; the cells left less 2, 3; masks (all
    // ones where the round has two, three cells: an AND-OR, which synthesis does not fold
    // into an adder of a selected operand); the next round's first cell and cells left.
    left: [Signal<Local, Bits<CENTER>>; 3],
    three_cells: [Signal<Local, Bit>; 3],
    last_round: [Signal<Local, Bit>; 3],
    rr_p1: [Signal<Local, Bits<CENTER>>; 3],
    rr_p2: [Signal<Local, Bits<CENTER>>; 3],
    rr_p3: [Signal<Local, Bits<CENTER>>; 3],
    left_m2: [Signal<Local, Bits<CENTER>>; 3],
    left_m3: [Signal<Local, Bits<CENTER>>; 3],
    two_m: [Signal<Local, Bits<CENTER>>; 3],
    three_m: [Signal<Local, Bits<CENTER>>; 3],
    next_rr: [Signal<Local, Bits<CENTER>>; 3],
    next_left: [Signal<Local, Bits<CENTER>>; 3],
    plan_span: [Signal<Local, Bits<CENTER>>; 3],
    // All ones; all but the low bit; all but the two low bits.
    center_ones: Constant<Bits<CENTER>>,
    above_one: Constant<Bits<CENTER>>,
    above_three: Constant<Bits<CENTER>>,
    plan_lo: [Signal<Local, Bits<CENTER>>; 3],
    plan_hi: [Signal<Local, Bits<CENTER>>; 3],
    plan_wide: Signal<Local, Bit>,
    /// K+3: a large arriving box joins the chain.
    large_in: Signal<Local, Bit>,
    /// V+2: the visited box's home is in the round; the mask pairs the groups. V+3: the pair
    /// passes.
    home_ok: Vec<Signal<Local, Bit>>,
    // The round's first cell; all ones unless it is cell zero.
    wl_cell: Vec<Signal<Local, Bits<CENTER>>>,
    wl_keep: Vec<Signal<Local, Bits<CENTER>>>,
    mask_row: Vec<Signal<Local, Bits<MASK>>>,
    mask_ok: Vec<Signal<Local, Bit>>,
    pass: Vec<Signal<Local, Bit>>,
    // The SAT test issued: per lane, a lower lane holds one (`lower[k]`, prefix ORs); the lane
    // issues; its word (zero unless it issues), their OR.
    lower: Vec<Signal<Local, Bit>>,
    issuer: Vec<Signal<Local, Bit>>,
    out_pick: Vec<Signal<Local, Bits<TEST_WORD>>>,
    out_word: Signal<Local, Bits<TEST_WORD>>,
    // The slow path's next large box: per lane, a lower lane's chain holds one (prefix ORs);
    // the lane's chain is the first that does; its head if so; their OR.
    lprior: Vec<Signal<Local, Bit>>,
    lfirst: Vec<Signal<Local, Bit>>,
    lpick: Vec<Signal<Local, Bits<C>>>,
    lhead: Signal<Local, Bits<C>>,
    // The visits' outputs, gathered lane by lane; the visits counted.
    visit_acc: Signal<Local, Bits<8>>,
    vis_pack_i: Vec<Signal<Local, Bits<64>>>,
    vis_pack_j: Vec<Signal<Local, Bits<64>>>,
    // The lanes' visits a clock before (bit k, lane k), and their counts in two-bit, then
    // four-bit fields (a tree: eight increments in a row were the eight-lane core's slowest
    // path, 7 LUT levels into the visit counter).
    visited_acc: Signal<Local, Bits<8>>,
    visited_twos: Signal<Local, Bits<8>>,
    visited_fours: Signal<Local, Bits<8>>,
    vis_i: Vec<Resize<64, C>>,
    vis_j: Vec<Resize<64, C>>,
    // A large box is left on some lane's chain; every lane has a credit; a SAT test is on
    // some lane's queue's output; every lane is drained (and the list heads are clear).
    large_left: Signal<Local, Bit>,
    credit_acc: Signal<Local, Bit>,
    /// The credit, registered: every lane had room for two more boxes on the clock before.
    credit_q: DFF<Bit>,
    out_valid: Signal<Local, Bit>,
    drained: Signal<Local, Bit>,
    /// The group mask's row of the slow path's box's group.
    lrow: Signal<Local, Bits<MASK>>,
    /// The frame's group mask (the haptic one in a haptic frame).
    fmask: DFF<Bits<MASK>>,
    // The clear before an update frame's load runs (it writes every list; the clear after a
    // walk only the streamed groups'); the clear is at its last bucket.
    pre_clear: DFF<Bit>,
    clear_last: Signal<Local, Bit>,
    // The resident set shifted to the box's group at K+3; the box is of a resident group, in
    // an update frame.
    res_row: Signal<Local, Bits<8>>,
    s3_res: Signal<Local, Bit>,
    /// Per lane, the chain of large boxes as the resident ones left it (`lnext`, `lnext2`):
    /// a haptic frame's chain starts from it.
    res_lnext: Vec<DFF<Bits<C>>>,
    res_lnext2: Vec<DFF<Bits<C>>>,
    update_q: DFF<Bit>,
}

impl<const A: usize, const C: usize> GridPhase<A, C> {
    /// The grid of configuration `cfg` (valid; its cell edge fits the keys).
    pub fn new(cfg: &HwConfig) -> GridPhase<A, C> {
        assert!(C == A + 1, "successors need one bit more than indices");
        let shape = GridShape::new(cfg);
        let groups = shape.groups as usize;
        let lanes = cfg.lanes as usize;
        assert!(
            lanes.is_power_of_two() && lanes <= MAX_LANES as usize,
            "lanes: a power of two up to {MAX_LANES}"
        );
        let lpl = BANKS * groups;
        let lists = lpl * lanes;
        // A lane's banks of the per-box tables hold its boxes: every `lanes`-th.
        let depth = (1u64 << A) / lanes as u64;
        // The mask as bits: bit `8 g + h` for each pair of groups it allows.
        let mask_bits = |m: &obb_model::GroupMask| {
            let mut bits = Bits::<MASK>::default();
            for g in 0..1u32 << GROUP {
                for h in (0..1u32 << GROUP).filter(|&h| m.allows(g, h)) {
                    bits = bits.replace_bit((g << GROUP | h) as usize, true);
                }
            }
            bits
        };
        let mask = mask_bits(&cfg.groups);
        let haptic_mask = mask_bits(&cfg.haptic_mask());
        let resident_set: u64 = cfg.resident_groups.iter().map(|&g| 1u64 << g).sum();
        let buckets = 1u64 << shape.hash_bits;
        GridPhase {
            clock: Default::default(),
            start: Default::default(),
            update: Default::default(),
            accept: Default::default(),
            loaded: Default::default(),
            credit: Default::default(),
            key_valid: Default::default(),
            key_index: Default::default(),
            key_min_x: Default::default(),
            key_min_y: Default::default(),
            key_min_z: Default::default(),
            key_max_x: Default::default(),
            key_max_y: Default::default(),
            key_max_z: Default::default(),
            key_margin: Default::default(),
            key_group: Default::default(),
            visit: Default::default(),
            visit_i0: Default::default(),
            visit_i1: Default::default(),
            visit_i2: Default::default(),
            visit_i3: Default::default(),
            visit_j0: Default::default(),
            visit_j1: Default::default(),
            visit_j2: Default::default(),
            visit_j3: Default::default(),
            visits: Default::default(),
            test_valid: Default::default(),
            test_ready: Default::default(),
            test_a: Default::default(),
            test_b: Default::default(),
            test_ma: Default::default(),
            test_mb: Default::default(),
            walked: Default::default(),
            finished: Default::default(),
            too_wide: Default::default(),
            queue_overflow: Default::default(),
            lanes_overflow: Default::default(),
            _groups: groups,
            _lanes: lanes,
            _lpl: lpl,
            _lpl_end: lpl + 1,
            _lists: lists,
            lane_mask: Constant::new((lanes as u64 - 1).into()),
            lane_id: (0..lanes as u64).map(|k| Constant::new(k.into())).collect(),
            key_lane_mask: Constant::new((lanes as u64 - 1).into()),
            key_lane_id: (0..lanes as u64).map(|k| Constant::new(k.into())).collect(),
            lane_shift: Constant::new(u64::from(lanes.trailing_zeros()).into()),
            lane_bit: (0..lanes)
                .map(|k| Constant::new((1u64 << k).into()))
                .collect(),
            lane_at: (0..lanes as u64)
                .map(|k| Constant::new((32 * (k % 2)).into()))
                .collect(),
            last_bucket: Constant::new((buckets - 1).into()),
            mask: Constant::new(mask),
            haptic_mask: Constant::new(haptic_mask),
            resident_set: Constant::new(resident_set.into()),
            has_resident: Constant::new(resident_set != 0),
            group_streamed: (0..groups as u32)
                .map(|g| Constant::new(!cfg.is_resident(g)))
                .collect(),
            credits_used: Constant::new(((1u64 << COUNT) - GRID_CREDITS as u64).into()),
            top: Constant::new((1u64 << A).into()),
            index_mask: Constant::new(((1u64 << A) - 1).into()),
            group_keep: Constant::new(if groups == 1 { 0 } else { (1u64 << GROUP) - 1 }.into()),
            list_group: (0..lists)
                .map(|l| Constant::new(((l % lpl / BANKS) as u64).into()))
                .collect(),
            cell_bits: Constant::new(u64::from(shape.cell_bits).into()),
            max_span: Constant::new((MAX_WINDOW - 2).into()),
            at_a: Constant::new(((INDEX + 2 * MARGIN) as u64).into()),
            at_b: Constant::new(((2 * MARGIN) as u64).into()),
            at_ma: Constant::new((MARGIN as u64).into()),
            cells: GridCells::new(cfg),

            s1_valid: Default::default(),
            s1_index: Default::default(),
            s1_min: Default::default(),
            s1_max: Default::default(),
            s1_margin: Default::default(),
            s1_kind: Default::default(),
            s1_group: Default::default(),
            s2_valid: Default::default(),
            s2_index: Default::default(),
            s2_min: Default::default(),
            s2_max: Default::default(),
            s2_margin: Default::default(),
            s2_kind: Default::default(),
            s2_group: Default::default(),
            s3_valid: Default::default(),
            s3_index: Default::default(),
            s3_min: Default::default(),
            s3_max: Default::default(),
            s3_margin: Default::default(),
            s3_kind: Default::default(),
            s3_group: Default::default(),
            s3_allowed: Default::default(),
            s4_valid: Default::default(),
            s4_index: Default::default(),
            s4_min: Default::default(),
            s4_max: Default::default(),
            s4_margin: Default::default(),
            s4_kind: Default::default(),
            s4_meta: vec(lists),
            s4_old: vec(lists),
            s4_old2: vec(lists),
            s4_walk: vec(lists),
            s4_enter: vec(lists),
            s4_bucket: Default::default(),
            s4_fp: Default::default(),
            s4_fwd: vec(lists),
            s4_home_fp: Default::default(),
            s4_large: Default::default(),
            s4_lprev: Default::default(),
            s5_valid: Default::default(),
            s5_index: Default::default(),
            s5_min: Default::default(),
            s5_max: Default::default(),
            s5_margin: Default::default(),
            s5_kind: Default::default(),
            s5_live: vec(lists),
            s5_head: vec(lists),
            s5_head2: vec(lists),
            s5_entry: vec(27),
            s5_meta_w: vec(lists),
            s5_large: Default::default(),
            s5_lprev: Default::default(),
            meta: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            head: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            head2: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            succ: (0..lanes).map(|_| TableRam::with_depth(depth)).collect(),
            kt_min: (0..3 * lanes)
                .map(|_| TableRam::with_depth(depth))
                .collect(),
            kt_max: (0..3 * lanes)
                .map(|_| TableRam::with_depth(depth))
                .collect(),
            kt_margin: (0..lanes).map(|_| TableRam::with_depth(depth)).collect(),
            kt_group: (0..lanes).map(|_| TableRam::with_depth(depth)).collect(),
            rec: vec(lists),
            rec2: vec(lists),
            rec_box: vec(lanes),
            wp: vec(lanes),
            rp: vec(lanes),
            count: vec(lanes),
            inflight: vec(lanes),
            e_busy: vec(lanes),
            e_rem: vec(lists),
            e_head: vec(lists),
            e_head2: vec(lists),
            e_chosen: vec(lanes),
            e_sel: vec(lists),
            e_index: vec(lanes),
            e_min: vec(3 * lanes),
            e_max: vec(3 * lanes),
            e_margin: vec(lanes),
            e_kind: vec(lanes),
            lq_head: (0..lanes).map(|_| DistRam::registers()).collect(),
            lq_head2: (0..lanes).map(|_| DistRam::registers()).collect(),
            lq_box: vec(lanes),
            lq_last: vec(lanes),
            lq_wp: vec(lanes),
            lq_rp: vec(lanes),
            lq_fill: vec(3 * lanes),
            cur_valid: vec(lanes),
            cur_last: vec(lanes),
            cur_index: vec(lanes),
            cur_min: vec(3 * lanes),
            cur_max: vec(3 * lanes),
            cur_margin: vec(lanes),
            cur_kind: vec(lanes),
            succ_q: vec(lanes),
            r1: vec(lanes),
            arrive_q: vec(lanes),
            q0v: vec(lanes),
            q0: vec(lanes),
            q1v: vec(lanes),
            q1: vec(lanes),
            v1_valid: vec(lanes),
            v1_i: vec(lanes),
            v1_j: vec(lanes),
            v1_min: vec(3 * lanes),
            v1_max: vec(3 * lanes),
            v1_margin: vec(lanes),
            v1_kind: vec(lanes),
            v2_valid: vec(lanes),
            v2_i: vec(lanes),
            v2_j: vec(lanes),
            v2_min_i: vec(3 * lanes),
            v2_max_i: vec(3 * lanes),
            v2_min_j: vec(3 * lanes),
            v2_max_j: vec(3 * lanes),
            v2_margin_i: vec(lanes),
            v2_margin_j: vec(lanes),
            v2_kind: vec(lanes),
            v2_wl: vec(3 * lanes),
            v2_wh: vec(3 * lanes),
            v2_jc: vec(3 * lanes),
            v2_group_j: vec(lanes),
            v3_valid: vec(lanes),
            v3_overlap: vec(lanes),
            v3_home: vec(lanes),
            v3_anywhere: vec(lanes),
            v3_mask: vec(lanes),
            v3_word: vec(lanes),
            fifo: (0..lanes)
                .map(|_| PairFifo::new(GRID_TEST_STALL as u64))
                .collect(),
            clearing: Default::default(),
            cleared: Default::default(),
            clear_at: Default::default(),
            slow: Default::default(),
            lnext: vec(lanes),
            lnext2: vec(lanes),
            lcur: Default::default(),
            lk_min: Default::default(),
            lk_lim: Default::default(),
            lk_max: Default::default(),
            lmargin: Default::default(),
            lgroup: Default::default(),
            wlo: Default::default(),
            wspan: Default::default(),
            rleft: Default::default(),
            rr: Default::default(),
            wide: Default::default(),
            fetch_q: Default::default(),
            inj: Default::default(),
            inj_kind: Default::default(),
            inj_min: Default::default(),
            inj_max: Default::default(),
            visits_q: Default::default(),
            key_min: Default::default(),
            key_max: Default::default(),
            rd_min: vec(3 * lanes),
            rd_max: vec(3 * lanes),
            sel_min: Default::default(),
            sel_max: Default::default(),
            sel_margin: Default::default(),
            sel_group: Default::default(),
            allowed: Default::default(),
            allow: vec(lists),
            fwd: vec(lists),
            same: Default::default(),
            meta_src: vec(2 * lists),
            live_src: vec(2 * lists),
            meta_new_src: vec(2 * lists),
            meta_eff: vec(lists),
            old_eff: vec(lists),
            old_eff2: vec(lists),
            live: vec(lists),
            meta_new: vec(lists),
            entry_pick: vec(lists),
            entry_acc: vec(27),
            succ_acc: Default::default(),
            any_live: vec(lanes),
            bank_any: vec(27 * lanes),
            group_prior: vec(lists),
            chunk_prior: vec(10 * lanes),
            bank_prior: vec(27 * lanes),
            bank_next: vec(27 * lanes),
            bank_load: vec(27 * lanes),
            bank_left: vec(27 * lanes),
            chunk_next: vec(9 * lanes),
            chunk_load: vec(9 * lanes),
            chunk_left: vec(9 * lanes),
            e_first: vec(lists),
            e_push: vec(lanes),
            e_pick: vec(lists),
            e_out: vec(lanes),
            e_pick2: vec(lists),
            e_out2: vec(lanes),
            e_more: vec(lanes),
            e_load: vec(lanes),
            arrive: vec(lanes),
            avail: vec(lanes),
            after: vec(lanes),
            after_v: vec(lanes),
            need: vec(lanes),
            retire_rec: vec(lanes),
            take: vec(lanes),
            rd_live: vec(lists),
            inflight_up: Default::default(),
            inflight_inc: vec(lanes),
            inflight_dec: vec(lanes),
            inflight_dec2: vec(lanes),
            inflight_m: vec(3 * lanes),
            inflight_n0: vec(lanes),
            inflight_n1: vec(lanes),
            count_inc: vec(lanes),
            count_dec: vec(lanes),
            count_m: vec(3 * lanes),
            ones: Constant::new(((1u64 << COUNT) - 1).into()),
            test_word: vec(lanes),
            unpack_a: Default::default(),
            unpack_b: Default::default(),
            unpack_ma: Default::default(),
            next_box: vec(lanes),
            entry: Default::default(),
            entry4: Default::default(),
            entry5: Default::default(),
            next_ok: vec(lanes),
            go: vec(lanes),
            stall: vec(lanes),
            retire_probe: vec(lanes),
            retire_probe_q: vec(lanes),
            rec_write: vec(lanes),
            overlap: vec(lanes),
            swap: vec(lanes),
            test_lo: vec(lanes),
            test_hi: vec(lanes),
            margin_lo: vec(lanes),
            margin_hi: vec(lanes),
            done_walk: Default::default(),
            idle: Default::default(),
            idle_next: Default::default(),
            fetch: Default::default(),
            inject: Default::default(),
            inject_kind: Default::default(),
            inject_min: Default::default(),
            inject_max: Default::default(),
            left: Default::default(),
            three_cells: Default::default(),
            last_round: Default::default(),
            rr_p1: Default::default(),
            rr_p2: Default::default(),
            rr_p3: Default::default(),
            left_m2: Default::default(),
            left_m3: Default::default(),
            two_m: Default::default(),
            three_m: Default::default(),
            next_rr: Default::default(),
            next_left: Default::default(),
            plan_span: Default::default(),
            center_ones: Constant::new(((1u64 << CENTER) - 1).into()),
            above_one: Constant::new(((1u64 << CENTER) - 2).into()),
            above_three: Constant::new(((1u64 << CENTER) - 4).into()),
            plan_lo: Default::default(),
            plan_hi: Default::default(),
            plan_wide: Default::default(),
            large_in: Default::default(),
            home_ok: vec(lanes),
            wl_cell: vec(3 * lanes),
            wl_keep: vec(3 * lanes),
            mask_row: vec(lanes),
            mask_ok: vec(lanes),
            pass: vec(lanes),
            lower: vec(lanes + 1),
            out_word: Default::default(),
            lprior: vec(lanes + 1),
            lhead: Default::default(),
            visit_acc: Default::default(),
            vis_pack_i: vec(4),
            vis_pack_j: vec(4),
            visited_acc: Default::default(),
            visited_twos: Default::default(),
            visited_fours: Default::default(),
            key_addr: Default::default(),
            succ_addr: Default::default(),
            vis_i: vec(lanes),
            vis_j: vec(lanes),
            pack_lo: vec(lanes),
            pack_hi: vec(lanes),
            pack_mlo: vec(lanes),
            pack_mhi: vec(lanes),
            large_left: Default::default(),
            credit_acc: Default::default(),
            credit_q: Default::default(),
            out_valid: Default::default(),
            drained: Default::default(),
            lrow: Default::default(),
            fmask: Default::default(),
            pre_clear: Default::default(),
            clear_last: Default::default(),
            res_row: Default::default(),
            s3_res: Default::default(),
            res_lnext: vec(lanes),
            res_lnext2: vec(lanes),
            update_q: Default::default(),
            s3_lane: vec(lanes),
            s4_lane: vec(lanes),
            s5_lane: vec(lanes),
            slane: vec(lanes),
            rd_margin: vec(lanes),
            rd_group: vec(lanes),
            key_lane: vec(lanes),
            rd_address: vec(lanes),
            issuer: vec(lanes),
            out_pick: vec(lanes),
            lfirst: vec(lanes),
            lpick: vec(lanes),
        }
    }
}

impl<const A: usize, const C: usize> Logic for GridPhase<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, s1_valid, s1_index, s1_margin, s1_group, s2_valid, s2_index, s2_margin,
            s2_group, s3_valid, s3_index, s3_margin, s3_group, s3_allowed, s4_valid, s4_large,
            s4_lprev, s4_index, s4_margin, s4_kind, s4_home_fp, s5_valid, s5_large, s5_lprev,
            s5_index, s5_margin, clearing, cleared, clear_at, s1_kind, s2_kind, s3_kind, s5_kind,
            slow, lcur, lmargin, lgroup, wide, fetch_q, inj, inj_kind, idle, credit_q, fmask,
            pre_clear, update_q, visits_q
        );
        clock!(self, clock, cells);
        for b in 0..27 {
            self.s4_bucket[b].clock.next = self.clock.val();
            self.s4_fp[b].clock.next = self.clock.val();
            self.s5_entry[b].clock.next = self.clock.val();
        }
        for x in 0..3 {
            self.s1_min[x].clock.next = self.clock.val();
            self.s1_max[x].clock.next = self.clock.val();
            self.s2_min[x].clock.next = self.clock.val();
            self.s2_max[x].clock.next = self.clock.val();
            self.s3_min[x].clock.next = self.clock.val();
            self.s3_max[x].clock.next = self.clock.val();
            self.s4_min[x].clock.next = self.clock.val();
            self.s4_max[x].clock.next = self.clock.val();
            self.s5_min[x].clock.next = self.clock.val();
            self.s5_max[x].clock.next = self.clock.val();
            self.lk_min[x].clock.next = self.clock.val();
            self.lk_lim[x].clock.next = self.clock.val();
            self.lk_max[x].clock.next = self.clock.val();
            self.wlo[x].clock.next = self.clock.val();
            self.wspan[x].clock.next = self.clock.val();
            self.rleft[x].clock.next = self.clock.val();
            self.rr[x].clock.next = self.clock.val();
            self.inj_min[x].clock.next = self.clock.val();
            self.inj_max[x].clock.next = self.clock.val();
            self.lk_min[x].d.next = self.lk_min[x].q.val();
            self.lk_lim[x].d.next = self.lk_lim[x].q.val();
            self.lk_max[x].d.next = self.lk_max[x].q.val();
            self.wlo[x].d.next = self.wlo[x].q.val();
            self.wspan[x].d.next = self.wspan[x].q.val();
            self.rleft[x].d.next = self.rleft[x].q.val();
            self.rr[x].d.next = self.rr[x].q.val();
        }
        for l in 0..self._lists {
            self.s5_live[l].clock.next = self.clock.val();
            self.s5_head[l].clock.next = self.clock.val();
            self.s5_head2[l].clock.next = self.clock.val();
            self.s5_meta_w[l].clock.next = self.clock.val();
            self.s4_meta[l].clock.next = self.clock.val();
            self.s4_fwd[l].clock.next = self.clock.val();
            self.s4_old[l].clock.next = self.clock.val();
            self.s4_old2[l].clock.next = self.clock.val();
            self.s4_walk[l].clock.next = self.clock.val();
            self.s4_enter[l].clock.next = self.clock.val();
            self.meta[l].clock.next = self.clock.val();
            self.head[l].clock.next = self.clock.val();
            self.head2[l].clock.next = self.clock.val();
            self.rec[l].clock.next = self.clock.val();
            self.rec2[l].clock.next = self.clock.val();
            self.e_rem[l].clock.next = self.clock.val();
            self.e_head[l].clock.next = self.clock.val();
            self.e_head2[l].clock.next = self.clock.val();
            self.e_sel[l].clock.next = self.clock.val();
            self.e_rem[l].d.next = self.e_rem[l].q.val();
            self.e_head[l].d.next = self.e_head[l].q.val();
            self.e_head2[l].d.next = self.e_head2[l].q.val();
            self.e_sel[l].d.next = self.e_sel[l].q.val();
        }
        // Per lane: its memories and registers (each register holds unless written).
        for k in 0..self._lanes {
            self.succ[k].clock.next = self.clock.val();
            self.kt_margin[k].clock.next = self.clock.val();
            self.kt_group[k].clock.next = self.clock.val();
            self.rec_box[k].clock.next = self.clock.val();
            self.lq_head[k].clock.next = self.clock.val();
            self.lq_head2[k].clock.next = self.clock.val();
            self.lq_box[k].clock.next = self.clock.val();
            self.lq_last[k].clock.next = self.clock.val();
            self.fifo[k].clock.next = self.clock.val();
            self.s3_lane[k].clock.next = self.clock.val();
            self.s4_lane[k].clock.next = self.clock.val();
            self.s5_lane[k].clock.next = self.clock.val();
            self.s3_lane[k].d.next = self.s3_lane[k].q.val();
            self.s4_lane[k].d.next = self.s4_lane[k].q.val();
            self.s5_lane[k].d.next = self.s5_lane[k].q.val();
            self.wp[k].clock.next = self.clock.val();
            self.rp[k].clock.next = self.clock.val();
            self.count[k].clock.next = self.clock.val();
            self.inflight[k].clock.next = self.clock.val();
            self.retire_probe_q[k].clock.next = self.clock.val();
            self.wp[k].d.next = self.wp[k].q.val();
            self.rp[k].d.next = self.rp[k].q.val();
            self.count[k].d.next = self.count[k].q.val();
            self.inflight[k].d.next = self.inflight[k].q.val();
            self.e_busy[k].clock.next = self.clock.val();
            self.e_chosen[k].clock.next = self.clock.val();
            self.e_index[k].clock.next = self.clock.val();
            self.e_margin[k].clock.next = self.clock.val();
            self.e_kind[k].clock.next = self.clock.val();
            self.e_busy[k].d.next = self.e_busy[k].q.val();
            self.e_chosen[k].d.next = self.e_chosen[k].q.val();
            self.e_index[k].d.next = self.e_index[k].q.val();
            self.e_margin[k].d.next = self.e_margin[k].q.val();
            self.e_kind[k].d.next = self.e_kind[k].q.val();
            self.lq_wp[k].clock.next = self.clock.val();
            self.lq_rp[k].clock.next = self.clock.val();
            self.lq_wp[k].d.next = self.lq_wp[k].q.val();
            self.lq_rp[k].d.next = self.lq_rp[k].q.val();
            self.cur_valid[k].clock.next = self.clock.val();
            self.cur_last[k].clock.next = self.clock.val();
            self.cur_index[k].clock.next = self.clock.val();
            self.cur_margin[k].clock.next = self.clock.val();
            self.cur_kind[k].clock.next = self.clock.val();
            self.cur_valid[k].d.next = self.cur_valid[k].q.val();
            self.cur_last[k].d.next = self.cur_last[k].q.val();
            self.cur_index[k].d.next = self.cur_index[k].q.val();
            self.cur_margin[k].d.next = self.cur_margin[k].q.val();
            self.cur_kind[k].d.next = self.cur_kind[k].q.val();
            self.succ_q[k].clock.next = self.clock.val();
            self.r1[k].clock.next = self.clock.val();
            self.arrive_q[k].clock.next = self.clock.val();
            self.q0v[k].clock.next = self.clock.val();
            self.q0[k].clock.next = self.clock.val();
            self.q1v[k].clock.next = self.clock.val();
            self.q1[k].clock.next = self.clock.val();
            self.succ_q[k].d.next = self.succ_q[k].q.val();
            self.r1[k].d.next = self.r1[k].q.val();
            self.arrive_q[k].d.next = self.arrive_q[k].q.val();
            self.q0v[k].d.next = self.q0v[k].q.val();
            self.q0[k].d.next = self.q0[k].q.val();
            self.q1v[k].d.next = self.q1v[k].q.val();
            self.q1[k].d.next = self.q1[k].q.val();
            self.v1_valid[k].clock.next = self.clock.val();
            self.v1_i[k].clock.next = self.clock.val();
            self.v1_j[k].clock.next = self.clock.val();
            self.v1_margin[k].clock.next = self.clock.val();
            self.v1_kind[k].clock.next = self.clock.val();
            self.v2_valid[k].clock.next = self.clock.val();
            self.v2_i[k].clock.next = self.clock.val();
            self.v2_j[k].clock.next = self.clock.val();
            self.v2_margin_i[k].clock.next = self.clock.val();
            self.v2_margin_j[k].clock.next = self.clock.val();
            self.v2_kind[k].clock.next = self.clock.val();
            self.v2_group_j[k].clock.next = self.clock.val();
            self.v3_valid[k].clock.next = self.clock.val();
            self.v3_overlap[k].clock.next = self.clock.val();
            self.v3_home[k].clock.next = self.clock.val();
            self.v3_anywhere[k].clock.next = self.clock.val();
            self.v3_mask[k].clock.next = self.clock.val();
            self.v3_word[k].clock.next = self.clock.val();
            self.lnext[k].clock.next = self.clock.val();
            self.lnext2[k].clock.next = self.clock.val();
            self.res_lnext[k].clock.next = self.clock.val();
            self.res_lnext2[k].clock.next = self.clock.val();
            self.res_lnext[k].d.next = self.res_lnext[k].q.val();
            self.res_lnext2[k].d.next = self.res_lnext2[k].q.val();
            self.slane[k].clock.next = self.clock.val();
            self.lnext[k].d.next = self.lnext[k].q.val();
            self.lnext2[k].d.next = self.lnext2[k].q.val();
            self.slane[k].d.next = self.slane[k].q.val();
            for x in 0..3 {
                self.kt_min[3 * k + x].clock.next = self.clock.val();
                self.kt_max[3 * k + x].clock.next = self.clock.val();
                self.lq_fill[3 * k + x].clock.next = self.clock.val();
                self.lq_fill[3 * k + x].d.next = self.lq_fill[3 * k + x].q.val();
                self.e_min[3 * k + x].clock.next = self.clock.val();
                self.e_max[3 * k + x].clock.next = self.clock.val();
                self.e_min[3 * k + x].d.next = self.e_min[3 * k + x].q.val();
                self.e_max[3 * k + x].d.next = self.e_max[3 * k + x].q.val();
                self.cur_min[3 * k + x].clock.next = self.clock.val();
                self.cur_max[3 * k + x].clock.next = self.clock.val();
                self.cur_min[3 * k + x].d.next = self.cur_min[3 * k + x].q.val();
                self.cur_max[3 * k + x].d.next = self.cur_max[3 * k + x].q.val();
                self.v1_min[3 * k + x].clock.next = self.clock.val();
                self.v1_max[3 * k + x].clock.next = self.clock.val();
                self.v2_min_i[3 * k + x].clock.next = self.clock.val();
                self.v2_max_i[3 * k + x].clock.next = self.clock.val();
                self.v2_min_j[3 * k + x].clock.next = self.clock.val();
                self.v2_max_j[3 * k + x].clock.next = self.clock.val();
                self.v2_wl[3 * k + x].clock.next = self.clock.val();
                self.v2_wh[3 * k + x].clock.next = self.clock.val();
                self.v2_jc[3 * k + x].clock.next = self.clock.val();
            }
            for b in 0..27 {
                self.bank_left[27 * k + b].clock.next = self.clock.val();
            }
            for c in 0..9 {
                self.chunk_left[9 * k + c].clock.next = self.clock.val();
            }
        }

        // (A loop of one pass, so that a list of lane k at `lpl k + l` is indexed by loop
        // variables alone, as rust-hdl's Verilog writer requires.)
        for lpl in self._lpl..self._lpl_end {
            self.key_min[0].next = self.key_min_x.val();
            self.key_min[1].next = self.key_min_y.val();
            self.key_min[2].next = self.key_min_z.val();
            self.key_max[0].next = self.key_max_x.val();
            self.key_max[1].next = self.key_max_y.val();
            self.key_max[2].next = self.key_max_z.val();

            // The per-box tables: an arriving box's keys, margin and group are written in its
            // lane's banks; each lane's walker reads its banks on port B.
            self.key_addr.next = bit_cast::<C, A>(self.key_index.val()) >> self.lane_shift.val();
            for k in 0..self._lanes {
                self.key_lane[k].next =
                    (self.key_index.val() & self.key_lane_mask.val()) == self.key_lane_id[k].val();
                for x in 0..3 {
                    self.kt_min[3 * k + x].write_enable.next =
                        self.key_valid.val() & self.key_lane[k].val();
                    self.kt_min[3 * k + x].write_address.next = self.key_addr.val();
                    self.kt_min[3 * k + x].write_data.next = self.key_min[x].val();
                    self.kt_min[3 * k + x].read_address_a.next = 0.into();
                    self.rd_min[3 * k + x].next = self.kt_min[3 * k + x].read_data_b.val();
                    self.kt_max[3 * k + x].write_enable.next =
                        self.key_valid.val() & self.key_lane[k].val();
                    self.kt_max[3 * k + x].write_address.next = self.key_addr.val();
                    self.kt_max[3 * k + x].write_data.next = self.key_max[x].val();
                    self.kt_max[3 * k + x].read_address_a.next = 0.into();
                    self.rd_max[3 * k + x].next = self.kt_max[3 * k + x].read_data_b.val();
                }
                self.kt_margin[k].write_enable.next = self.key_valid.val() & self.key_lane[k].val();
                self.kt_margin[k].write_address.next = self.key_addr.val();
                self.kt_margin[k].write_data.next = self.key_margin.val();
                self.kt_margin[k].read_address_a.next = 0.into();
                self.rd_margin[k].next = self.kt_margin[k].read_data_b.val();
                self.kt_group[k].write_enable.next = self.key_valid.val() & self.key_lane[k].val();
                self.kt_group[k].write_address.next = self.key_addr.val();
                self.kt_group[k].write_data.next = self.key_group.val();
                self.kt_group[k].read_address_a.next = 0.into();
                self.rd_group[k].next = self.kt_group[k].read_data_b.val();
            }

            // The slow path's sequencer (it injects after the load, when no box arrives, nothing
            // in flight on any lane). Its next large box: the head of the first lane's chain that
            // holds one.
            self.idle_next.next = self.loaded.val();
            self.lprior[0].next = false;
            self.lhead.next = 0.into();
            for k in 0..self._lanes {
                self.idle_next.next = self.idle_next.val() & (self.inflight[k].q.val() == 0);
                self.lfirst[k].next =
                    ((self.lnext[k].q.val() & self.top.val()) != 0) & !self.lprior[k].val();
                self.lprior[k + 1].next =
                    self.lprior[k].val() | ((self.lnext[k].q.val() & self.top.val()) != 0);
                self.lpick[k].next = 0.into();
                if self.lfirst[k].val() {
                    self.lpick[k].next = self.lnext[k].q.val();
                }
                self.lhead.next = self.lhead.val() | self.lpick[k].val();
            }
            self.large_left.next = (self.lhead.val() & self.top.val()) != 0;
            self.fetch.next = false;
            self.inject.next = false;
            self.inject_kind.next = 0.into();
            self.plan_wide.next = false;
            for x in 0..3 {
                // A round spans three cells when three or five or more are left (`left` is 1 or
                // at least 3), else two; it is the last when at most three are left (`left` <= 1).
                self.left[x].next = self.rleft[x].q.val();
                self.three_cells[x].next = self.left[x].val().get_bit(0)
                    | ((self.left[x].val() & self.above_three.val()) != 0);
                self.last_round[x].next = (self.left[x].val() & self.above_one.val()) == 0;
                self.rr_p1[x].next = self.rr[x].q.val() + 1;
                self.rr_p2[x].next = self.rr[x].q.val() + 2;
                self.rr_p3[x].next = self.rr[x].q.val() + 3;
                self.left_m2[x].next = self.left[x].val() - 2;
                self.left_m3[x].next = self.left[x].val() - 3;
                self.two_m[x].next = self.center_ones.val();
                self.three_m[x].next = 0.into();
                if self.three_cells[x].val() {
                    self.two_m[x].next = 0.into();
                    self.three_m[x].next = self.center_ones.val();
                }
                self.next_rr[x].next = (self.rr_p2[x].val() & self.two_m[x].val())
                    | (self.rr_p3[x].val() & self.three_m[x].val());
                self.next_left[x].next = (self.left_m2[x].val() & self.two_m[x].val())
                    | (self.left_m3[x].val() & self.three_m[x].val());
                self.inject_min[x].next = self.rr[x].q.val() << self.cell_bits.val();
                self.inject_max[x].next = ((self.rr[x].q.val() & self.two_m[x].val())
                    | (self.rr_p1[x].val() & self.three_m[x].val()))
                    << self.cell_bits.val();
                if self.slow.q.val() == SlowState::Partner {
                    self.inject_min[x].next = self.lk_min[x].q.val();
                    self.inject_max[x].next = self.lk_max[x].q.val();
                }
                self.inj_min[x].d.next = self.inject_min[x].val();
                self.inj_max[x].d.next = self.inject_max[x].val();
                self.plan_lo[x].next = self.lk_min[x].q.val() >> self.cell_bits.val();
                self.plan_hi[x].next = self.lk_max[x].q.val() >> self.cell_bits.val();
                self.plan_span[x].next = self.plan_hi[x].val() - self.plan_lo[x].val();
                if (self.lk_max[x].q.val() >> self.cell_bits.val()) > self.lk_lim[x].q.val() {
                    self.plan_wide.next = true;
                }
            }
            self.sel_margin.next = 0.into();
            self.sel_group.next = 0.into();
            for x in 0..3 {
                self.sel_min[x].next = 0.into();
                self.sel_max[x].next = 0.into();
            }
            for k in 0..self._lanes {
                if self.slane[k].q.val() {
                    self.sel_margin.next = self.sel_margin.val() | self.rd_margin[k].val();
                    self.sel_group.next = self.sel_group.val() | self.rd_group[k].val();
                    for x in 0..3 {
                        self.sel_min[x].next = self.sel_min[x].val() | self.rd_min[3 * k + x].val();
                        self.sel_max[x].next = self.sel_max[x].val() | self.rd_max[3 * k + x].val();
                    }
                }
            }
            match self.slow.q.val() {
                SlowState::Fetch => {
                    if self.idle.q.val() {
                        if self.large_left.val() {
                            self.fetch.next = true;
                            self.lcur.d.next = self.lhead.val() ^ self.top.val();
                            for k in 0..self._lanes {
                                self.slane[k].d.next = self.lfirst[k].val();
                                if self.lfirst[k].val() {
                                    self.lnext[k].d.next = self.lnext2[k].q.val();
                                }
                            }
                            self.slow.d.next = SlowState::Address;
                        } else {
                            self.slow.d.next = SlowState::Over;
                        }
                    }
                }
                SlowState::Address => {
                    self.slow.d.next = SlowState::Read;
                }
                SlowState::Read => {
                    // The box's keys, from its lane's banks.
                    self.lmargin.d.next = self.sel_margin.val();
                    self.lgroup.d.next = self.sel_group.val();
                    for x in 0..3 {
                        self.lk_min[x].d.next = self.sel_min[x].val();
                        self.lk_max[x].d.next = self.sel_max[x].val();
                    }
                    self.slow.d.next = SlowState::Limit;
                }
                SlowState::Limit => {
                    // The fetched box's second successor, from its lane's registered output.
                    for k in 0..self._lanes {
                        if self.slane[k].q.val() {
                            self.lnext2[k].d.next = self.succ_q[k].q.val();
                        }
                    }
                    for x in 0..3 {
                        self.lk_lim[x].d.next =
                            (self.lk_min[x].q.val() >> self.cell_bits.val()) + self.max_span.val();
                    }
                    self.slow.d.next = SlowState::Plan;
                }
                SlowState::Plan => {
                    for x in 0..3 {
                        self.wlo[x].d.next = self.plan_lo[x].val();
                        self.wspan[x].d.next = self.plan_span[x].val();
                        self.rleft[x].d.next = self.plan_span[x].val();
                        self.rr[x].d.next = self.plan_lo[x].val();
                    }
                    self.slow.d.next = SlowState::Round;
                    if self.plan_wide.val() {
                        self.wide.d.next = true;
                        self.slow.d.next = SlowState::Over;
                    }
                }
                SlowState::Round => {
                    // Inject the round; step x, then y, then z; after the last, the rest of the
                    // chains (if any large box is left) or the next box.
                    if self.idle.q.val() {
                        self.inject.next = true;
                        self.inject_kind.next = 1.into();
                        if !self.last_round[0].val() {
                            self.rr[0].d.next = self.next_rr[0].val();
                            self.rleft[0].d.next = self.next_left[0].val();
                        } else {
                            self.rr[0].d.next = self.wlo[0].q.val();
                            self.rleft[0].d.next = self.wspan[0].q.val();
                            if !self.last_round[1].val() {
                                self.rr[1].d.next = self.next_rr[1].val();
                                self.rleft[1].d.next = self.next_left[1].val();
                            } else {
                                self.rr[1].d.next = self.wlo[1].q.val();
                                self.rleft[1].d.next = self.wspan[1].q.val();
                                if !self.last_round[2].val() {
                                    self.rr[2].d.next = self.next_rr[2].val();
                                    self.rleft[2].d.next = self.next_left[2].val();
                                } else if self.large_left.val() {
                                    self.slow.d.next = SlowState::Partner;
                                } else {
                                    self.slow.d.next = SlowState::Fetch;
                                }
                            }
                        }
                    }
                }
                SlowState::Partner => {
                    if self.idle.q.val() {
                        self.inject.next = true;
                        self.inject_kind.next = 2.into();
                        self.slow.d.next = SlowState::Fetch;
                    }
                }
                SlowState::Over => {}
            }
            // (After the states that set them: a local is read where it is written.)
            self.fetch_q.d.next = self.fetch.val();
            self.inj.d.next = self.inject.val();
            self.inj_kind.d.next = self.inject_kind.val();
            self.idle.d.next = self.idle_next.val() & !self.inject.val();
            // K+1 to K+3: the cells of the box's window (`GridCells`); its index, keys, margin and
            // group alongside. An injected record takes the place of an arriving box.
            self.cells.key_valid.next = self.key_valid.val() | self.inj.q.val();
            self.s1_valid.d.next = self.key_valid.val() | self.inj.q.val();
            self.s1_index.d.next = bit_cast::<C, A>(self.key_index.val());
            self.s1_margin.d.next = self.key_margin.val();
            self.s1_group.d.next = self.key_group.val();
            self.s1_kind.d.next = self.inj_kind.q.val();
            if self.inj.q.val() {
                self.s1_index.d.next = self.lcur.q.val();
                self.s1_margin.d.next = self.lmargin.q.val();
                self.s1_group.d.next = self.lgroup.q.val();
            }
            self.s2_kind.d.next = self.s1_kind.q.val();
            self.s3_kind.d.next = self.s2_kind.q.val();
            self.s5_kind.d.next = self.s4_kind.q.val();
            self.s2_valid.d.next = self.s1_valid.q.val();
            self.s2_index.d.next = self.s1_index.q.val();
            self.s2_margin.d.next = self.s1_margin.q.val();
            self.s2_group.d.next = self.s1_group.q.val();
            self.s3_valid.d.next = self.s2_valid.q.val();
            self.s3_index.d.next = self.s2_index.q.val();
            self.s3_margin.d.next = self.s2_margin.q.val();
            self.s3_group.d.next = self.s2_group.q.val();
            for x in 0..3 {
                self.cells.key_min[x].next = self.key_min[x].val();
                self.cells.key_max[x].next = self.key_max[x].val();
                self.s1_min[x].d.next = self.key_min[x].val();
                self.s1_max[x].d.next = self.key_max[x].val();
                if self.inj.q.val() {
                    self.cells.key_min[x].next = self.inj_min[x].q.val();
                    self.cells.key_max[x].next = self.inj_max[x].q.val();
                    self.s1_min[x].d.next = self.inj_min[x].q.val();
                    self.s1_max[x].d.next = self.inj_max[x].q.val();
                }
                self.s2_min[x].d.next = self.s1_min[x].q.val();
                self.s2_max[x].d.next = self.s1_max[x].q.val();
                self.s3_min[x].d.next = self.s2_min[x].q.val();
                self.s3_max[x].d.next = self.s2_max[x].q.val();
            }
            self.allowed.next =
                self.fmask.q.val() >> (bit_cast::<MASK, GROUP>(self.s2_group.q.val()) << 3_u64);
            self.s3_allowed.d.next = self.allowed.val();

            // K+3, per list (bank b, group h): the list heads are read at the bank's bucket and
            // registered, with what decides the lists to walk and the entry. (The box one ahead
            // writes its entry on this clock: the read misses it, so the banks whose bucket it
            // writes are marked, and its entry is forwarded at K+4.)
            self.entry.next = self.s3_index.q.val() | self.top.val();
            for k in 0..self._lanes {
                self.s3_lane[k].d.next =
                    (self.s2_index.q.val() & self.lane_mask.val()) == self.lane_id[k].val();
                self.s4_lane[k].d.next = self.s3_lane[k].q.val();
                self.s5_lane[k].d.next = self.s4_lane[k].q.val();
            }
            for k in 0..self._lanes {
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.meta[lpl * k + 27 * q + b].read_address.next =
                            self.cells.bucket[b].val();
                        self.head[lpl * k + 27 * q + b].read_address.next =
                            self.cells.bucket[b].val();
                        self.allow[lpl * k + 27 * q + b].next =
                            self.s3_allowed.q.val() >> self.list_group[lpl * k + 27 * q + b].val();
                        self.s4_meta[lpl * k + 27 * q + b].d.next =
                            self.meta[lpl * k + 27 * q + b].read_data.val();
                        self.head2[lpl * k + 27 * q + b].read_address.next =
                            self.cells.bucket[b].val();
                        self.s4_old[lpl * k + 27 * q + b].d.next =
                            self.head[lpl * k + 27 * q + b].read_data.val();
                        self.s4_old2[lpl * k + 27 * q + b].d.next =
                            self.head2[lpl * k + 27 * q + b].read_data.val();
                        self.s4_walk[lpl * k + 27 * q + b].d.next = self.s3_valid.q.val()
                            & self.cells.small_box.val()
                            & self.cells.inside[b].val()
                            & self.allow[lpl * k + 27 * q + b].val().get_bit(0);
                        self.s4_enter[lpl * k + 27 * q + b].d.next = self.s3_valid.q.val()
                            & (self.s3_kind.q.val() == 0)
                            & self.cells.small_box.val()
                            & self.cells.home[b].val()
                            & ((self.s3_group.q.val() & self.group_keep.val())
                                == self.list_group[lpl * k + 27 * q + b].val())
                            & self.s3_lane[k].q.val();
                    }
                }
            }
            for b in 0..27 {
                self.s4_bucket[b].d.next = self.cells.bucket[b].val();
                self.s4_fp[b].d.next = self.cells.fp[b].val();
                self.same[b].next = self.cells.bucket[b].val() == self.s4_bucket[b].q.val();
            }
            for k in 0..self._lanes {
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.s4_fwd[lpl * k + 27 * q + b].d.next =
                            self.same[b].val() & self.s4_enter[lpl * k + 27 * q + b].q.val();
                    }
                }
            }
            self.s4_home_fp.d.next = self.cells.home_fp.val();
            // A large box takes the chain of large boxes instead of a list.
            self.large_in.next =
                self.s3_valid.q.val() & (self.s3_kind.q.val() == 0) & !self.cells.small_box.val();
            self.s4_large.d.next = self.large_in.val();
            // An update frame's resident boxes come first: the chain as they leave it is where a
            // haptic frame's starts.
            self.res_row.next =
                self.resident_set.val() >> bit_cast::<8, GROUP>(self.s3_group.q.val());
            self.s3_res.next = self.update_q.q.val() & self.res_row.val().get_bit(0);
            for k in 0..self._lanes {
                if self.s3_lane[k].q.val() {
                    self.s4_lprev.d.next = self.lnext2[k].q.val();
                    if self.large_in.val() {
                        self.lnext[k].d.next = self.entry.val();
                        self.lnext2[k].d.next = self.lnext[k].q.val();
                        if self.s3_res.val() {
                            self.res_lnext[k].d.next = self.entry.val();
                            self.res_lnext2[k].d.next = self.lnext[k].q.val();
                        }
                    }
                }
            }
            self.s4_valid.d.next = self.s3_valid.q.val();
            self.s4_index.d.next = self.s3_index.q.val();
            self.s4_margin.d.next = self.s3_margin.q.val();
            self.s4_kind.d.next = self.s3_kind.q.val();
            for x in 0..3 {
                self.s4_min[x].d.next = self.s3_min[x].q.val();
                self.s4_max[x].d.next = self.s3_max[x].q.val();
            }

            // K+4, per list: the owner and first two boxes the box sees (the box before's entry
            // where it wrote the same bucket on the clock of this box's read: then the box before
            // and its old head). The box walks a list of a
            // group its own pairs with, of a cell in its window, that may hold a box of that cell:
            // its owner has the cell's fingerprint, or it is mixed. A small box enters its home
            // cell's list of its own group: the first owns the list, a box of another fingerprint
            // mixes it; the list's old head becomes its second, and the old second the box's entry
            // (written at K+5). At the end of a frame the clear writes every bucket empty.
            self.entry4.next = self.s4_index.q.val() | self.top.val();
            for b in 0..27 {
                self.entry_acc[b].next = 0.into();
            }
            self.entry5.next = self.s5_index.q.val() | self.top.val();
            for k in 0..self._lanes {
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.fwd[lpl * k + 27 * q + b].next =
                            self.s4_fwd[lpl * k + 27 * q + b].q.val();
                        self.meta_eff[lpl * k + 27 * q + b].next =
                            self.s4_meta[lpl * k + 27 * q + b].q.val();
                        self.old_eff[lpl * k + 27 * q + b].next =
                            self.s4_old[lpl * k + 27 * q + b].q.val();
                        self.old_eff2[lpl * k + 27 * q + b].next =
                            self.s4_old2[lpl * k + 27 * q + b].q.val();
                        if self.fwd[lpl * k + 27 * q + b].val() {
                            self.meta_eff[lpl * k + 27 * q + b].next =
                                self.s5_meta_w[lpl * k + 27 * q + b].q.val();
                            self.old_eff[lpl * k + 27 * q + b].next = self.entry5.val();
                            self.old_eff2[lpl * k + 27 * q + b].next =
                                self.s5_head[lpl * k + 27 * q + b].q.val();
                        }
                        self.meta_src[2 * (lpl * k + 27 * q + b)].next =
                            self.s4_meta[lpl * k + 27 * q + b].q.val();
                        self.meta_src[2 * (lpl * k + 27 * q + b) + 1].next =
                            self.s5_meta_w[lpl * k + 27 * q + b].q.val();
                        for m in 0..2 {
                            // Walked if valid and mixed or owned by the cell's fingerprint. Owned: kept,
                            // and mixed by another fingerprint; free: owned by this one.
                            self.live_src[2 * (lpl * k + 27 * q + b) + m].next =
                                self.s4_walk[lpl * k + 27 * q + b].q.val()
                                    & self.meta_src[2 * (lpl * k + 27 * q + b) + m]
                                        .val()
                                        .get_bit(9)
                                    & (self.meta_src[2 * (lpl * k + 27 * q + b) + m]
                                        .val()
                                        .get_bit(8)
                                        | (self.meta_src[2 * (lpl * k + 27 * q + b) + m]
                                            .val()
                                            .get_bits::<FP>(0)
                                            == self.s4_fp[b].q.val()));
                            self.meta_new_src[2 * (lpl * k + 27 * q + b) + m].next =
                                bit_cast::<META, FP>(self.s4_home_fp.q.val()) | 512_u64;
                            if self.meta_src[2 * (lpl * k + 27 * q + b) + m]
                                .val()
                                .get_bit(9)
                            {
                                self.meta_new_src[2 * (lpl * k + 27 * q + b) + m].next =
                                    self.meta_src[2 * (lpl * k + 27 * q + b) + m].val();
                                if self.meta_src[2 * (lpl * k + 27 * q + b) + m]
                                    .val()
                                    .get_bits::<FP>(0)
                                    != self.s4_home_fp.q.val()
                                {
                                    self.meta_new_src[2 * (lpl * k + 27 * q + b) + m].next =
                                        self.meta_src[2 * (lpl * k + 27 * q + b) + m].val()
                                            | 256_u64;
                                }
                            }
                        }
                        self.live[lpl * k + 27 * q + b].next =
                            self.live_src[2 * (lpl * k + 27 * q + b)].val();
                        self.meta_new[lpl * k + 27 * q + b].next =
                            self.meta_new_src[2 * (lpl * k + 27 * q + b)].val();
                        if self.fwd[lpl * k + 27 * q + b].val() {
                            self.live[lpl * k + 27 * q + b].next =
                                self.live_src[2 * (lpl * k + 27 * q + b) + 1].val();
                            self.meta_new[lpl * k + 27 * q + b].next =
                                self.meta_new_src[2 * (lpl * k + 27 * q + b) + 1].val();
                        }
                        self.meta[lpl * k + 27 * q + b].write_enable.next =
                            self.s4_enter[lpl * k + 27 * q + b].q.val();
                        self.meta[lpl * k + 27 * q + b].write_address.next =
                            self.s4_bucket[b].q.val();
                        self.meta[lpl * k + 27 * q + b].write_data.next =
                            self.meta_new[lpl * k + 27 * q + b].val();
                        self.head[lpl * k + 27 * q + b].write_enable.next =
                            self.s4_enter[lpl * k + 27 * q + b].q.val();
                        self.head[lpl * k + 27 * q + b].write_address.next =
                            self.s4_bucket[b].q.val();
                        self.head[lpl * k + 27 * q + b].write_data.next = self.entry4.val();
                        self.head2[lpl * k + 27 * q + b].write_enable.next =
                            self.s4_enter[lpl * k + 27 * q + b].q.val();
                        self.head2[lpl * k + 27 * q + b].write_address.next =
                            self.s4_bucket[b].q.val();
                        self.head2[lpl * k + 27 * q + b].write_data.next =
                            self.old_eff[lpl * k + 27 * q + b].val();
                        if self.clearing.q.val()
                            & (self.pre_clear.q.val() | self.group_streamed[q].val())
                        {
                            self.meta[lpl * k + 27 * q + b].write_enable.next = true;
                            self.meta[lpl * k + 27 * q + b].write_address.next =
                                self.clear_at.q.val();
                            self.meta[lpl * k + 27 * q + b].write_data.next = 0.into();
                            self.head[lpl * k + 27 * q + b].write_enable.next = true;
                            self.head[lpl * k + 27 * q + b].write_address.next =
                                self.clear_at.q.val();
                            self.head[lpl * k + 27 * q + b].write_data.next = 0.into();
                            self.head2[lpl * k + 27 * q + b].write_enable.next = true;
                            self.head2[lpl * k + 27 * q + b].write_address.next =
                                self.clear_at.q.val();
                            self.head2[lpl * k + 27 * q + b].write_data.next = 0.into();
                        }
                        self.entry_pick[lpl * k + 27 * q + b].next = 0.into();
                        if self.s4_enter[lpl * k + 27 * q + b].q.val()
                            & self.meta_eff[lpl * k + 27 * q + b].val().get_bit(9)
                        {
                            self.entry_pick[lpl * k + 27 * q + b].next =
                                self.old_eff2[lpl * k + 27 * q + b].val();
                        }
                        self.entry_acc[b].next =
                            self.entry_acc[b].val() | self.entry_pick[lpl * k + 27 * q + b].val();
                        self.s5_meta_w[lpl * k + 27 * q + b].d.next =
                            self.meta_new[lpl * k + 27 * q + b].val();
                        self.s5_live[lpl * k + 27 * q + b].d.next =
                            self.live[lpl * k + 27 * q + b].val();
                        self.s5_head[lpl * k + 27 * q + b].d.next =
                            self.old_eff[lpl * k + 27 * q + b].val();
                        self.s5_head2[lpl * k + 27 * q + b].d.next =
                            self.old_eff2[lpl * k + 27 * q + b].val();
                    }
                }
            }
            for b in 0..27 {
                self.s5_entry[b].d.next = self.entry_acc[b].val();
            }
            self.s5_large.d.next = self.s4_large.q.val();
            self.s5_lprev.d.next = 0.into();
            if self.s4_large.q.val() {
                self.s5_lprev.d.next = self.s4_lprev.q.val();
            }
            self.s5_valid.d.next = self.s4_valid.q.val();
            self.s5_index.d.next = self.s4_index.q.val();
            self.s5_margin.d.next = self.s4_margin.q.val();
            for x in 0..3 {
                self.s5_min[x].d.next = self.s4_min[x].q.val();
                self.s5_max[x].d.next = self.s4_max[x].q.val();
            }

            // K+5: the box's entry is written: the old second of the list it entered (zero where
            // it entered none), or the chain's old second. (A later box sees the box's entry at its
            // K+4 at the earliest, and reads it five clocks after that, at its first visit.) A box
            // with lists to walk is written to the record queue; any other retires. The rest of the
            // chain is one list (the first), from the large box's successor (`lnext`, `lnext2`).
            self.succ_acc.next = self.s5_lprev.q.val();
            for b in 0..27 {
                self.succ_acc.next = self.succ_acc.val() | self.s5_entry[b].q.val();
            }
            // Per lane: the box's entry goes to its lane's bank; a record of the lane's lists to
            // walk to its record queue. The rest of the chains is one list on each lane: its own
            // chain as left (the lanes before the slow path's box's have none left).
            self.succ_addr.next = self.s5_index.q.val() >> self.lane_shift.val();
            for k in 0..self._lanes {
                self.any_live[k].next = false;
                for l in 0..self._lpl {
                    self.any_live[k].next =
                        self.any_live[k].val() | self.s5_live[lpl * k + l].q.val();
                }
                self.succ[k].write_enable.next =
                    self.s5_valid.q.val() & (self.s5_kind.q.val() == 0) & self.s5_lane[k].q.val();
                self.succ[k].write_address.next = self.succ_addr.val();
                self.succ[k].write_data.next = self.succ_acc.val();
                self.rec_write[k].next = self.s5_valid.q.val()
                    & (self.any_live[k].val()
                        | (self.s5_kind.q.val().get_bit(1)
                            & ((self.lnext[k].q.val() & self.top.val()) != 0)));
                self.retire_probe[k].next = self.s5_valid.q.val() & !self.rec_write[k].val();
                self.retire_probe_q[k].d.next = self.retire_probe[k].val();
                for l in 0..self._lpl {
                    self.rec[lpl * k + l].write_enable.next = self.rec_write[k].val();
                    self.rec[lpl * k + l].write_address.next = self.wp[k].q.val();
                    // A list head has the flag bit set; a list not to walk is written as none.
                    self.rec[lpl * k + l].write_data.next = 0.into();
                    self.rec2[lpl * k + l].write_enable.next = self.rec_write[k].val();
                    self.rec2[lpl * k + l].write_address.next = self.wp[k].q.val();
                    self.rec2[lpl * k + l].write_data.next = 0.into();
                    if self.s5_live[lpl * k + l].q.val() {
                        self.rec[lpl * k + l].write_data.next = self.s5_head[lpl * k + l].q.val();
                        self.rec2[lpl * k + l].write_data.next = self.s5_head2[lpl * k + l].q.val();
                    }
                    self.rec[lpl * k + l].read_address.next = self.rp[k].q.val();
                    self.rec2[lpl * k + l].read_address.next = self.rp[k].q.val();
                }
                if self.s5_kind.q.val().get_bit(1) {
                    self.rec[lpl * k].write_data.next = self.lnext[k].q.val();
                    self.rec2[lpl * k].write_data.next = self.lnext2[k].q.val();
                }
                self.rec_box[k].write_enable.next = self.rec_write[k].val();
                self.rec_box[k].write_address.next = self.wp[k].q.val();
                self.rec_box[k].read_address.next = self.rp[k].q.val();
                self.rec_box[k].in_index.next = self.s5_index.q.val();
                self.rec_box[k].in_margin.next = self.s5_margin.q.val();
                self.rec_box[k].in_kind.next = self.s5_kind.q.val();
                self.rec_box[k].in_min_x.next = self.s5_min[0].q.val();
                self.rec_box[k].in_min_y.next = self.s5_min[1].q.val();
                self.rec_box[k].in_min_z.next = self.s5_min[2].q.val();
                self.rec_box[k].in_max_x.next = self.s5_max[0].q.val();
                self.rec_box[k].in_max_y.next = self.s5_max[1].q.val();
                self.rec_box[k].in_max_z.next = self.s5_max[2].q.val();
                if self.rec_write[k].val() {
                    self.wp[k].d.next = self.wp[k].q.val() + 1;
                }
            }

            // The enumerator, per lane: it takes the lane's records in order and writes their
            // lists to the lane's list queue in the walker's order (bank, then group), each over two
            // clocks: on a clock it writes none it chooses the next list left (a one-hot), on a
            // later clock it writes that list, when at most two are queued (so that the write finds
            // room whatever the walker takes), and whether it is the record's last (no other list
            // left). It loads the next record on a clock it holds none. Each clock's logic runs from
            // registers alone: the walker only picks the queue's output.
            for k in 0..self._lanes {
                for b in 0..27 {
                    self.bank_any[27 * k + b].next = false;
                }
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.group_prior[lpl * k + 27 * q + b].next =
                            self.bank_any[27 * k + b].val();
                        self.bank_any[27 * k + b].next = self.bank_any[27 * k + b].val()
                            | self.e_rem[lpl * k + 27 * q + b].q.val();
                    }
                }
                // The banks before b: the chunks before b's, then b's chunk's banks before it.
                self.chunk_prior[10 * k].next = false;
                for c in 0..9 {
                    self.chunk_prior[10 * k + c + 1].next =
                        self.chunk_prior[10 * k + c].val() | self.chunk_left[9 * k + c].q.val();
                    self.bank_prior[27 * k + 3 * c].next = self.chunk_prior[10 * k + c].val();
                    for i in 1..3 {
                        self.bank_prior[27 * k + 3 * c + i].next =
                            self.bank_prior[27 * k + 3 * c + i - 1].val()
                                | self.bank_left[27 * k + 3 * c + i - 1].q.val();
                    }
                }
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.e_first[lpl * k + 27 * q + b].next =
                            self.e_rem[lpl * k + 27 * q + b].q.val()
                                & !self.group_prior[lpl * k + 27 * q + b].val()
                                & !self.bank_prior[27 * k + b].val();
                    }
                }
                self.e_push[k].next = self.e_chosen[k].q.val() & !self.lq_fill[3 * k + 2].q.val();
                self.e_load[k].next = (self.count[k].q.val() != 0) & !self.e_busy[k].q.val();
                for l in 0..self._lpl {
                    self.rd_live[lpl * k + l].next =
                        (self.rec[lpl * k + l].read_data.val() & self.top.val()) != 0;
                }
                // What is left after this clock, per bank and per chunk, registered for the next
                // choice: on a load, the record's lists; else the lists left but the chosen (the
                // lists left after its write, computed before the write's late enable: a choice
                // only follows a load or a write). The choice's widest ORs start at registers.
                for b in 0..27 {
                    self.bank_next[27 * k + b].next = false;
                    self.bank_load[27 * k + b].next = false;
                }
                for q in 0..self._groups {
                    for b in 0..27 {
                        self.bank_next[27 * k + b].next = self.bank_next[27 * k + b].val()
                            | (self.e_rem[lpl * k + 27 * q + b].q.val()
                                & !self.e_sel[lpl * k + 27 * q + b].q.val());
                        self.bank_load[27 * k + b].next = self.bank_load[27 * k + b].val()
                            | self.rd_live[lpl * k + 27 * q + b].val();
                    }
                }
                self.e_more[k].next = false;
                for c in 0..9 {
                    self.chunk_next[9 * k + c].next = false;
                    self.chunk_load[9 * k + c].next = false;
                    for i in 0..3 {
                        self.chunk_next[9 * k + c].next = self.chunk_next[9 * k + c].val()
                            | self.bank_next[27 * k + 3 * c + i].val();
                        self.chunk_load[9 * k + c].next = self.chunk_load[9 * k + c].val()
                            | self.bank_load[27 * k + 3 * c + i].val();
                    }
                    self.e_more[k].next = self.e_more[k].val() | self.chunk_next[9 * k + c].val();
                    self.chunk_left[9 * k + c].d.next = self.chunk_next[9 * k + c].val();
                    if self.e_load[k].val() {
                        self.chunk_left[9 * k + c].d.next = self.chunk_load[9 * k + c].val();
                    }
                }
                for b in 0..27 {
                    self.bank_left[27 * k + b].d.next = self.bank_next[27 * k + b].val();
                    if self.e_load[k].val() {
                        self.bank_left[27 * k + b].d.next = self.bank_load[27 * k + b].val();
                    }
                }
                self.e_out[k].next = 0.into();
                self.e_out2[k].next = 0.into();
                for l in 0..self._lpl {
                    self.e_pick[lpl * k + l].next = 0.into();
                    self.e_pick2[lpl * k + l].next = 0.into();
                    if self.e_sel[lpl * k + l].q.val() {
                        self.e_pick[lpl * k + l].next = self.e_head[lpl * k + l].q.val();
                        self.e_pick2[lpl * k + l].next = self.e_head2[lpl * k + l].q.val();
                    }
                    self.e_out[k].next = self.e_out[k].val() | self.e_pick[lpl * k + l].val();
                    self.e_out2[k].next = self.e_out2[k].val() | self.e_pick2[lpl * k + l].val();
                }
                self.lq_head[k].write_enable.next = self.e_push[k].val();
                self.lq_head[k].write_address.next = self.lq_wp[k].q.val();
                self.lq_head[k].write_data.next = self.e_out[k].val();
                self.lq_head[k].read_address.next = self.lq_rp[k].q.val();
                self.lq_head2[k].write_enable.next = self.e_push[k].val();
                self.lq_head2[k].write_address.next = self.lq_wp[k].q.val();
                self.lq_head2[k].write_data.next = self.e_out2[k].val();
                self.lq_head2[k].read_address.next = self.lq_rp[k].q.val();
                self.lq_last[k].write_enable.next = self.e_push[k].val();
                self.lq_last[k].write_address.next = self.lq_wp[k].q.val();
                self.lq_last[k].write_data.next = !self.e_more[k].val();
                self.lq_last[k].read_address.next = self.lq_rp[k].q.val();
                self.lq_box[k].write_enable.next = self.e_push[k].val();
                self.lq_box[k].write_address.next = self.lq_wp[k].q.val();
                self.lq_box[k].read_address.next = self.lq_rp[k].q.val();
                self.lq_box[k].in_index.next = self.e_index[k].q.val();
                self.lq_box[k].in_margin.next = self.e_margin[k].q.val();
                self.lq_box[k].in_kind.next = self.e_kind[k].q.val();
                self.lq_box[k].in_min_x.next = self.e_min[3 * k].q.val();
                self.lq_box[k].in_min_y.next = self.e_min[3 * k + 1].q.val();
                self.lq_box[k].in_min_z.next = self.e_min[3 * k + 2].q.val();
                self.lq_box[k].in_max_x.next = self.e_max[3 * k].q.val();
                self.lq_box[k].in_max_y.next = self.e_max[3 * k + 1].q.val();
                self.lq_box[k].in_max_z.next = self.e_max[3 * k + 2].q.val();
                if self.e_push[k].val() {
                    self.lq_wp[k].d.next = self.lq_wp[k].q.val() + 1;
                    self.e_chosen[k].d.next = false;
                    if !self.e_more[k].val() {
                        self.e_busy[k].d.next = false;
                    }
                    for l in 0..self._lpl {
                        if self.e_sel[lpl * k + l].q.val() {
                            self.e_rem[lpl * k + l].d.next = false;
                        }
                    }
                } else if self.e_busy[k].q.val() & !self.e_chosen[k].q.val() {
                    // The choice holds while its write waits: the lists left registered for it
                    // (`bank_left`, `chunk_left`) already leave the chosen out.
                    self.e_chosen[k].d.next = true;
                    for l in 0..self._lpl {
                        self.e_sel[lpl * k + l].d.next = self.e_first[lpl * k + l].val();
                    }
                }
                if self.e_load[k].val() {
                    self.rp[k].d.next = self.rp[k].q.val() + 1;
                    self.e_busy[k].d.next = true;
                    self.e_chosen[k].d.next = false;
                    self.e_index[k].d.next = self.rec_box[k].index.val();
                    self.e_margin[k].d.next = self.rec_box[k].margin.val();
                    self.e_kind[k].d.next = self.rec_box[k].kind.val();
                    self.e_min[3 * k].d.next = self.rec_box[k].min_x.val();
                    self.e_min[3 * k + 1].d.next = self.rec_box[k].min_y.val();
                    self.e_min[3 * k + 2].d.next = self.rec_box[k].min_z.val();
                    self.e_max[3 * k].d.next = self.rec_box[k].max_x.val();
                    self.e_max[3 * k + 1].d.next = self.rec_box[k].max_y.val();
                    self.e_max[3 * k + 2].d.next = self.rec_box[k].max_z.val();
                    for l in 0..self._lpl {
                        self.e_rem[lpl * k + l].d.next = self.rd_live[lpl * k + l].val();
                        self.e_head[lpl * k + l].d.next = self.rec[lpl * k + l].read_data.val();
                        self.e_head2[lpl * k + l].d.next = self.rec2[lpl * k + l].read_data.val();
                    }
                }
            }

            // The walker, per lane. The list's next box is known from registers alone (so that no
            // decision waits for the successor table's block RAM): the first known and not visited
            // (`q0`), or the second successor of the box visited two clocks before, arriving on the
            // table's registered output. Else the list is over: the walker takes the list queue's
            // next (its head now, its second on the next clock, from the queue) or, its record's
            // last list done, retires the record. (Flags are tested by a mask, not `>= top`: a
            // compare is a carry chain in synthesis.) A fetch of the slow path puts its box's
            // address on every lane's port B (all are idle); the sequencer takes its lane's.
            for k in 0..self._lanes {
                self.arrive[k].next = self.arrive_q[k].q.val();
                self.avail[k].next = self.q0v[k].q.val() | self.arrive[k].val();
                self.need[k].next = !self.avail[k].val();
                self.take[k].next = self.need[k].val() & self.lq_fill[3 * k].q.val();
                self.retire_rec[k].next =
                    self.need[k].val() & self.cur_valid[k].q.val() & self.cur_last[k].q.val();
                self.next_box[k].next = self.lq_head[k].read_data.val();
                if self.fetch_q.q.val() {
                    self.next_box[k].next = self.lcur.q.val();
                }
                if self.arrive[k].val() {
                    self.next_box[k].next = self.succ_q[k].q.val();
                }
                if self.q0v[k].q.val() {
                    self.next_box[k].next = self.q0[k].q.val();
                }
                // The box after `next_box`: `q1`, the arrival behind `q0`, or a taken list's second.
                self.after[k].next = self.succ_q[k].q.val();
                if self.q1v[k].q.val() {
                    self.after[k].next = self.q1[k].q.val();
                }
                self.after_v[k].next =
                    self.q1v[k].q.val() | (self.q0v[k].q.val() & self.arrive[k].val());
                if self.take[k].val() {
                    self.after[k].next = self.lq_head2[k].read_data.val();
                    self.after_v[k].next = (self.lq_head2[k].read_data.val() & self.top.val()) != 0;
                }
                self.next_ok[k].next = self.avail[k].val() | self.take[k].val();
                self.stall[k].next = self.fifo[k].almost_full.val();
                self.go[k].next = self.next_ok[k].val() & !self.stall[k].val();
                if self.go[k].val() {
                    self.q0[k].d.next = self.after[k].val();
                    self.q0v[k].d.next = self.after_v[k].val();
                    self.q1v[k].d.next = false;
                } else {
                    self.q0[k].d.next = self.next_box[k].val();
                    self.q0v[k].d.next = self.next_ok[k].val();
                    self.q1[k].d.next = self.after[k].val();
                    self.q1v[k].d.next = self.next_ok[k].val() & self.after_v[k].val();
                }
                self.r1[k].d.next = self.go[k].val();
                self.arrive_q[k].d.next =
                    self.r1[k].q.val() & ((self.succ[k].read_data_b.val() & self.top.val()) != 0);
                self.succ_q[k].d.next = self.succ[k].read_data_b.val();
                // The visit's box i: the list's, or the one taken this clock.
                self.v1_i[k].d.next = self.cur_index[k].q.val();
                self.v1_margin[k].d.next = self.cur_margin[k].q.val();
                self.v1_kind[k].d.next = self.cur_kind[k].q.val();
                for x in 0..3 {
                    self.v1_min[3 * k + x].d.next = self.cur_min[3 * k + x].q.val();
                    self.v1_max[3 * k + x].d.next = self.cur_max[3 * k + x].q.val();
                }
                if self.take[k].val() {
                    self.lq_rp[k].d.next = self.lq_rp[k].q.val() + 1;
                    self.cur_valid[k].d.next = true;
                    self.cur_last[k].d.next = self.lq_last[k].read_data.val();
                    self.cur_index[k].d.next = self.lq_box[k].index.val();
                    self.cur_margin[k].d.next = self.lq_box[k].margin.val();
                    self.v1_i[k].d.next = self.lq_box[k].index.val();
                    self.v1_margin[k].d.next = self.lq_box[k].margin.val();
                    self.cur_kind[k].d.next = self.lq_box[k].kind.val();
                    self.v1_kind[k].d.next = self.lq_box[k].kind.val();
                    self.cur_min[3 * k].d.next = self.lq_box[k].min_x.val();
                    self.cur_min[3 * k + 1].d.next = self.lq_box[k].min_y.val();
                    self.cur_min[3 * k + 2].d.next = self.lq_box[k].min_z.val();
                    self.cur_max[3 * k].d.next = self.lq_box[k].max_x.val();
                    self.cur_max[3 * k + 1].d.next = self.lq_box[k].max_y.val();
                    self.cur_max[3 * k + 2].d.next = self.lq_box[k].max_z.val();
                    self.v1_min[3 * k].d.next = self.lq_box[k].min_x.val();
                    self.v1_min[3 * k + 1].d.next = self.lq_box[k].min_y.val();
                    self.v1_min[3 * k + 2].d.next = self.lq_box[k].min_z.val();
                    self.v1_max[3 * k].d.next = self.lq_box[k].max_x.val();
                    self.v1_max[3 * k + 1].d.next = self.lq_box[k].max_y.val();
                    self.v1_max[3 * k + 2].d.next = self.lq_box[k].max_z.val();
                } else if self.retire_rec[k].val() {
                    self.cur_valid[k].d.next = false;
                }
                if self.e_push[k].val() & !self.take[k].val() {
                    self.lq_fill[3 * k].d.next = true;
                    self.lq_fill[3 * k + 1].d.next = self.lq_fill[3 * k].q.val();
                    self.lq_fill[3 * k + 2].d.next = self.lq_fill[3 * k + 1].q.val();
                }
                if self.take[k].val() & !self.e_push[k].val() {
                    self.lq_fill[3 * k].d.next = self.lq_fill[3 * k + 1].q.val();
                    self.lq_fill[3 * k + 1].d.next = self.lq_fill[3 * k + 2].q.val();
                    self.lq_fill[3 * k + 2].d.next = false;
                }
                self.rd_address[k].next =
                    (self.next_box[k].val() & self.index_mask.val()) >> self.lane_shift.val();
                self.succ[k].read_address_a.next = 0.into();
                self.succ[k].read_address_b.next = self.rd_address[k].val();
                for x in 0..3 {
                    self.kt_min[3 * k + x].read_address_b.next = self.rd_address[k].val();
                    self.kt_max[3 * k + x].read_address_b.next = self.rd_address[k].val();
                }
                self.kt_margin[k].read_address_b.next = self.rd_address[k].val();
                self.kt_group[k].read_address_b.next = self.rd_address[k].val();
            }
            // The visits, lane by lane, for the tests; their count, for the core.
            self.visit_acc.next = 0.into();
            for m in 0..4 {
                self.vis_pack_i[m].next = 0.into();
                self.vis_pack_j[m].next = 0.into();
            }
            self.visited_acc.next = 0.into();
            for k in 0..self._lanes {
                self.vis_i[k].value.next = self.v1_i[k].d.val();
                self.vis_j[k].value.next = self.next_box[k].val() & self.index_mask.val();
                if self.go[k].val() {
                    self.visit_acc.next = self.visit_acc.val() | self.lane_bit[k].val();
                }
                if self.v1_valid[k].q.val() {
                    self.visited_acc.next = self.visited_acc.val() | self.lane_bit[k].val();
                }
                self.vis_pack_i[k / 2].next = self.vis_pack_i[k / 2].val()
                    | (self.vis_i[k].resized.val() << self.lane_at[k].val());
                self.vis_pack_j[k / 2].next = self.vis_pack_j[k / 2].val()
                    | (self.vis_j[k].resized.val() << self.lane_at[k].val());
            }
            self.visit.next = self.visit_acc.val();
            self.visit_i0.next = self.vis_pack_i[0].val();
            self.visit_i1.next = self.vis_pack_i[1].val();
            self.visit_i2.next = self.vis_pack_i[2].val();
            self.visit_i3.next = self.vis_pack_i[3].val();
            self.visit_j0.next = self.vis_pack_j[0].val();
            self.visit_j1.next = self.vis_pack_j[1].val();
            self.visit_j2.next = self.vis_pack_j[2].val();
            self.visit_j3.next = self.vis_pack_j[3].val();
            // Counted field by field: no sum carries out of its field.
            self.visited_twos.next =
                (self.visited_acc.val() & 0x55) + ((self.visited_acc.val() >> 1) & 0x55);
            self.visited_fours.next =
                (self.visited_twos.val() & 0x33) + ((self.visited_twos.val() >> 2) & 0x33);
            self.visits_q.d.next = bit_cast::<4, 8>(
                (self.visited_fours.val() & 0x0f) + (self.visited_fours.val() >> 4),
            );
            self.visits.next = self.visits_q.q.val();

            // Credits and records, per lane. A box is accepted when every lane has a credit.
            self.inflight_up.next = self.accept.val() | self.inject.val();
            self.credit_acc.next = true;
            for k in 0..self._lanes {
                self.inflight_inc[k].next = self.inflight[k].q.val() + 1;
                self.inflight_dec[k].next = self.inflight[k].q.val() - 1;
                self.inflight_dec2[k].next = self.inflight[k].q.val() - 2;
                for m in 0..3 {
                    self.inflight_m[3 * k + m].next = 0.into();
                }
                if self.inflight_up.val() == self.retire_probe_q[k].q.val() {
                    self.inflight_m[3 * k].next = self.ones.val();
                } else if self.inflight_up.val() {
                    self.inflight_m[3 * k + 1].next = self.ones.val();
                } else {
                    self.inflight_m[3 * k + 2].next = self.ones.val();
                }
                self.inflight_n0[k].next = (self.inflight[k].q.val()
                    & self.inflight_m[3 * k].val())
                    | (self.inflight_inc[k].val() & self.inflight_m[3 * k + 1].val())
                    | (self.inflight_dec[k].val() & self.inflight_m[3 * k + 2].val());
                self.inflight_n1[k].next = (self.inflight_dec[k].val()
                    & self.inflight_m[3 * k].val())
                    | (self.inflight[k].q.val() & self.inflight_m[3 * k + 1].val())
                    | (self.inflight_dec2[k].val() & self.inflight_m[3 * k + 2].val());
                self.inflight[k].d.next = self.inflight_n0[k].val();
                if self.retire_rec[k].val() {
                    self.inflight[k].d.next = self.inflight_n1[k].val();
                }
                self.credit_acc.next = self.credit_acc.val()
                    & ((self.inflight_inc[k].val() & self.credits_used.val()) == 0);
                self.count_inc[k].next = self.count[k].q.val() + 1;
                self.count_dec[k].next = self.count[k].q.val() - 1;
                for m in 0..3 {
                    self.count_m[3 * k + m].next = 0.into();
                }
                if self.rec_write[k].val() == self.e_load[k].val() {
                    self.count_m[3 * k].next = self.ones.val();
                } else if self.rec_write[k].val() {
                    self.count_m[3 * k + 1].next = self.ones.val();
                } else {
                    self.count_m[3 * k + 2].next = self.ones.val();
                }
                self.count[k].d.next = (self.count[k].q.val() & self.count_m[3 * k].val())
                    | (self.count_inc[k].val() & self.count_m[3 * k + 1].val())
                    | (self.count_dec[k].val() & self.count_m[3 * k + 2].val());
            }
            // (No box is taken while the list heads are cleared before an update frame's load.)
            self.clear_last.next = self.clear_at.q.val() == self.last_bucket.val();
            self.credit_q.d.next =
                self.credit_acc.val() & !(self.pre_clear.q.val() & !self.clear_last.val());
            self.credit.next = self.credit_q.q.val();

            // The key check, per lane: V+1 the visited box's keys come from the lane's banks;
            // V+2 they are compared with the walking box's; V+3 a SAT test (lower index first)
            // enters the lane's test queue. A round passes a box whose home cell is in it;
            // the chain's boxes pass if the mask pairs the groups (`lrow`: the mask's row of the
            // slow path's box's group).
            self.lrow.next =
                self.fmask.q.val() >> (bit_cast::<MASK, GROUP>(self.lgroup.q.val()) << 3_u64);
            for k in 0..self._lanes {
                self.v1_valid[k].d.next = self.go[k].val();
                self.v1_j[k].d.next = self.next_box[k].val() & self.index_mask.val();
                self.v2_valid[k].d.next = self.v1_valid[k].q.val();
                self.v2_i[k].d.next = self.v1_i[k].q.val();
                self.v2_j[k].d.next = self.v1_j[k].q.val();
                self.v2_margin_i[k].d.next = self.v1_margin[k].q.val();
                self.v2_margin_j[k].d.next = self.rd_margin[k].val();
                self.v2_kind[k].d.next = self.v1_kind[k].q.val();
                self.v2_group_j[k].d.next = self.rd_group[k].val();
                for x in 0..3 {
                    // A round's record holds the round's cells; the large box's keys are the
                    // sequencer's.
                    self.v2_min_i[3 * k + x].d.next = self.v1_min[3 * k + x].q.val();
                    self.v2_max_i[3 * k + x].d.next = self.v1_max[3 * k + x].q.val();
                    if self.v1_kind[k].q.val().get_bit(0) {
                        self.v2_min_i[3 * k + x].d.next = self.lk_min[x].q.val();
                        self.v2_max_i[3 * k + x].d.next = self.lk_max[x].q.val();
                    }
                    self.wl_cell[3 * k + x].next =
                        self.v1_min[3 * k + x].q.val() >> self.cell_bits.val();
                    self.wl_keep[3 * k + x].next = 0.into();
                    if self.wl_cell[3 * k + x].val().any() {
                        self.wl_keep[3 * k + x].next = self.center_ones.val();
                    }
                    self.v2_wl[3 * k + x].d.next =
                        (self.wl_cell[3 * k + x].val() - 1) & self.wl_keep[3 * k + x].val();
                    self.v2_wh[3 * k + x].d.next =
                        self.v1_max[3 * k + x].q.val() >> self.cell_bits.val();
                    self.v2_jc[3 * k + x].d.next =
                        self.rd_min[3 * k + x].val() >> self.cell_bits.val();
                    self.v2_min_j[3 * k + x].d.next = self.rd_min[3 * k + x].val();
                    self.v2_max_j[3 * k + x].d.next = self.rd_max[3 * k + x].val();
                }
                self.overlap[k].next = (self.v2_min_i[3 * k].q.val()
                    <= self.v2_max_j[3 * k].q.val())
                    & (self.v2_min_j[3 * k].q.val() <= self.v2_max_i[3 * k].q.val())
                    & (self.v2_min_i[3 * k + 1].q.val() <= self.v2_max_j[3 * k + 1].q.val())
                    & (self.v2_min_j[3 * k + 1].q.val() <= self.v2_max_i[3 * k + 1].q.val())
                    & (self.v2_min_i[3 * k + 2].q.val() <= self.v2_max_j[3 * k + 2].q.val())
                    & (self.v2_min_j[3 * k + 2].q.val() <= self.v2_max_i[3 * k + 2].q.val());
                self.swap[k].next = self.v2_i[k].q.val() < self.v2_j[k].q.val();
                self.test_lo[k].next = self.v2_j[k].q.val();
                self.test_hi[k].next = self.v2_i[k].q.val();
                self.margin_lo[k].next = self.v2_margin_j[k].q.val();
                self.margin_hi[k].next = self.v2_margin_i[k].q.val();
                if self.swap[k].val() {
                    self.test_lo[k].next = self.v2_i[k].q.val();
                    self.test_hi[k].next = self.v2_j[k].q.val();
                    self.margin_lo[k].next = self.v2_margin_i[k].q.val();
                    self.margin_hi[k].next = self.v2_margin_j[k].q.val();
                }
                self.pack_lo[k].value.next = self.test_lo[k].val();
                self.pack_hi[k].value.next = self.test_hi[k].val();
                self.pack_mlo[k].value.next = self.margin_lo[k].val();
                self.pack_mhi[k].value.next = self.margin_hi[k].val();
                self.test_word[k].next = (self.pack_lo[k].resized.val() << self.at_a.val())
                    | (self.pack_hi[k].resized.val() << self.at_b.val())
                    | (self.pack_mlo[k].resized.val() << self.at_ma.val())
                    | self.pack_mhi[k].resized.val();
                self.home_ok[k].next = (self.v2_wl[3 * k].q.val() <= self.v2_jc[3 * k].q.val())
                    & (self.v2_jc[3 * k].q.val() <= self.v2_wh[3 * k].q.val())
                    & (self.v2_wl[3 * k + 1].q.val() <= self.v2_jc[3 * k + 1].q.val())
                    & (self.v2_jc[3 * k + 1].q.val() <= self.v2_wh[3 * k + 1].q.val())
                    & (self.v2_wl[3 * k + 2].q.val() <= self.v2_jc[3 * k + 2].q.val())
                    & (self.v2_jc[3 * k + 2].q.val() <= self.v2_wh[3 * k + 2].q.val());
                self.mask_row[k].next = self.lrow.val() >> self.v2_group_j[k].q.val();
                self.mask_ok[k].next = self.mask_row[k].val().get_bit(0);
                self.v3_valid[k].d.next = self.v2_valid[k].q.val();
                self.v3_overlap[k].d.next = self.overlap[k].val();
                self.v3_home[k].d.next = self.home_ok[k].val();
                self.v3_anywhere[k].d.next = !self.v2_kind[k].q.val().get_bit(0);
                self.v3_mask[k].d.next =
                    self.mask_ok[k].val() | !self.v2_kind[k].q.val().get_bit(1);
                self.v3_word[k].d.next = self.test_word[k].val();
                self.pass[k].next = self.v3_valid[k].q.val()
                    & self.v3_overlap[k].q.val()
                    & (self.v3_home[k].q.val() | self.v3_anywhere[k].q.val())
                    & self.v3_mask[k].q.val();
                self.fifo[k].write.next = self.pass[k].val();
                self.fifo[k].data_in.next = self.v3_word[k].q.val();
            }
            // The SAT test stream: the lowest lane with a SAT test on its queue's output issues it.
            // `out_valid` is its own OR of the queues' flags, not the last of the `lower` chain:
            // Verilator orders this block by groups of statements linked through the signals they
            // write, and the core's ready depends on `test_valid`, so `test_valid` must share no
            // written signal with the queues' ready terms below (else UNOPTFLAT, a loop).
            self.lower[0].next = false;
            self.out_word.next = 0.into();
            self.out_valid.next = false;
            for k in 0..self._lanes {
                self.issuer[k].next = self.fifo[k].valid.val() & !self.lower[k].val();
                self.lower[k + 1].next = self.lower[k].val() | self.fifo[k].valid.val();
                self.out_pick[k].next = 0.into();
                if self.issuer[k].val() {
                    self.out_pick[k].next = self.fifo[k].data_out.val();
                }
                self.out_word.next = self.out_word.val() | self.out_pick[k].val();
                self.out_valid.next = self.out_valid.val() | self.fifo[k].valid.val();
            }
            self.test_valid.next = self.out_valid.val();
            self.unpack_a.next = self.out_word.val() >> self.at_a.val();
            self.unpack_b.next = self.out_word.val() >> self.at_b.val();
            self.unpack_ma.next = self.out_word.val() >> self.at_ma.val();
            self.test_a.next = bit_cast::<A, TEST_WORD>(self.unpack_a.val());
            self.test_b.next = bit_cast::<A, TEST_WORD>(self.unpack_b.val());
            self.test_ma.next = bit_cast::<MARGIN, TEST_WORD>(self.unpack_ma.val());
            self.test_mb.next = bit_cast::<MARGIN, TEST_WORD>(self.out_word.val());
            for k in 0..self._lanes {
                self.fifo[k].ready.next = self.test_ready.val() & self.issuer[k].val();
            }
            self.lanes_overflow.next = false;
            for k in 0..self._lanes {
                self.fifo[k].clear.next = self.start.val();
                self.lanes_overflow.next = self.lanes_overflow.val() | self.fifo[k].overflow.val();
            }
            self.queue_overflow.next = self.lanes_overflow.val();

            // The end: every box accepted and retired, the slow path over; then the clear, one
            // bucket a clock.
            self.done_walk.next = self.idle.q.val()
                & ((self.slow.q.val() == SlowState::Over)
                    | ((self.slow.q.val() == SlowState::Fetch) & !self.large_left.val()));
            self.walked.next = self.done_walk.val();
            if self.done_walk.val() & !self.clearing.q.val() & !self.cleared.q.val() {
                self.clearing.d.next = true;
                self.clear_at.d.next = 0.into();
            }
            if self.clearing.q.val() {
                self.clear_at.d.next = self.clear_at.q.val() + 1;
                if self.clear_last.val() {
                    self.clearing.d.next = false;
                    self.pre_clear.d.next = false;
                    self.cleared.d.next = !self.pre_clear.q.val();
                }
            }
            self.drained.next = self.cleared.q.val();
            for k in 0..self._lanes {
                self.drained.next = self.drained.val()
                    & self.fifo[k].empty.val()
                    & !self.v1_valid[k].q.val()
                    & !self.v2_valid[k].q.val()
                    & !self.pass[k].val();
            }
            self.finished.next = self.drained.val();
            self.too_wide.next = self.wide.q.val();
            if self.start.val() {
                self.idle.d.next = false;
                self.credit_q.d.next = true;
                self.clearing.d.next = false;
                self.cleared.d.next = false;
                // An update frame (with resident groups) clears every list first; a haptic frame
                // takes the haptic mask and the resident chain.
                self.update_q.d.next = self.update.val();
                self.fmask.d.next = self.mask.val();
                self.pre_clear.d.next = false;
                if self.has_resident.val() {
                    if self.update.val() {
                        self.clearing.d.next = true;
                        self.clear_at.d.next = 0.into();
                        self.pre_clear.d.next = true;
                        self.credit_q.d.next = false;
                    } else {
                        self.fmask.d.next = self.haptic_mask.val();
                    }
                }
                self.slow.d.next = SlowState::Fetch;
                self.wide.d.next = false;
                for k in 0..self._lanes {
                    self.wp[k].d.next = 0.into();
                    self.rp[k].d.next = 0.into();
                    self.count[k].d.next = 0.into();
                    self.inflight[k].d.next = 0.into();
                    self.cur_valid[k].d.next = false;
                    self.e_busy[k].d.next = false;
                    self.e_chosen[k].d.next = false;
                    self.lq_wp[k].d.next = 0.into();
                    self.lq_rp[k].d.next = 0.into();
                    for m in 0..3 {
                        self.lq_fill[3 * k + m].d.next = false;
                    }
                    self.q0v[k].d.next = false;
                    self.q1v[k].d.next = false;
                    self.r1[k].d.next = false;
                    self.arrive_q[k].d.next = false;
                    self.lnext[k].d.next = 0.into();
                    self.lnext2[k].d.next = 0.into();
                    if self.has_resident.val() {
                        if self.update.val() {
                            self.res_lnext[k].d.next = 0.into();
                            self.res_lnext2[k].d.next = 0.into();
                        } else {
                            self.lnext[k].d.next = self.res_lnext[k].q.val();
                            self.lnext2[k].d.next = self.res_lnext2[k].q.val();
                        }
                    }
                }
            }
        }
    }
}
