//! The hardware grid (`broad_phase = "grid"`): a spatial hash built while the boxes arrive, so
//! that the broad phase's work follows the real overlaps and runs during the load
//! (docs/hardware.md, "The grid"; docs/numerics.md has the proof that no pair is lost).
//!
//! Cells are `2^g` key units on a side (`HwConfig::grid_cell_mm`). A box is *small* when its
//! keys span at most one cell on every axis; it is entered in one cell only, the one holding
//! its lower corner. Any small box whose keys overlap a small box `i` has its lower corner in
//! `i`'s *window*: per axis the cells from `kmin >> g` to `(kmax >> g) + 1` in offset
//! coordinates (`(key >> g) + 1`), two or three cells. So when box `i` arrives it reads the
//! lists of its window's cells (only the groups the mask pairs with its own), and every earlier
//! box it must meet is on one of them; then it enters itself. A pair is met once: each box is on
//! one list, and the window's cells lie in 27 different banks (coordinates mod 3), so no list is
//! read twice for one box.
//!
//! A bank holds, per bucket (an H3 hash of the cell's coordinates on `grid_hash_bits` bits)
//! and per group (`grid_groups`), a list of box indices (latest first) with the fingerprint (8
//! more bits of the hash) of the cell that entered it first and whether a box of a cell with
//! another fingerprint entered it too (*mixed*); each box's successor is in one per-box table.
//! A probe skips a pure list of another fingerprint without a visit (it holds no box of the
//! probed cell); any other list is walked whole, and the key check removes the other cells'
//! boxes, so a hash collision costs visits, never a pair.
//!
//! Boxes larger than a cell (*large*) are entered nowhere: they are chained, latest first, on
//! their own successor entries. After the load each, in the chain's order, reads its whole
//! window in *rounds* (`GridShape::rounds`: two or three cells per axis, as a small box's window
//! has), meeting a small box only when the box's home cell is in the round, and then walks the
//! chain after it (the large boxes before it). A window of more than `MAX_WINDOW` cells on an
//! axis is not read: the slow path stops there, and the frame is *incomplete* (the core flags
//! it; a larger cell takes the box).
//!
//! With `resident_groups`, a haptic frame's first boxes (`ModelFrame::resident`) are the last
//! update frame's resident ones, still in the core: they are entered without a probe, in their
//! order, which rebuilds the lists and the chain the update left, and only the streamed boxes
//! after them probe (docs/numerics.md, "Resident groups").
//!
//! With `lanes` walkers, box `i` is on lane `i mod lanes`: each bucket has a list per group and
//! lane, a box enters its lane's list and probes every lane's, and the large boxes chain per
//! lane. A lane's walker then visits only its lane's boxes, so in the hardware each reads its
//! own bank of the per-box tables.

use super::config::{HwConfig, GROUP_BITS};
use super::frame::ModelFrame;
use super::work::BroadWork;
use crate::groups::GroupMask;

/// Banks of list heads: a cell's bank is its coordinates mod 3, `x + 3 y + 9 z`.
pub const BANKS: usize = 27;
pub use super::config::{MAX_HASH_BITS, MAX_KEY_BITS};
/// Bits of a cell's fingerprint, which a list keeps of the cell that entered it first.
pub const FINGERPRINT_BITS: u32 = 8;
/// Cells per axis a large box's window may span (eight rounds): a wider one makes the frame
/// incomplete.
pub const MAX_WINDOW: u64 = 24;
/// The end of a list.
const NONE: u32 = u32::MAX;

/// The grid's geometry under one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridShape {
    /// log2 of the cell edge in key units.
    pub cell_bits: u32,
    /// Bits of an offset cell coordinate: `key_bits - g + 1`.
    pub coord_bits: u32,
    /// Bits of a bucket within a bank.
    pub hash_bits: u32,
    /// Lists per bucket (`HwConfig::list_groups`): one per group a box may be in, or one for
    /// every group; a box of group g is on list `g % groups`.
    pub groups: u32,
}

impl GridShape {
    pub fn new(cfg: &HwConfig) -> GridShape {
        let cell_bits = cfg.grid_cell_bits();
        GridShape {
            cell_bits,
            coord_bits: cfg.key_bits - cell_bits + 1,
            hash_bits: cfg.grid_hash_bits,
            groups: cfg.list_groups(),
        }
    }

    /// Keys spanning at most one cell edge on every axis: the window covers every box that can
    /// overlap them.
    pub fn is_small(&self, lo: &[u64; 3], hi: &[u64; 3]) -> bool {
        (0..3).all(|x| hi[x] - lo[x] <= 1 << self.cell_bits)
    }

    /// The cell a small box is entered in (offset coordinates): its lower corner's.
    pub fn home(&self, lo: &[u64; 3]) -> [u64; 3] {
        lo.map(|k| (k >> self.cell_bits) + 1)
    }

    /// The first and last cell of the window per axis (offset coordinates).
    pub fn window(&self, lo: &[u64; 3], hi: &[u64; 3]) -> ([u64; 3], [u64; 3]) {
        (
            lo.map(|k| k >> self.cell_bits),
            hi.map(|k| (k >> self.cell_bits) + 1),
        )
    }

    /// The rounds of a large box's window on one axis, `first..=last` (at least two cells):
    /// three cells each, but two and two where three would leave one alone, so that a round,
    /// like a small box's window, has two or three cells per axis.
    pub fn rounds(first: u64, last: u64) -> Vec<(u64, u64)> {
        let mut out = Vec::new();
        let mut r = first;
        while r <= last {
            let left = last - r + 1;
            let width = if left == 3 || left >= 5 { 3 } else { 2 };
            out.push((r, r + width - 1));
            r += width;
        }
        out
    }

    /// A cell's bank: its coordinates mod 3.
    pub fn bank(c: &[u64; 3]) -> usize {
        (c[0] % 3 + 3 * (c[1] % 3) + 9 * (c[2] % 3)) as usize
    }

    /// A cell's bucket in its bank: an H3 hash of the coordinates concatenated (x lowest):
    /// bucket bit k is the parity of the coordinate bits selected by `hash_row(k)`. Such a
    /// hash is linear, so the hardware hashes each axis apart and XORs the three; and a random
    /// matrix spreads any set of cells evenly, where folding or selecting bits gives whole
    /// planes of a surface one bucket.
    pub fn bucket(&self, c: &[u64; 3]) -> usize {
        self.hash(c, 0, self.hash_bits)
    }

    /// A cell's fingerprint: the same hash on the matrix rows after the bucket's widest.
    pub fn fingerprint(&self, c: &[u64; 3]) -> usize {
        self.hash(c, MAX_HASH_BITS, FINGERPRINT_BITS)
    }

    /// Bits `0..bits` of the H3 hash on matrix rows `first..first + bits`.
    fn hash(&self, c: &[u64; 3], first: u32, bits: u32) -> usize {
        let a = self.coord_bits;
        let word = u128::from(c[0]) | u128::from(c[1]) << a | u128::from(c[2]) << (2 * a);
        (0..bits)
            .map(|k| ((word & hash_row(first + k)).count_ones() as usize & 1) << k)
            .sum()
    }

    /// The window's cell in bank `b`, if it has one: per axis the cell whose coordinate mod 3 is
    /// the bank's (a window has at most three cells per axis).
    pub fn cell_in_bank(b: usize, first: &[u64; 3], last: &[u64; 3]) -> Option<[u64; 3]> {
        let want = [b % 3, b / 3 % 3, b / 9];
        let mut c = [0; 3];
        for x in 0..3 {
            let up = (want[x] as u64 + 3 - first[x] % 3) % 3;
            c[x] = first[x] + up;
            if c[x] > last[x] {
                return None;
            }
        }
        Some(c)
    }
}

/// Row `k` of the bucket hash's bit matrix: 128 pseudo-random bits (SplitMix64 from a fixed
/// seed), the same for every configuration; a configuration uses the columns of its
/// coordinate bits.
pub fn hash_row(k: u32) -> u128 {
    let split_mix = |i: u64| {
        let mut z = 0x6f62_6263_645f_6772u64.wrapping_add(i.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let k = u64::from(k);
    u128::from(split_mix(2 * k)) | u128::from(split_mix(2 * k + 1)) << 64
}

/// One group's list in a bucket of a bank: the fingerprint of the cell that entered it first
/// this frame, whether a box of a cell with another fingerprint entered it too, and the latest
/// box.
#[derive(Clone, Copy, Debug)]
struct List {
    owner: Option<usize>,
    mixed: bool,
    head: u32,
}

impl Default for List {
    fn default() -> Self {
        List {
            owner: None,
            mixed: false,
            head: NONE,
        }
    }
}

impl List {
    /// The first box to visit for a cell of fingerprint `fp`: the head, if the list may hold
    /// boxes of that cell (the owner has its fingerprint, or the list is mixed). A pure list of
    /// another fingerprint holds none, and is skipped without a visit.
    fn first_for(&self, fp: usize) -> u32 {
        if self.mixed || self.owner == Some(fp) {
            self.head
        } else {
            NONE
        }
    }

    /// Box `i` of a cell of fingerprint `fp` enters: the first owns the list, a box of another
    /// fingerprint mixes it. Returns the box it follows.
    fn enter(&mut self, fp: usize, i: usize) -> u32 {
        match self.owner {
            None => self.owner = Some(fp),
            Some(o) if o != fp => self.mixed = true,
            Some(_) => {}
        }
        std::mem::replace(&mut self.head, i as u32)
    }
}

/// The lists of one frame: per bank, bucket, group and lane a `List`, and each box's successor
/// (on its lane's list).
struct Lists {
    shape: GridShape,
    buckets: usize,
    lanes: usize,
    lists: Vec<List>,
    next: Vec<u32>,
}

impl Lists {
    fn new(shape: GridShape, n: usize, lanes: usize) -> Lists {
        let buckets = 1usize << shape.hash_bits;
        Lists {
            shape,
            buckets,
            lanes,
            lists: vec![List::default(); BANKS * buckets * shape.groups as usize * lanes],
            next: vec![NONE; n],
        }
    }

    /// Where `cell`'s list `g` (`GridShape::groups`) on `lane` is in `lists`.
    fn slot(&self, cell: &[u64; 3], g: u32, lane: usize) -> usize {
        let base = (GridShape::bank(cell) * self.buckets + self.shape.bucket(cell))
            * self.shape.groups as usize;
        (base + g as usize) * self.lanes + lane
    }

    /// Box `i` of group `g` enters its lane's list of its home cell.
    fn enter(&mut self, home: &[u64; 3], g: u32, i: usize) {
        let slot = self.slot(home, g % self.shape.groups, i % self.lanes);
        self.next[i] = self.lists[slot].enter(self.shape.fingerprint(home), i);
    }

    /// `meet(cell, j, starts)` for every box `j` on `lane`'s lists of the cells `first..=last`
    /// (at most 3 per axis, so one per bank) that a box of group `g` may meet under `mask`, in
    /// the lane walker's order: bank, group, latest box first.
    fn probe(
        &self,
        (first, last): (&[u64; 3], &[u64; 3]),
        (g, lane): (u32, usize),
        mask: &GroupMask,
        mut meet: impl FnMut(&[u64; 3], usize, bool),
    ) {
        // One list for every group: walked if the box's group pairs with any (the key check
        // applies the mask; the hardware's mask, with one list, pairs every group).
        let any = self.shape.groups == 1 && (0..1 << GROUP_BITS).any(|h| mask.allows(g, h));
        let walked = |h: u32| match self.shape.groups {
            1 => any,
            _ => mask.allows(g, h),
        };
        for b in 0..BANKS {
            let Some(cell) = GridShape::cell_in_bank(b, first, last) else {
                continue;
            };
            let fp = self.shape.fingerprint(&cell);
            for h in (0..self.shape.groups).filter(|&h| walked(h)) {
                let mut j = self.lists[self.slot(&cell, h, lane)].first_for(fp);
                let mut starts = true;
                while j != NONE {
                    meet(&cell, j as usize, starts);
                    starts = false;
                    j = self.next[j as usize];
                }
            }
        }
    }
}

/// What the grid's walk met, in the order the walkers meet it: the clock model's input. A
/// *record* (a box, a large box's round, the rest of the chains) has its visits on each lane,
/// lane by lane; each lane's are those of whole lists of that lane.
#[derive(Clone, Debug, Default)]
pub struct GridWalk {
    /// Walker lanes: box `i` is on lane `i % lanes`, which walks its lists.
    pub lanes: usize,
    /// Per box the frame streams (a haptic frame's resident boxes are not) and lane
    /// (`visits[i * lanes + lane]`), its visits on that lane (none for a large box; they follow
    /// each other in `passes`).
    pub visits: Vec<usize>,
    /// Per visit, in order: the pair passed the key check (and, on the slow path, the mask and
    /// the home cell).
    pub passes: Vec<bool>,
    /// Per visit, in order: the box walking and the box it meets.
    pub pairs: Vec<(u32, u32)>,
    /// Per list walked, in order: its visits (at least one).
    pub lists: Vec<usize>,
    /// The slow path, per large box in its order (lane by lane, each lane's chain latest
    /// first), up to and including the first whose window is too wide.
    pub large: Vec<LargeWalk>,
    /// The large box whose window spans more than `MAX_WINDOW` cells on an axis, if any: the
    /// slow path stopped at it, and the frame is incomplete.
    pub too_wide: Option<usize>,
    /// Bucket bits of a bank: the list heads take `2^hash_bits` clocks to clear.
    pub hash_bits: u32,
    /// An update frame (`resident_groups`): every list head is cleared before the first box
    /// is taken, for the resident groups' lists are kept after a frame.
    pub clear_first: bool,
}

/// A large box's slow path, after the load: its window read in rounds (at most one cell per
/// bank), then the large boxes after it in the slow path's order.
#[derive(Clone, Debug, Default)]
pub struct LargeWalk {
    pub index: usize,
    /// Visits per round and lane (`rounds[r * lanes + lane]`).
    pub rounds: Vec<usize>,
    /// Visits per lane to the large boxes after it: the rest of its own lane's chain, and the
    /// whole chains of the lanes after its own.
    pub partners: Vec<usize>,
}

/// Runs the grid on `frame`: every visit in the hardware's order goes to `send`, which emits the
/// pair when the mask allows it and the keys overlap. Fills `w.visits`, `w.large` and
/// `w.incomplete`.
pub(super) fn walk(
    frame: &ModelFrame,
    mask: &GroupMask,
    w: &mut BroadWork,
    send: &mut impl FnMut(&mut BroadWork, usize, usize),
) -> GridWalk {
    let shape = GridShape::new(&frame.cfg);
    let n = frame.obbs.len();
    let lanes = frame.cfg.lanes as usize;
    let mut lists = Lists::new(shape, n, lanes);
    let mut out = GridWalk {
        lanes,
        visits: Vec::with_capacity(n * lanes),
        hash_bits: shape.hash_bits,
        clear_first: frame.resident.is_none() && !frame.cfg.resident_groups.is_empty(),
        ..GridWalk::default()
    };
    // `send` checks the mask and the keys and counts what it emits; a visit outside its home
    // cell (`at_home` false, the slow path only) is not sent.
    let mut visit = |w: &mut BroadWork,
                     out: &mut GridWalk,
                     (i, j): (usize, usize),
                     starts: bool,
                     at_home: bool| {
        if starts {
            out.lists.push(0);
        }
        *out.lists.last_mut().expect("a list was started") += 1;
        let tests = w.sat_tests;
        w.visits += 1;
        if at_home {
            send(w, i, j);
        }
        out.passes.push(w.sat_tests > tests);
        out.pairs.push((i as u32, j as u32));
    };
    let mut large = Vec::new();
    // A haptic frame's resident boxes are in the lists the update frame left (entered in the
    // same order, so the lists are the same): they probe nothing and are not loaded.
    let resident = frame.resident.unwrap_or(0);
    for i in 0..n {
        let (lo, hi) = &frame.keys[i];
        let g = frame.obbs[i].group;
        if !shape.is_small(lo, hi) {
            large.push(i);
            if i >= resident {
                out.visits.extend(std::iter::repeat_n(0, lanes));
            }
            continue;
        }
        if i < resident {
            lists.enter(&shape.home(lo), g, i);
            continue;
        }
        let (wlo, whi) = shape.window(lo, hi);
        for lane in 0..lanes {
            let first = out.passes.len();
            lists.probe((&wlo, &whi), (g, lane), mask, |_, j, starts| {
                visit(w, &mut out, (i, j), starts, true)
            });
            out.visits.push(out.passes.len() - first);
        }
        lists.enter(&shape.home(lo), g, i);
    }
    // The slow path, after every small box has entered: the large boxes lane by lane, each
    // lane's latest first (the hardware chains them on their successor entries). Each reads its
    // window round by round (x fastest, then y, then z); a box is met only when its home cell
    // is in the round (a mixed list can be read in two rounds); then it meets the large boxes
    // after it: the rest of its lane's chain and the whole chains of the lanes after it.
    let chains: Vec<Vec<usize>> = (0..lanes)
        .map(|lane| {
            large
                .iter()
                .rev()
                .copied()
                .filter(|&l| l % lanes == lane)
                .collect()
        })
        .collect();
    'lanes: for (a, chain) in chains.iter().enumerate() {
        for (k, &l) in chain.iter().enumerate() {
            let (lo, hi) = &frame.keys[l];
            let g = frame.obbs[l].group;
            let (wlo, whi) = shape.window(lo, hi);
            let mut walk = LargeWalk {
                index: l,
                ..LargeWalk::default()
            };
            if (0..3).any(|x| whi[x] - wlo[x] + 1 > MAX_WINDOW) {
                out.too_wide = Some(l);
                out.large.push(walk);
                break 'lanes;
            }
            let [xs, ys, zs] = [0, 1, 2].map(|x| GridShape::rounds(wlo[x], whi[x]));
            for &(z0, z1) in &zs {
                for &(y0, y1) in &ys {
                    for &(x0, x1) in &xs {
                        for lane in 0..lanes {
                            let first = out.passes.len();
                            lists.probe(
                                (&[x0, y0, z0], &[x1, y1, z1]),
                                (g, lane),
                                mask,
                                |cell, j, starts| {
                                    let home = shape.home(&frame.keys[j].0) == *cell;
                                    visit(w, &mut out, (l, j), starts, home);
                                },
                            );
                            walk.rounds.push(out.passes.len() - first);
                        }
                    }
                }
            }
            // Per lane one list: the rest of its own chain, the whole chain of a later lane.
            for (b, other) in chains.iter().enumerate() {
                let after: &[usize] = match b.cmp(&a) {
                    std::cmp::Ordering::Less => &[],
                    std::cmp::Ordering::Equal => &chain[k + 1..],
                    std::cmp::Ordering::Greater => other,
                };
                for (p, &m) in after.iter().enumerate() {
                    visit(w, &mut out, (l, m), p == 0, true);
                }
                walk.partners.push(after.len());
            }
            out.large.push(walk);
        }
    }
    w.large = large.len() as u64;
    w.incomplete = out.too_wide.is_some();
    out
}
