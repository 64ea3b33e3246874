//! `GridPhase`: the grid broad phase (`broad_phase = "grid"`), the spatial hash of
//! `obb_model::fixed::grid` built while the boxes arrive, on the clocks of
//! `obb_model::fixed::grid_clocks` (docs/hardware.md, "The grid").
//!
//! | clock | stage |
//! | --- | --- |
//! | K | a box's keys leave the projection (`key_valid`) |
//! | K+1 to K+3 | `GridCells`: the window's cells, and per bank (cell coordinates mod 3) its cell's bucket and fingerprint |
//! | K+3 | the list heads of every bank and group are read (distributed RAM, at once) and registered |
//! | K+4 | the lists to walk decided; the box is entered in its home cell's list (the entry the box before wrote at K+3 forwarded) |
//! | K+5 | its entry (second successor) written; the lists to walk written to the record queue, or the box retires |
//! | K+6 | the enumerator may load the record |
//! | K+7 | it chooses the record's first list |
//! | K+8 | it writes it to the list queue |
//! | K+9 | the walker may take it |
//!
//! Lists are stored at `27 h + b` for bank b and group h, so that every index the Verilog needs
//! is a literal expression of loop variables. The enumerator writes them bank by bank, group by
//! group, as the model walks them.
//!
//! The successor table holds each box's *second* successor (the box two places after it in its
//! list), and its block RAM's output is registered: a visit at V reads the entry of the box it
//! visits, which names the box to visit at V+2. So a list is two chains walked in turn, and the
//! walker still makes one visit per clock, in the list's order, while no path runs from the
//! block RAM's output through logic (its clock-to-output is most of a 4 ns clock). The list
//! heads, the record queue and the list queue carry each list's first two boxes. The next
//! visit is the first of the list's boxes known and not visited (at most two, held in
//! registers while a stall lasts), or the arriving second successor, or, the list over, the
//! list queue's next list. A visit's keys are read on the key table's port B (`rd_addr`; the walking box's keys ride in
//! the list queue), compared two clocks later, registered and, if they overlap, written to the candidate
//! queue (`PairFifo`), which the core drains on clocks it does not accept a box. At the end of
//! the walk every bucket is written empty, one a clock, so that the next frame finds the lists
//! clear.
//!
//! A box larger than a cell (*large*) is entered in no list: at K+3 it joins the chain of large
//! boxes (`lnext` and `lnext2`, its first two, latest first) and its successor entry takes the
//! chain's old second. The slow path runs when the load is over and nothing is in flight
//! (*idle*): a sequencer fetches each large box of the chain (its keys on port B, its entry: the
//! large box two places on), plans its window, and injects its *rounds*
//! into the probe as boxes whose keys span two or three cells per axis (kind *round*: they read
//! lists and enter none; the key check takes the large box's keys, and passes a box only if its
//! home cell is in the round, so a list read in two rounds gives its pairs once); then, when
//! large boxes follow, one record of one list, the rest of the chain (kind *partner*: the key
//! check applies the group mask). A window of more than `MAX_WINDOW` cells on an axis ends the
//! slow path and raises the sticky `too_wide`: the frame is incomplete.

use crate::box_queue::{BoxQueue, KIND};
use crate::dist_ram::DistRam;
use crate::grid_cells::{vec, GridCells, BUCKET, FP};
use crate::pair_fifo::{self, PairFifo};
use crate::projection::{CENTER, MARGIN};
use crate::radix::VAL;
use crate::table_ram::TableRam;
use obb_model::fixed::config::GROUP_BITS;
use obb_model::fixed::cycles::{GRID_CAND_STALL, GRID_CREDITS};
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
/// Width of a box index in the candidate queue (as on the core's pair stream).
const INDEX: usize = VAL;
/// A candidate: a, b (a < b), their margins.
const CAND: usize = 2 * INDEX + 2 * MARGIN;
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
    /// Register its keys, group, margin (its entry, the chain's box two on, is read at `Plan`).
    Read,
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
const _: () = assert!(GRID_CAND_STALL as u64 + 3 < pair_fifo::DEPTH);

#[derive(LogicBlock)]
pub struct GridPhase<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Pulse: a new frame (the list heads were cleared at the end of the last).
    pub start: Signal<In, Bit>,
    /// A box is accepted this clock (the core's load).
    pub accept: Signal<In, Bit>,
    /// Every box of the frame has been accepted.
    pub loaded: Signal<In, Bit>,
    /// Fewer than `GRID_CREDITS` boxes accepted and not retired: the core may accept.
    pub credit: Signal<Out, Bit>,
    /// A box's keys, margin and group from the projection, and its index.
    pub key_valid: Signal<In, Bit>,
    pub key_index: Signal<In, Bits<A>>,
    /// (Axis by axis, not arrays: the core holds the block in a list, and rust-hdl emits an
    /// array port of a listed block wrongly.)
    pub key_min_x: Signal<In, Bits<CENTER>>,
    pub key_min_y: Signal<In, Bits<CENTER>>,
    pub key_min_z: Signal<In, Bits<CENTER>>,
    pub key_max_x: Signal<In, Bits<CENTER>>,
    pub key_max_y: Signal<In, Bits<CENTER>>,
    pub key_max_z: Signal<In, Bits<CENTER>>,
    pub key_margin: Signal<In, Bits<MARGIN>>,
    pub key_group: Signal<In, Bits<GROUP>>,
    /// The key table's port B: the visited box (`visit`), its keys and margin a clock later.
    pub visit: Signal<Out, Bit>,
    pub visit_i: Signal<Out, Bits<A>>,
    pub rd_addr: Signal<Out, Bits<A>>,
    pub rd_min_x: Signal<In, Bits<CENTER>>,
    pub rd_min_y: Signal<In, Bits<CENTER>>,
    pub rd_min_z: Signal<In, Bits<CENTER>>,
    pub rd_max_x: Signal<In, Bits<CENTER>>,
    pub rd_max_y: Signal<In, Bits<CENTER>>,
    pub rd_max_z: Signal<In, Bits<CENTER>>,
    pub rd_margin: Signal<In, Bits<MARGIN>>,
    pub rd_group: Signal<In, Bits<GROUP>>,
    /// The candidate stream (first word fall-through): taken on a clock with `cand_ready`.
    pub cand_valid: Signal<Out, Bit>,
    pub cand_ready: Signal<In, Bit>,
    pub cand_a: Signal<Out, Bits<A>>,
    pub cand_b: Signal<Out, Bits<A>>,
    pub cand_ma: Signal<Out, Bits<MARGIN>>,
    pub cand_mb: Signal<Out, Bits<MARGIN>>,
    /// Every box has retired and the slow path is done: the walk is over (the list heads are
    /// being cleared).
    pub walked: Signal<Out, Bit>,
    /// The list heads are clear, the candidate queue is empty: the grid's frame is over.
    pub finished: Signal<Out, Bit>,
    /// Sticky for the frame: a large box's window spans more than `MAX_WINDOW` cells on an
    /// axis; the slow path stopped, the frame is incomplete.
    pub too_wide: Signal<Out, Bit>,
    // Configuration.
    /// Groups with lists (`grid_groups`), and lists: 27 per group.
    _groups: usize,
    _lists: usize,
    last_bucket: Constant<Bits<BUCKET>>,
    mask: Constant<Bits<MASK>>,
    /// The bits of `inflight` at or above `GRID_CREDITS` (a power of two): none set, a credit
    /// is left. (A mask, not a compare: a compare is a carry chain in synthesis.)
    credits_used: Constant<Bits<COUNT>>,
    /// A successor's or a record head's flag bit (`2^A`).
    top: Constant<Bits<C>>,
    /// Per list (stored at `27 h + b`): its group h.
    list_group: Vec<Constant<Bits<GROUP>>>,
    /// log2 of the cell edge; the widest span of a large box in cells (`MAX_WINDOW - 2`).
    cell_bits: Constant<Bits<8>>,
    max_span: Constant<Bits<CENTER>>,
    /// The candidate's fields' places in the queue's word.
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
    /// Per list: the box entered it and it held a box (its old second is the box's entry).
    s5_enter: Vec<DFF<Bit>>,
    /// Per list: the box entered it, and the owner it wrote (forwarded to the next box).
    s5_wrote: Vec<DFF<Bit>>,
    s5_meta_w: Vec<DFF<Bits<META>>>,
    /// A large box arrived: the chain's old second is its entry.
    s5_large: DFF<Bit>,
    s5_lprev: DFF<Bits<C>>,
    // Memories.
    /// Per list: the owner (valid, mixed, fingerprint) and the latest box, by bucket.
    meta: Vec<DistRam<Bits<META>, BUCKET>>,
    head: Vec<DistRam<Bits<C>, BUCKET>>,
    /// Per list: the box after the latest (its second), by bucket.
    head2: Vec<DistRam<Bits<C>, BUCKET>>,
    /// Each box's second successor on its list (the top bit: there is one).
    succ: TableRam<Bits<C>, A>,
    /// The record queue: per list its head (top bit: walk it), and the box's index, keys, margin.
    rec: Vec<DistRam<Bits<C>, SLOT>>,
    /// Per list: its second box (top bit: there is one).
    rec2: Vec<DistRam<Bits<C>, SLOT>>,
    rec_box: BoxQueue<SLOT, C>,
    wp: DFF<Bits<SLOT>>,
    rp: DFF<Bits<SLOT>>,
    count: DFF<Bits<COUNT>>,
    inflight: DFF<Bits<COUNT>>,
    // The enumerator: it holds a record; its lists left, their heads; the box's index, keys,
    // margin, kind.
    e_busy: DFF<Bit>,
    e_rem: Vec<DFF<Bit>>,
    e_head: Vec<DFF<Bits<C>>>,
    e_head2: Vec<DFF<Bits<C>>>,
    /// The list chosen on a clock before, to write next: one-hot.
    e_chosen: DFF<Bit>,
    e_sel: Vec<DFF<Bit>>,
    e_index: DFF<Bits<C>>,
    e_min: [DFF<Bits<CENTER>>; 3],
    e_max: [DFF<Bits<CENTER>>; 3],
    e_margin: DFF<Bits<MARGIN>>,
    e_kind: DFF<Bits<KIND>>,
    /// The list queue: per entry a list's head, its box, whether it is its record's last.
    lq_head: DistRam<Bits<C>, LQ>,
    lq_head2: DistRam<Bits<C>, LQ>,
    lq_box: BoxQueue<LQ, C>,
    lq_last: DistRam<Bit, LQ>,
    lq_wp: DFF<Bits<LQ>>,
    lq_rp: DFF<Bits<LQ>>,
    /// Its fill as a thermometer code: `lq_fill[k]`, more than k lists are queued (at most three:
    /// the enumerator writes at two or fewer). Each bit's next value is one LUT of the walker's
    /// take.
    lq_fill: [DFF<Bit>; 3],
    // The walker: the list's box, whether the list is its record's last.
    cur_valid: DFF<Bit>,
    cur_last: DFF<Bit>,
    cur_index: DFF<Bits<C>>,
    cur_min: [DFF<Bits<CENTER>>; 3],
    cur_max: [DFF<Bits<CENTER>>; 3],
    cur_margin: DFF<Bits<MARGIN>>,
    cur_kind: DFF<Bits<KIND>>,
    /// The successor table's output, registered: the second successor of the box read two
    /// clocks before. A visit one clock before (`r1`) reads it; `arrive_q`: a visit two clocks
    /// before read it and it names a box (its flag), registered with it so that the walker's
    /// decisions start at registers (one LUT follows the block RAM's output).
    succ_q: DFF<Bits<C>>,
    r1: DFF<Bit>,
    arrive_q: DFF<Bit>,
    /// The list's next boxes known and not yet visited, in order (at most two: the successor
    /// of a box arrives only after the box before it was visited).
    q0v: DFF<Bit>,
    q0: DFF<Bits<C>>,
    q1v: DFF<Bit>,
    q1: DFF<Bits<C>>,
    // The key check: the visit (V+1), the keys of both boxes (V+2), the verdict (V+3).
    v1_valid: DFF<Bit>,
    v1_i: DFF<Bits<C>>,
    v1_j: DFF<Bits<C>>,
    v1_min: [DFF<Bits<CENTER>>; 3],
    v1_max: [DFF<Bits<CENTER>>; 3],
    v1_margin: DFF<Bits<MARGIN>>,
    v1_kind: DFF<Bits<KIND>>,
    v2_valid: DFF<Bit>,
    v2_i: DFF<Bits<C>>,
    v2_j: DFF<Bits<C>>,
    v2_min_i: [DFF<Bits<CENTER>>; 3],
    v2_max_i: [DFF<Bits<CENTER>>; 3],
    v2_min_j: [DFF<Bits<CENTER>>; 3],
    v2_max_j: [DFF<Bits<CENTER>>; 3],
    v2_margin_i: DFF<Bits<MARGIN>>,
    v2_margin_j: DFF<Bits<MARGIN>>,
    v2_kind: DFF<Bits<KIND>>,
    /// A round passes a visited box whose home cell, its first cell j plus one, lies within
    /// the round's first and last cells. All three are compared less one, so that no adder
    /// stands behind the key table's block RAM (j is its key shifted) nor before the
    /// compares: the round's first cell less one (zero for cell zero: every home is at least
    /// one), its last cell less one (its largest key shifted), j; the visited box's group.
    v2_wl: [DFF<Bits<CENTER>>; 3],
    v2_wh: [DFF<Bits<CENTER>>; 3],
    v2_jc: [DFF<Bits<CENTER>>; 3],
    v2_group_j: DFF<Bits<GROUP>>,
    /// V+3: the verdict and the candidate, registered, so that the compares and the queue's
    /// count (chosen by the write) are not one path.
    v3_write: DFF<Bit>,
    v3_word: DFF<Bits<CAND>>,
    fifo: PairFifo<CAND>,
    // End of frame.
    clearing: DFF<Bit>,
    cleared: DFF<Bit>,
    clear_at: DFF<Bits<BUCKET>>,
    // The slow path: the chain's next large box (top bit: there is one), the box on the path,
    // its keys, margin and group, its window's first cells and its cells less one, the round's
    // first cells and the window's cells after them (less one).
    slow: DFF<SlowState>,
    lnext: DFF<Bits<C>>,
    lnext2: DFF<Bits<C>>,
    lcur: DFF<Bits<C>>,
    lk_min: [DFF<Bits<CENTER>>; 3],
    /// Its first cell plus the widest span (`Read`): the window is too wide when its last
    /// cell is beyond (one carry chain in `Plan`, not a difference and a compare).
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
    /// The injected record (at K), its kind and its keys: registered, so that the probe's
    /// first stage takes them through one multiplexer.
    inj: DFF<Bit>,
    inj_kind: DFF<Bits<KIND>>,
    inj_min: [DFF<Bits<CENTER>>; 3],
    inj_max: [DFF<Bits<CENTER>>; 3],
    // Combinational.
    /// The ports' keys as arrays: the arriving box's, the box read on port B.
    key_min: [Signal<Local, Bits<CENTER>>; 3],
    key_max: [Signal<Local, Bits<CENTER>>; 3],
    rd_min: [Signal<Local, Bits<CENTER>>; 3],
    rd_max: [Signal<Local, Bits<CENTER>>; 3],
    allowed: Signal<Local, Bits<MASK>>,
    /// Per list: the box's mask bits shifted to the list's group.
    allow: Vec<Signal<Local, Bits<MASK>>>,
    /// K+4, per list: the entry the box before wrote is this box's (same bucket, written); the
    /// owner and the head the box sees; walk it; its owner after the entry.
    fwd: Vec<Signal<Local, Bit>>,
    /// K+3, per bank: its bucket is the one the box ahead (at K+4) writes.
    same: [Signal<Local, Bit>; 27],
    /// K+4, per list, from the owner as read (`2 l`) and as forwarded (`2 l + 1`), side by side
    /// so that the compares start at registers and the forwarding only picks: the owner, walk
    /// the list, the owner after the entry.
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
    succ_pick: Vec<Signal<Local, Bits<C>>>,
    succ_acc: Signal<Local, Bits<C>>,
    any_live: Signal<Local, Bit>,
    /// The enumerator's choice, in the walker's order (bank, then group): per bank, a list is
    /// left in it; per list, a list of a lower group is left in its bank; a list is left in a
    /// bank before b (`bank_prior[b]`); the list is the first left. Pure ANDs and ORs, which
    /// synthesis balances into trees (written as `if`s, they became multiplexer chains).
    bank_any: [Signal<Local, Bit>; 27],
    /// Per bank, a list is left in it: registered (from the lists' next values), so that the
    /// choice's widest OR (`bank_prior`) starts at registers.
    bank_next: [Signal<Local, Bit>; 27],
    bank_left: [DFF<Bit>; 27],
    group_prior: Vec<Signal<Local, Bit>>,
    bank_prior: [Signal<Local, Bit>; 28],
    e_first: Vec<Signal<Local, Bit>>,
    /// A list is written to the list queue: its head (each list's masked by the one-hot choice,
    /// then ORed); a list other than the chosen is left (none: it is the record's last).
    e_push: Signal<Local, Bit>,
    e_pick: Vec<Signal<Local, Bits<C>>>,
    e_out: Signal<Local, Bits<C>>,
    e_pick2: Vec<Signal<Local, Bits<C>>>,
    e_out2: Signal<Local, Bits<C>>,
    e_more: Signal<Local, Bit>,
    /// A record is loaded.
    e_load: Signal<Local, Bit>,
    // The walker.
    /// A box of the list arrives on the registered successor; a box is known to visit; the
    /// box after it (and whether there is one).
    arrive: Signal<Local, Bit>,
    avail: Signal<Local, Bit>,
    after: Signal<Local, Bits<C>>,
    after_v: Signal<Local, Bit>,
    need: Signal<Local, Bit>,
    retire_rec: Signal<Local, Bit>,
    take: Signal<Local, Bit>,
    rd_live: Vec<Signal<Local, Bit>>,
    /// Credits and records: this clock's changes.
    /// Each count's next value is selected among its neighbours, computed from the register
    /// alone, so that the late enables only pick: an adder after them was a carry chain behind
    /// the walker's and the enumerator's decisions. The selection is an AND-OR of masks (all
    /// ones where the enable picks): a multiplexer of sums is folded back by synthesis into
    /// one adder of a selected operand, the carry chain again.
    inflight_up: Signal<Local, Bit>,
    inflight_inc: Signal<Local, Bits<COUNT>>,
    inflight_dec: Signal<Local, Bits<COUNT>>,
    inflight_dec2: Signal<Local, Bits<COUNT>>,
    /// Masks of the early changes (the load's or the slow path's box, a probe's retirement):
    /// they cancel, one more, one less. The values without and with a record's retirement,
    /// which comes late from the walker's decision and only picks one of them.
    inflight_m: [Signal<Local, Bits<COUNT>>; 3],
    inflight_n0: Signal<Local, Bits<COUNT>>,
    inflight_n1: Signal<Local, Bits<COUNT>>,
    count_inc: Signal<Local, Bits<COUNT>>,
    count_dec: Signal<Local, Bits<COUNT>>,
    /// Masks: keep, one more, one less.
    count_m: [Signal<Local, Bits<COUNT>>; 3],
    ones: Constant<Bits<COUNT>>,
    cand_word: Signal<Local, Bits<CAND>>,
    unpack_a: Signal<Local, Bits<CAND>>,
    unpack_b: Signal<Local, Bits<CAND>>,
    unpack_ma: Signal<Local, Bits<CAND>>,
    cand: Signal<Local, Bits<C>>,
    /// The box's index with the flag bit, a list head: at K+3 (a large box joins the chain), at
    /// K+4 (it enters a list), at K+5 (forwarded).
    entry: Signal<Local, Bits<C>>,
    entry4: Signal<Local, Bits<C>>,
    entry5: Signal<Local, Bits<C>>,
    cand_ok: Signal<Local, Bit>,
    go: Signal<Local, Bit>,
    stall: Signal<Local, Bit>,
    retire_probe: Signal<Local, Bit>,
    rec_write: Signal<Local, Bit>,
    overlap: Signal<Local, Bit>,
    swap: Signal<Local, Bit>,
    cand_lo: Signal<Local, Bits<INDEX>>,
    cand_hi: Signal<Local, Bits<INDEX>>,
    margin_lo: Signal<Local, Bits<MARGIN>>,
    margin_hi: Signal<Local, Bits<MARGIN>>,
    done_walk: Signal<Local, Bit>,
    /// The slow path: nothing in flight after the load; this clock fetches a large box,
    /// injects a record (and of which kind, with which keys).
    idle: Signal<Local, Bit>,
    fetch: Signal<Local, Bit>,
    inject: Signal<Local, Bit>,
    inject_kind: Signal<Local, Bits<KIND>>,
    inject_min: [Signal<Local, Bits<CENTER>>; 3],
    inject_max: [Signal<Local, Bits<CENTER>>; 3],
    /// Per axis: the cells left, the round's included, less two (`rleft`, kept by steps: a
    /// difference would be a carry chain before the compares; less two, so that the plan's
    /// difference needs no increment); the round has three cells; it is the
    /// axis's last; the round's first cell plus 1, 2, 3; the cells left less 2, 3; masks (all
    /// ones where the round has two, three cells: an AND-OR, which synthesis does not fold
    /// into an adder of a selected operand); the next round's first cell and cells left.
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
    /// All ones; all but the low bit; all but the two low bits.
    center_ones: Constant<Bits<CENTER>>,
    above_one: Constant<Bits<CENTER>>,
    above_three: Constant<Bits<CENTER>>,
    plan_lo: [Signal<Local, Bits<CENTER>>; 3],
    plan_hi: [Signal<Local, Bits<CENTER>>; 3],
    plan_wide: Signal<Local, Bit>,
    /// K+3: a large arriving box joins the chain.
    large_in: Signal<Local, Bit>,
    /// V+2: the visited box's home is in the round; the mask pairs the groups; the pair passes.
    home_ok: Signal<Local, Bit>,
    /// The round's first cell; all ones unless it is cell zero.
    wl_cell: [Signal<Local, Bits<CENTER>>; 3],
    wl_keep: [Signal<Local, Bits<CENTER>>; 3],
    mask_row: Signal<Local, Bits<MASK>>,
    mask_ok: Signal<Local, Bit>,
    pass: Signal<Local, Bit>,
}

impl<const A: usize, const C: usize> GridPhase<A, C> {
    /// The grid of configuration `cfg` (valid; its cell edge fits the keys).
    pub fn new(cfg: &HwConfig) -> GridPhase<A, C> {
        assert!(C == A + 1, "successors need one bit more than indices");
        let shape = GridShape::new(cfg);
        let groups = shape.groups as usize;
        let lists = BANKS * groups;
        let mut mask = Bits::<MASK>::default();
        for g in 0..1u32 << GROUP {
            for h in 0..1u32 << GROUP {
                if cfg.groups.allows(g, h) {
                    mask = mask.replace_bit((g << GROUP | h) as usize, true);
                }
            }
        }
        let buckets = 1u64 << shape.hash_bits;
        GridPhase {
            clock: Default::default(),
            start: Default::default(),
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
            visit_i: Default::default(),
            rd_addr: Default::default(),
            rd_min_x: Default::default(),
            rd_min_y: Default::default(),
            rd_min_z: Default::default(),
            rd_max_x: Default::default(),
            rd_max_y: Default::default(),
            rd_max_z: Default::default(),
            rd_margin: Default::default(),
            rd_group: Default::default(),
            cand_valid: Default::default(),
            cand_ready: Default::default(),
            cand_a: Default::default(),
            cand_b: Default::default(),
            cand_ma: Default::default(),
            cand_mb: Default::default(),
            walked: Default::default(),
            finished: Default::default(),
            too_wide: Default::default(),
            _groups: groups,
            _lists: lists,
            last_bucket: Constant::new((buckets - 1).into()),
            mask: Constant::new(mask),
            credits_used: Constant::new(((1u64 << COUNT) - GRID_CREDITS as u64).into()),
            top: Constant::new((1u64 << A).into()),
            list_group: (0..lists)
                .map(|l| Constant::new(((l / BANKS) as u64).into()))
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
            s5_enter: vec(lists),
            s5_wrote: vec(lists),
            s5_meta_w: vec(lists),
            s5_large: Default::default(),
            s5_lprev: Default::default(),
            meta: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            head: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            head2: (0..lists).map(|_| DistRam::zeroed(buckets)).collect(),
            succ: Default::default(),
            rec: vec(lists),
            rec2: vec(lists),
            rec_box: Default::default(),
            wp: Default::default(),
            rp: Default::default(),
            count: Default::default(),
            inflight: Default::default(),
            e_busy: Default::default(),
            e_rem: vec(lists),
            e_head: vec(lists),
            e_head2: vec(lists),
            e_chosen: Default::default(),
            e_sel: vec(lists),
            e_index: Default::default(),
            e_min: Default::default(),
            e_max: Default::default(),
            e_margin: Default::default(),
            e_kind: Default::default(),
            lq_head: Default::default(),
            lq_head2: Default::default(),
            lq_box: Default::default(),
            lq_last: Default::default(),
            lq_wp: Default::default(),
            lq_rp: Default::default(),
            lq_fill: Default::default(),
            cur_valid: Default::default(),
            cur_last: Default::default(),
            cur_index: Default::default(),
            cur_min: Default::default(),
            cur_max: Default::default(),
            cur_margin: Default::default(),
            cur_kind: Default::default(),
            succ_q: Default::default(),
            r1: Default::default(),
            arrive_q: Default::default(),
            q0v: Default::default(),
            q0: Default::default(),
            q1v: Default::default(),
            q1: Default::default(),
            v1_valid: Default::default(),
            v1_i: Default::default(),
            v1_j: Default::default(),
            v1_min: Default::default(),
            v1_max: Default::default(),
            v1_margin: Default::default(),
            v1_kind: Default::default(),
            v2_valid: Default::default(),
            v2_i: Default::default(),
            v2_j: Default::default(),
            v2_min_i: Default::default(),
            v2_max_i: Default::default(),
            v2_min_j: Default::default(),
            v2_max_j: Default::default(),
            v2_margin_i: Default::default(),
            v2_margin_j: Default::default(),
            v2_kind: Default::default(),
            v2_wl: Default::default(),
            v2_wh: Default::default(),
            v2_jc: Default::default(),
            v2_group_j: Default::default(),
            v3_write: Default::default(),
            v3_word: Default::default(),
            fifo: PairFifo::new(GRID_CAND_STALL as u64),
            clearing: Default::default(),
            cleared: Default::default(),
            clear_at: Default::default(),
            slow: Default::default(),
            lnext: Default::default(),
            lnext2: Default::default(),
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
            key_min: Default::default(),
            key_max: Default::default(),
            rd_min: Default::default(),
            rd_max: Default::default(),
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
            succ_pick: vec(lists),
            succ_acc: Default::default(),
            any_live: Default::default(),
            bank_any: Default::default(),
            bank_next: Default::default(),
            bank_left: Default::default(),
            group_prior: vec(lists),
            bank_prior: Default::default(),
            e_first: vec(lists),
            e_push: Default::default(),
            e_pick: vec(lists),
            e_out: Default::default(),
            e_pick2: vec(lists),
            e_out2: Default::default(),
            e_more: Default::default(),
            e_load: Default::default(),
            arrive: Default::default(),
            avail: Default::default(),
            after: Default::default(),
            after_v: Default::default(),
            need: Default::default(),
            retire_rec: Default::default(),
            take: Default::default(),
            rd_live: vec(lists),
            inflight_up: Default::default(),
            inflight_inc: Default::default(),
            inflight_dec: Default::default(),
            inflight_dec2: Default::default(),
            inflight_m: Default::default(),
            inflight_n0: Default::default(),
            inflight_n1: Default::default(),
            count_inc: Default::default(),
            count_dec: Default::default(),
            count_m: Default::default(),
            ones: Constant::new(((1u64 << COUNT) - 1).into()),
            cand_word: Default::default(),
            unpack_a: Default::default(),
            unpack_b: Default::default(),
            unpack_ma: Default::default(),
            cand: Default::default(),
            entry: Default::default(),
            entry4: Default::default(),
            entry5: Default::default(),
            cand_ok: Default::default(),
            go: Default::default(),
            stall: Default::default(),
            retire_probe: Default::default(),
            rec_write: Default::default(),
            overlap: Default::default(),
            swap: Default::default(),
            cand_lo: Default::default(),
            cand_hi: Default::default(),
            margin_lo: Default::default(),
            margin_hi: Default::default(),
            done_walk: Default::default(),
            idle: Default::default(),
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
            home_ok: Default::default(),
            wl_cell: Default::default(),
            wl_keep: Default::default(),
            mask_row: Default::default(),
            mask_ok: Default::default(),
            pass: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for GridPhase<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            s1_valid,
            s1_index,
            s1_margin,
            s1_group,
            s2_valid,
            s2_index,
            s2_margin,
            s2_group,
            s3_valid,
            s3_index,
            s3_margin,
            s3_group,
            s3_allowed,
            s4_valid,
            s4_large,
            s4_lprev,
            s4_index,
            s4_margin,
            s4_kind,
            s4_home_fp,
            s5_valid,
            s5_large,
            s5_lprev,
            s5_index,
            s5_margin,
            wp,
            rp,
            count,
            inflight,
            cur_valid,
            cur_last,
            e_busy,
            e_chosen,
            e_index,
            e_margin,
            e_kind,
            lq_wp,
            lq_rp,
            cur_index,
            cur_margin,
            succ_q,
            r1,
            arrive_q,
            q0v,
            q0,
            q1v,
            q1,
            v1_valid,
            v1_i,
            v1_j,
            v1_margin,
            v2_valid,
            v2_i,
            v2_j,
            v2_margin_i,
            v2_margin_j,
            clearing,
            cleared,
            clear_at,
            s1_kind,
            s2_kind,
            s3_kind,
            s5_kind,
            cur_kind,
            v1_kind,
            v2_kind,
            v2_group_j,
            v3_write,
            v3_word,
            slow,
            lnext,
            lnext2,
            lcur,
            lmargin,
            lgroup,
            wide,
            fetch_q,
            inj,
            inj_kind
        );
        clock!(self, clock, cells, succ, rec_box, fifo, lq_head, lq_head2, lq_box, lq_last);
        for b in 0..27 {
            self.s4_bucket[b].clock.next = self.clock.val();
            self.s4_fp[b].clock.next = self.clock.val();
        }
        for x in 0..3 {
            self.lq_fill[x].clock.next = self.clock.val();
            self.lq_fill[x].d.next = self.lq_fill[x].q.val();
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
            self.cur_min[x].clock.next = self.clock.val();
            self.cur_max[x].clock.next = self.clock.val();
            self.e_min[x].clock.next = self.clock.val();
            self.e_max[x].clock.next = self.clock.val();
            self.v1_min[x].clock.next = self.clock.val();
            self.v1_max[x].clock.next = self.clock.val();
            self.v2_min_i[x].clock.next = self.clock.val();
            self.v2_max_i[x].clock.next = self.clock.val();
            self.v2_min_j[x].clock.next = self.clock.val();
            self.v2_max_j[x].clock.next = self.clock.val();
            self.v2_wl[x].clock.next = self.clock.val();
            self.v2_wh[x].clock.next = self.clock.val();
            self.v2_jc[x].clock.next = self.clock.val();
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
            self.s5_enter[l].clock.next = self.clock.val();
            self.s5_wrote[l].clock.next = self.clock.val();
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
        for x in 0..3 {
            self.cur_min[x].d.next = self.cur_min[x].q.val();
            self.cur_max[x].d.next = self.cur_max[x].q.val();
            self.e_min[x].d.next = self.e_min[x].q.val();
            self.e_max[x].d.next = self.e_max[x].q.val();
        }

        self.key_min[0].next = self.key_min_x.val();
        self.key_min[1].next = self.key_min_y.val();
        self.key_min[2].next = self.key_min_z.val();
        self.key_max[0].next = self.key_max_x.val();
        self.key_max[1].next = self.key_max_y.val();
        self.key_max[2].next = self.key_max_z.val();
        self.rd_min[0].next = self.rd_min_x.val();
        self.rd_min[1].next = self.rd_min_y.val();
        self.rd_min[2].next = self.rd_min_z.val();
        self.rd_max[0].next = self.rd_max_x.val();
        self.rd_max[1].next = self.rd_max_y.val();
        self.rd_max[2].next = self.rd_max_z.val();

        // The slow path's sequencer (it injects after the load, when no box arrives).
        self.idle.next = self.loaded.val() & (self.inflight.q.val() == 0);
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
        match self.slow.q.val() {
            SlowState::Fetch => {
                if self.idle.val() {
                    if (self.lnext.q.val() & self.top.val()) != 0 {
                        self.fetch.next = true;
                        self.lcur.d.next = self.lnext.q.val() ^ self.top.val();
                        self.lnext.d.next = self.lnext2.q.val();
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
                self.lmargin.d.next = self.rd_margin.val();
                self.lgroup.d.next = self.rd_group.val();
                for x in 0..3 {
                    self.lk_min[x].d.next = self.rd_min[x].val();
                    self.lk_lim[x].d.next =
                        (self.rd_min[x].val() >> self.cell_bits.val()) + self.max_span.val();
                    self.lk_max[x].d.next = self.rd_max[x].val();
                }
                self.slow.d.next = SlowState::Plan;
            }
            SlowState::Plan => {
                // The fetched box's second successor, from the registered output.
                self.lnext2.d.next = self.succ_q.q.val();
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
                // chain (if any) or the next box.
                if self.idle.val() {
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
                            } else if (self.lnext.q.val() & self.top.val()) != 0 {
                                self.slow.d.next = SlowState::Partner;
                            } else {
                                self.slow.d.next = SlowState::Fetch;
                            }
                        }
                    }
                }
            }
            SlowState::Partner => {
                if self.idle.val() {
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
            self.mask.val() >> (bit_cast::<MASK, GROUP>(self.s2_group.q.val()) << 3_u64);
        self.s3_allowed.d.next = self.allowed.val();

        // K+3, per list (bank b, group h): the list heads are read at the bank's bucket and
        // registered, with what decides the lists to walk and the entry. (The box one ahead
        // writes its entry on this clock: the read misses it, so the banks whose bucket it
        // writes are marked, and its entry is forwarded at K+4.)
        self.entry.next = self.s3_index.q.val() | self.top.val();
        for q in 0..self._groups {
            for b in 0..27 {
                self.meta[27 * q + b].read_address.next = self.cells.bucket[b].val();
                self.head[27 * q + b].read_address.next = self.cells.bucket[b].val();
                self.allow[27 * q + b].next =
                    self.s3_allowed.q.val() >> self.list_group[27 * q + b].val();
                self.s4_meta[27 * q + b].d.next = self.meta[27 * q + b].read_data.val();
                self.head2[27 * q + b].read_address.next = self.cells.bucket[b].val();
                self.s4_old[27 * q + b].d.next = self.head[27 * q + b].read_data.val();
                self.s4_old2[27 * q + b].d.next = self.head2[27 * q + b].read_data.val();
                self.s4_walk[27 * q + b].d.next = self.s3_valid.q.val()
                    & self.cells.small_box.val()
                    & self.cells.inside[b].val()
                    & self.allow[27 * q + b].val().get_bit(0);
                self.s4_enter[27 * q + b].d.next = self.s3_valid.q.val()
                    & (self.s3_kind.q.val() == 0)
                    & self.cells.small_box.val()
                    & self.cells.home[b].val()
                    & (self.s3_group.q.val() == self.list_group[27 * q + b].val());
            }
        }
        for b in 0..27 {
            self.s4_bucket[b].d.next = self.cells.bucket[b].val();
            self.s4_fp[b].d.next = self.cells.fp[b].val();
            self.same[b].next = self.cells.bucket[b].val() == self.s4_bucket[b].q.val();
        }
        for q in 0..self._groups {
            for b in 0..27 {
                self.s4_fwd[27 * q + b].d.next =
                    self.same[b].val() & self.s4_enter[27 * q + b].q.val();
            }
        }
        self.s4_home_fp.d.next = self.cells.home_fp.val();
        // A large box takes the chain of large boxes instead of a list.
        self.large_in.next =
            self.s3_valid.q.val() & (self.s3_kind.q.val() == 0) & !self.cells.small_box.val();
        self.s4_large.d.next = self.large_in.val();
        self.s4_lprev.d.next = self.lnext2.q.val();
        if self.large_in.val() {
            self.lnext.d.next = self.entry.val();
            self.lnext2.d.next = self.lnext.q.val();
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
        self.entry5.next = self.s5_index.q.val() | self.top.val();
        for q in 0..self._groups {
            for b in 0..27 {
                self.fwd[27 * q + b].next = self.s4_fwd[27 * q + b].q.val();
                self.meta_eff[27 * q + b].next = self.s4_meta[27 * q + b].q.val();
                self.old_eff[27 * q + b].next = self.s4_old[27 * q + b].q.val();
                self.old_eff2[27 * q + b].next = self.s4_old2[27 * q + b].q.val();
                if self.fwd[27 * q + b].val() {
                    self.meta_eff[27 * q + b].next = self.s5_meta_w[27 * q + b].q.val();
                    self.old_eff[27 * q + b].next = self.entry5.val();
                    self.old_eff2[27 * q + b].next = self.s5_head[27 * q + b].q.val();
                }
                self.meta_src[2 * (27 * q + b)].next = self.s4_meta[27 * q + b].q.val();
                self.meta_src[2 * (27 * q + b) + 1].next = self.s5_meta_w[27 * q + b].q.val();
                for k in 0..2 {
                    // Walked if valid and mixed or owned by the cell's fingerprint. Owned: kept,
                    // and mixed by another fingerprint; free: owned by this one.
                    self.live_src[2 * (27 * q + b) + k].next = self.s4_walk[27 * q + b].q.val()
                        & self.meta_src[2 * (27 * q + b) + k].val().get_bit(9)
                        & (self.meta_src[2 * (27 * q + b) + k].val().get_bit(8)
                            | (self.meta_src[2 * (27 * q + b) + k].val().get_bits::<FP>(0)
                                == self.s4_fp[b].q.val()));
                    self.meta_new_src[2 * (27 * q + b) + k].next =
                        bit_cast::<META, FP>(self.s4_home_fp.q.val()) | 512_u64;
                    if self.meta_src[2 * (27 * q + b) + k].val().get_bit(9) {
                        self.meta_new_src[2 * (27 * q + b) + k].next =
                            self.meta_src[2 * (27 * q + b) + k].val();
                        if self.meta_src[2 * (27 * q + b) + k].val().get_bits::<FP>(0)
                            != self.s4_home_fp.q.val()
                        {
                            self.meta_new_src[2 * (27 * q + b) + k].next =
                                self.meta_src[2 * (27 * q + b) + k].val() | 256_u64;
                        }
                    }
                }
                self.live[27 * q + b].next = self.live_src[2 * (27 * q + b)].val();
                self.meta_new[27 * q + b].next = self.meta_new_src[2 * (27 * q + b)].val();
                if self.fwd[27 * q + b].val() {
                    self.live[27 * q + b].next = self.live_src[2 * (27 * q + b) + 1].val();
                    self.meta_new[27 * q + b].next = self.meta_new_src[2 * (27 * q + b) + 1].val();
                }
                self.meta[27 * q + b].write_enable.next = self.s4_enter[27 * q + b].q.val();
                self.meta[27 * q + b].write_address.next = self.s4_bucket[b].q.val();
                self.meta[27 * q + b].write_data.next = self.meta_new[27 * q + b].val();
                self.head[27 * q + b].write_enable.next = self.s4_enter[27 * q + b].q.val();
                self.head[27 * q + b].write_address.next = self.s4_bucket[b].q.val();
                self.head[27 * q + b].write_data.next = self.entry4.val();
                self.head2[27 * q + b].write_enable.next = self.s4_enter[27 * q + b].q.val();
                self.head2[27 * q + b].write_address.next = self.s4_bucket[b].q.val();
                self.head2[27 * q + b].write_data.next = self.old_eff[27 * q + b].val();
                if self.clearing.q.val() {
                    self.meta[27 * q + b].write_enable.next = true;
                    self.meta[27 * q + b].write_address.next = self.clear_at.q.val();
                    self.meta[27 * q + b].write_data.next = 0.into();
                    self.head[27 * q + b].write_enable.next = true;
                    self.head[27 * q + b].write_address.next = self.clear_at.q.val();
                    self.head[27 * q + b].write_data.next = 0.into();
                    self.head2[27 * q + b].write_enable.next = true;
                    self.head2[27 * q + b].write_address.next = self.clear_at.q.val();
                    self.head2[27 * q + b].write_data.next = 0.into();
                }
                self.s5_enter[27 * q + b].d.next =
                    self.s4_enter[27 * q + b].q.val() & self.meta_eff[27 * q + b].val().get_bit(9);
                self.s5_wrote[27 * q + b].d.next = self.s4_enter[27 * q + b].q.val();
                self.s5_meta_w[27 * q + b].d.next = self.meta_new[27 * q + b].val();
                self.s5_live[27 * q + b].d.next = self.live[27 * q + b].val();
                self.s5_head[27 * q + b].d.next = self.old_eff[27 * q + b].val();
                self.s5_head2[27 * q + b].d.next = self.old_eff2[27 * q + b].val();
            }
        }
        self.s5_large.d.next = self.s4_large.q.val();
        self.s5_lprev.d.next = self.s4_lprev.q.val();
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
        self.succ_acc.next = 0.into();
        if self.s5_large.q.val() {
            self.succ_acc.next = self.s5_lprev.q.val();
        }
        self.any_live.next = false;
        for l in 0..self._lists {
            self.succ_pick[l].next = 0.into();
            if self.s5_enter[l].q.val() {
                self.succ_pick[l].next = self.s5_head2[l].q.val();
            }
            self.succ_acc.next = self.succ_acc.val() | self.succ_pick[l].val();
            self.any_live.next = self.any_live.val() | self.s5_live[l].q.val();
        }
        self.succ.write_enable.next = self.s5_valid.q.val() & (self.s5_kind.q.val() == 0);
        self.succ.write_address.next = bit_cast::<A, C>(self.s5_index.q.val());
        self.succ.write_data.next = self.succ_acc.val();
        self.rec_write.next =
            self.s5_valid.q.val() & (self.any_live.val() | self.s5_kind.q.val().get_bit(1));
        self.retire_probe.next = self.s5_valid.q.val() & !self.rec_write.val();
        for l in 0..self._lists {
            self.rec[l].write_enable.next = self.rec_write.val();
            self.rec[l].write_address.next = self.wp.q.val();
            // A list head has the flag bit set; a list not to walk is written as none.
            self.rec[l].write_data.next = 0.into();
            self.rec2[l].write_enable.next = self.rec_write.val();
            self.rec2[l].write_address.next = self.wp.q.val();
            self.rec2[l].write_data.next = 0.into();
            if self.s5_live[l].q.val() {
                self.rec[l].write_data.next = self.s5_head[l].q.val();
                self.rec2[l].write_data.next = self.s5_head2[l].q.val();
            }
            self.rec[l].read_address.next = self.rp.q.val();
            self.rec2[l].read_address.next = self.rp.q.val();
        }
        if self.s5_kind.q.val().get_bit(1) {
            self.rec[0].write_data.next = self.lnext.q.val();
            self.rec2[0].write_data.next = self.lnext2.q.val();
        }
        self.rec_box.write_enable.next = self.rec_write.val();
        self.rec_box.write_address.next = self.wp.q.val();
        self.rec_box.read_address.next = self.rp.q.val();
        self.rec_box.in_index.next = self.s5_index.q.val();
        self.rec_box.in_margin.next = self.s5_margin.q.val();
        self.rec_box.in_kind.next = self.s5_kind.q.val();
        for x in 0..3 {
            self.rec_box.in_min[x].next = self.s5_min[x].q.val();
            self.rec_box.in_max[x].next = self.s5_max[x].q.val();
        }
        if self.rec_write.val() {
            self.wp.d.next = self.wp.q.val() + 1;
        }

        // The enumerator: it takes the records in order and writes their lists to the list
        // queue in the walker's order (bank, then group), each over two clocks: on a clock it
        // writes none it chooses the next list left (a one-hot), on a later clock it writes that
        // list, when at most two are queued (so that the write finds room whatever the walker
        // takes), and whether it is the record's last (no other list left). It loads the next
        // record on a clock it holds none. Each clock's logic runs from registers alone: the
        // walker only picks the queue's output.
        for b in 0..27 {
            self.bank_any[b].next = false;
        }
        for q in 0..self._groups {
            for b in 0..27 {
                self.group_prior[27 * q + b].next = self.bank_any[b].val();
                self.bank_any[b].next = self.bank_any[b].val() | self.e_rem[27 * q + b].q.val();
            }
        }
        self.bank_prior[0].next = false;
        for b in 0..27 {
            self.bank_prior[b + 1].next = self.bank_prior[b].val() | self.bank_left[b].q.val();
        }
        for q in 0..self._groups {
            for b in 0..27 {
                self.e_first[27 * q + b].next = self.e_rem[27 * q + b].q.val()
                    & !self.group_prior[27 * q + b].val()
                    & !self.bank_prior[b].val();
            }
        }
        self.e_push.next = self.e_chosen.q.val() & !self.lq_fill[2].q.val();
        self.e_load.next = (self.count.q.val() != 0) & !self.e_busy.q.val();
        self.e_out.next = 0.into();
        self.e_out2.next = 0.into();
        self.e_more.next = false;
        for l in 0..self._lists {
            self.e_pick[l].next = 0.into();
            self.e_pick2[l].next = 0.into();
            if self.e_sel[l].q.val() {
                self.e_pick[l].next = self.e_head[l].q.val();
                self.e_pick2[l].next = self.e_head2[l].q.val();
            }
            self.e_out.next = self.e_out.val() | self.e_pick[l].val();
            self.e_out2.next = self.e_out2.val() | self.e_pick2[l].val();
            self.e_more.next = self.e_more.val() | (self.e_rem[l].q.val() & !self.e_sel[l].q.val());
        }
        self.lq_head.write_enable.next = self.e_push.val();
        self.lq_head.write_address.next = self.lq_wp.q.val();
        self.lq_head.write_data.next = self.e_out.val();
        self.lq_head.read_address.next = self.lq_rp.q.val();
        self.lq_head2.write_enable.next = self.e_push.val();
        self.lq_head2.write_address.next = self.lq_wp.q.val();
        self.lq_head2.write_data.next = self.e_out2.val();
        self.lq_head2.read_address.next = self.lq_rp.q.val();
        self.lq_last.write_enable.next = self.e_push.val();
        self.lq_last.write_address.next = self.lq_wp.q.val();
        self.lq_last.write_data.next = !self.e_more.val();
        self.lq_last.read_address.next = self.lq_rp.q.val();
        self.lq_box.write_enable.next = self.e_push.val();
        self.lq_box.write_address.next = self.lq_wp.q.val();
        self.lq_box.read_address.next = self.lq_rp.q.val();
        self.lq_box.in_index.next = self.e_index.q.val();
        self.lq_box.in_margin.next = self.e_margin.q.val();
        self.lq_box.in_kind.next = self.e_kind.q.val();
        for x in 0..3 {
            self.lq_box.in_min[x].next = self.e_min[x].q.val();
            self.lq_box.in_max[x].next = self.e_max[x].q.val();
        }
        if self.e_push.val() {
            self.lq_wp.d.next = self.lq_wp.q.val() + 1;
            self.e_chosen.d.next = false;
            if !self.e_more.val() {
                self.e_busy.d.next = false;
            }
            for l in 0..self._lists {
                if self.e_sel[l].q.val() {
                    self.e_rem[l].d.next = false;
                }
            }
        } else if self.e_busy.q.val() {
            self.e_chosen.d.next = true;
            for l in 0..self._lists {
                self.e_sel[l].d.next = self.e_first[l].val();
            }
        }
        for l in 0..self._lists {
            self.rd_live[l].next = (self.rec[l].read_data.val() & self.top.val()) != 0;
        }
        if self.e_load.val() {
            self.rp.d.next = self.rp.q.val() + 1;
            self.e_busy.d.next = true;
            self.e_chosen.d.next = false;
            self.e_index.d.next = self.rec_box.index.val();
            self.e_margin.d.next = self.rec_box.margin.val();
            self.e_kind.d.next = self.rec_box.kind.val();
            for x in 0..3 {
                self.e_min[x].d.next = self.rec_box.min[x].val();
                self.e_max[x].d.next = self.rec_box.max[x].val();
            }
            for l in 0..self._lists {
                self.e_rem[l].d.next = self.rd_live[l].val();
                self.e_head[l].d.next = self.rec[l].read_data.val();
                self.e_head2[l].d.next = self.rec2[l].read_data.val();
            }
        }
        for b in 0..27 {
            self.bank_next[b].next = false;
        }
        for q in 0..self._groups {
            for b in 0..27 {
                self.bank_next[b].next = self.bank_next[b].val() | self.e_rem[27 * q + b].d.val();
            }
        }
        for b in 0..27 {
            self.bank_left[b].clock.next = self.clock.val();
            self.bank_left[b].d.next = self.bank_next[b].val();
        }

        // The walker. The list's next box is known from registers alone (so that no decision
        // waits for the successor table's block RAM): the first known and not visited (`q0`),
        // or the second successor of the box visited two clocks before, arriving on the
        // table's registered output. Else the list is over: the walker takes the list queue's
        // next (its head now, its second on the next clock, from the queue) or, its record's
        // last list done, retires the record. (Flags are tested by a mask, not `>= top`: a
        // compare is a carry chain in synthesis.)
        self.arrive.next = self.arrive_q.q.val();
        self.avail.next = self.q0v.q.val() | self.arrive.val();
        self.need.next = !self.avail.val();
        self.take.next = self.need.val() & self.lq_fill[0].q.val();
        self.retire_rec.next = self.need.val() & self.cur_valid.q.val() & self.cur_last.q.val();
        self.cand.next = self.lq_head.read_data.val();
        if self.fetch_q.q.val() {
            self.cand.next = self.lcur.q.val();
        }
        if self.arrive.val() {
            self.cand.next = self.succ_q.q.val();
        }
        if self.q0v.q.val() {
            self.cand.next = self.q0.q.val();
        }
        // The box after `cand`: `q1`, the arrival behind `q0`, or a taken list's second.
        self.after.next = self.succ_q.q.val();
        if self.q1v.q.val() {
            self.after.next = self.q1.q.val();
        }
        self.after_v.next = self.q1v.q.val() | (self.q0v.q.val() & self.arrive.val());
        if self.take.val() {
            self.after.next = self.lq_head2.read_data.val();
            self.after_v.next = (self.lq_head2.read_data.val() & self.top.val()) != 0;
        }
        self.cand_ok.next = self.avail.val() | self.take.val();
        self.stall.next = self.fifo.almost_full.val();
        self.go.next = self.cand_ok.val() & !self.stall.val();
        if self.go.val() {
            self.q0.d.next = self.after.val();
            self.q0v.d.next = self.after_v.val();
            self.q1v.d.next = false;
        } else {
            self.q0.d.next = self.cand.val();
            self.q0v.d.next = self.cand_ok.val();
            self.q1.d.next = self.after.val();
            self.q1v.d.next = self.cand_ok.val() & self.after_v.val();
        }
        self.r1.d.next = self.go.val();
        self.arrive_q.d.next =
            self.r1.q.val() & ((self.succ.read_data_b.val() & self.top.val()) != 0);
        self.succ_q.d.next = self.succ.read_data_b.val();
        // The visit's box i: the list's, or the one taken this clock.
        self.v1_i.d.next = self.cur_index.q.val();
        self.v1_margin.d.next = self.cur_margin.q.val();
        self.v1_kind.d.next = self.cur_kind.q.val();
        for x in 0..3 {
            self.v1_min[x].d.next = self.cur_min[x].q.val();
            self.v1_max[x].d.next = self.cur_max[x].q.val();
        }
        if self.take.val() {
            self.lq_rp.d.next = self.lq_rp.q.val() + 1;
            self.cur_valid.d.next = true;
            self.cur_last.d.next = self.lq_last.read_data.val();
            self.cur_index.d.next = self.lq_box.index.val();
            self.cur_margin.d.next = self.lq_box.margin.val();
            self.v1_i.d.next = self.lq_box.index.val();
            self.v1_margin.d.next = self.lq_box.margin.val();
            self.cur_kind.d.next = self.lq_box.kind.val();
            self.v1_kind.d.next = self.lq_box.kind.val();
            for x in 0..3 {
                self.cur_min[x].d.next = self.lq_box.min[x].val();
                self.cur_max[x].d.next = self.lq_box.max[x].val();
                self.v1_min[x].d.next = self.lq_box.min[x].val();
                self.v1_max[x].d.next = self.lq_box.max[x].val();
            }
        } else if self.retire_rec.val() {
            self.cur_valid.d.next = false;
        }
        if self.e_push.val() & !self.take.val() {
            self.lq_fill[0].d.next = true;
            self.lq_fill[1].d.next = self.lq_fill[0].q.val();
            self.lq_fill[2].d.next = self.lq_fill[1].q.val();
        }
        if self.take.val() & !self.e_push.val() {
            self.lq_fill[0].d.next = self.lq_fill[1].q.val();
            self.lq_fill[1].d.next = self.lq_fill[2].q.val();
            self.lq_fill[2].d.next = false;
        }
        self.visit.next = self.go.val();
        self.visit_i.next = bit_cast::<A, C>(self.v1_i.d.val());
        self.rd_addr.next = bit_cast::<A, C>(self.cand.val());
        self.succ.read_address_a.next = 0.into();
        self.succ.read_address_b.next = bit_cast::<A, C>(self.cand.val());

        // Credits and records.
        self.inflight_up.next = self.accept.val() | self.inject.val();
        self.inflight_inc.next = self.inflight.q.val() + 1;
        self.inflight_dec.next = self.inflight.q.val() - 1;
        self.inflight_dec2.next = self.inflight.q.val() - 2;
        for k in 0..3 {
            self.inflight_m[k].next = 0.into();
        }
        if self.inflight_up.val() == self.retire_probe.val() {
            self.inflight_m[0].next = self.ones.val();
        } else if self.inflight_up.val() {
            self.inflight_m[1].next = self.ones.val();
        } else {
            self.inflight_m[2].next = self.ones.val();
        }
        self.inflight_n0.next = (self.inflight.q.val() & self.inflight_m[0].val())
            | (self.inflight_inc.val() & self.inflight_m[1].val())
            | (self.inflight_dec.val() & self.inflight_m[2].val());
        self.inflight_n1.next = (self.inflight_dec.val() & self.inflight_m[0].val())
            | (self.inflight.q.val() & self.inflight_m[1].val())
            | (self.inflight_dec2.val() & self.inflight_m[2].val());
        self.inflight.d.next = self.inflight_n0.val();
        if self.retire_rec.val() {
            self.inflight.d.next = self.inflight_n1.val();
        }
        self.credit.next = (self.inflight.q.val() & self.credits_used.val()) == 0;
        self.count_inc.next = self.count.q.val() + 1;
        self.count_dec.next = self.count.q.val() - 1;
        for k in 0..3 {
            self.count_m[k].next = 0.into();
        }
        if self.rec_write.val() == self.e_load.val() {
            self.count_m[0].next = self.ones.val();
        } else if self.rec_write.val() {
            self.count_m[1].next = self.ones.val();
        } else {
            self.count_m[2].next = self.ones.val();
        }
        self.count.d.next = (self.count.q.val() & self.count_m[0].val())
            | (self.count_inc.val() & self.count_m[1].val())
            | (self.count_dec.val() & self.count_m[2].val());

        // The key check: V+1 the visited box's keys come from port B; V+2 they are compared
        // with the walking box's; V+3 a candidate (lower index first) enters the queue.
        self.v1_valid.d.next = self.go.val();
        self.v1_j.d.next = bit_cast::<C, A>(bit_cast::<A, C>(self.cand.val()));
        self.v2_valid.d.next = self.v1_valid.q.val();
        self.v2_i.d.next = self.v1_i.q.val();
        self.v2_j.d.next = self.v1_j.q.val();
        self.v2_margin_i.d.next = self.v1_margin.q.val();
        self.v2_margin_j.d.next = self.rd_margin.val();
        self.v2_kind.d.next = self.v1_kind.q.val();
        self.v2_group_j.d.next = self.rd_group.val();
        for x in 0..3 {
            // A round's record holds the round's cells; the large box's keys are the
            // sequencer's.
            self.v2_min_i[x].d.next = self.v1_min[x].q.val();
            self.v2_max_i[x].d.next = self.v1_max[x].q.val();
            if self.v1_kind.q.val().get_bit(0) {
                self.v2_min_i[x].d.next = self.lk_min[x].q.val();
                self.v2_max_i[x].d.next = self.lk_max[x].q.val();
            }
            self.wl_cell[x].next = self.v1_min[x].q.val() >> self.cell_bits.val();
            self.wl_keep[x].next = 0.into();
            if self.wl_cell[x].val().any() {
                self.wl_keep[x].next = self.center_ones.val();
            }
            self.v2_wl[x].d.next = (self.wl_cell[x].val() - 1) & self.wl_keep[x].val();
            self.v2_wh[x].d.next = self.v1_max[x].q.val() >> self.cell_bits.val();
            self.v2_jc[x].d.next = self.rd_min[x].val() >> self.cell_bits.val();
            self.v2_min_j[x].d.next = self.rd_min[x].val();
            self.v2_max_j[x].d.next = self.rd_max[x].val();
        }
        self.overlap.next = (self.v2_min_i[0].q.val() <= self.v2_max_j[0].q.val())
            & (self.v2_min_j[0].q.val() <= self.v2_max_i[0].q.val())
            & (self.v2_min_i[1].q.val() <= self.v2_max_j[1].q.val())
            & (self.v2_min_j[1].q.val() <= self.v2_max_i[1].q.val())
            & (self.v2_min_i[2].q.val() <= self.v2_max_j[2].q.val())
            & (self.v2_min_j[2].q.val() <= self.v2_max_i[2].q.val());
        self.swap.next = self.v2_i.q.val() < self.v2_j.q.val();
        self.cand_lo.next = bit_cast::<INDEX, C>(self.v2_j.q.val());
        self.cand_hi.next = bit_cast::<INDEX, C>(self.v2_i.q.val());
        self.margin_lo.next = self.v2_margin_j.q.val();
        self.margin_hi.next = self.v2_margin_i.q.val();
        if self.swap.val() {
            self.cand_lo.next = bit_cast::<INDEX, C>(self.v2_i.q.val());
            self.cand_hi.next = bit_cast::<INDEX, C>(self.v2_j.q.val());
            self.margin_lo.next = self.v2_margin_i.q.val();
            self.margin_hi.next = self.v2_margin_j.q.val();
        }
        self.cand_word.next = (bit_cast::<CAND, INDEX>(self.cand_lo.val()) << self.at_a.val())
            | (bit_cast::<CAND, INDEX>(self.cand_hi.val()) << self.at_b.val())
            | (bit_cast::<CAND, MARGIN>(self.margin_lo.val()) << self.at_ma.val())
            | bit_cast::<CAND, MARGIN>(self.margin_hi.val());
        // A round passes a box whose home cell is in it; the chain's boxes pass if the mask
        // pairs the groups.
        self.home_ok.next = (self.v2_wl[0].q.val() <= self.v2_jc[0].q.val())
            & (self.v2_jc[0].q.val() <= self.v2_wh[0].q.val())
            & (self.v2_wl[1].q.val() <= self.v2_jc[1].q.val())
            & (self.v2_jc[1].q.val() <= self.v2_wh[1].q.val())
            & (self.v2_wl[2].q.val() <= self.v2_jc[2].q.val())
            & (self.v2_jc[2].q.val() <= self.v2_wh[2].q.val());
        self.mask_row.next = self.mask.val()
            >> ((bit_cast::<MASK, GROUP>(self.lgroup.q.val()) << 3_u64)
                | bit_cast::<MASK, GROUP>(self.v2_group_j.q.val()));
        self.mask_ok.next = self.mask_row.val().get_bit(0);
        self.pass.next = self.overlap.val()
            & (self.home_ok.val() | !self.v2_kind.q.val().get_bit(0))
            & (self.mask_ok.val() | !self.v2_kind.q.val().get_bit(1));
        self.v3_write.d.next = self.v2_valid.q.val() & self.pass.val();
        self.v3_word.d.next = self.cand_word.val();
        self.fifo.write.next = self.v3_write.q.val();
        self.fifo.data_in.next = self.v3_word.q.val();
        self.fifo.ready.next = self.cand_ready.val();
        self.cand_valid.next = self.fifo.valid.val();
        self.unpack_a.next = self.fifo.data_out.val() >> self.at_a.val();
        self.unpack_b.next = self.fifo.data_out.val() >> self.at_b.val();
        self.unpack_ma.next = self.fifo.data_out.val() >> self.at_ma.val();
        self.cand_a.next = bit_cast::<A, CAND>(self.unpack_a.val());
        self.cand_b.next = bit_cast::<A, CAND>(self.unpack_b.val());
        self.cand_ma.next = bit_cast::<MARGIN, CAND>(self.unpack_ma.val());
        self.cand_mb.next = bit_cast::<MARGIN, CAND>(self.fifo.data_out.val());

        // The end: every box accepted and retired, the slow path over; then the clear, one
        // bucket a clock.
        self.done_walk.next = self.idle.val()
            & ((self.slow.q.val() == SlowState::Over)
                | ((self.slow.q.val() == SlowState::Fetch)
                    & ((self.lnext.q.val() & self.top.val()) == 0)));
        self.walked.next = self.done_walk.val();
        if self.done_walk.val() & !self.clearing.q.val() & !self.cleared.q.val() {
            self.clearing.d.next = true;
            self.clear_at.d.next = 0.into();
        }
        if self.clearing.q.val() {
            self.clear_at.d.next = self.clear_at.q.val() + 1;
            if self.clear_at.q.val() == self.last_bucket.val() {
                self.clearing.d.next = false;
                self.cleared.d.next = true;
            }
        }
        self.finished.next = self.cleared.q.val()
            & self.fifo.empty.val()
            & !self.v1_valid.q.val()
            & !self.v2_valid.q.val()
            & !self.v3_write.q.val();
        self.too_wide.next = self.wide.q.val();
        if self.start.val() {
            self.wp.d.next = 0.into();
            self.rp.d.next = 0.into();
            self.count.d.next = 0.into();
            self.inflight.d.next = 0.into();
            self.cur_valid.d.next = false;
            self.e_busy.d.next = false;
            self.e_chosen.d.next = false;
            self.lq_wp.d.next = 0.into();
            self.lq_rp.d.next = 0.into();
            for k in 0..3 {
                self.lq_fill[k].d.next = false;
            }
            self.q0v.d.next = false;
            self.q1v.d.next = false;
            self.r1.d.next = false;
            self.arrive_q.d.next = false;
            self.clearing.d.next = false;
            self.cleared.d.next = false;
            self.slow.d.next = SlowState::Fetch;
            self.lnext.d.next = 0.into();
            self.lnext2.d.next = 0.into();
            self.wide.d.next = false;
        }
    }
}
