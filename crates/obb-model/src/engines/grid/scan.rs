//! The pair work: the home pairs inside each cell, the sparse group's boxes probing the cells,
//! and the large boxes against every box.

use super::geometry::GridGeometry;
use super::occupied::Occupied;
use super::ranks::{Ranks, MAX_RANKS};
use super::{FLAG_BITS, MAX_CELLS_PER_BOX};
use crate::aabb::Aabb;
use crate::engines::{ordered, Counters, Pair};
use crate::groups::GroupMask;
use crate::prepared::Frame;
use crate::sat::retain_colliding;
use crate::simd::Vectors;
use std::mem::MaybeUninit;

mod corner;
#[cfg(target_arch = "x86_64")]
mod step;
#[cfg(target_arch = "x86_64")]
mod vector;
pub(super) use corner::scan_corner;
#[cfg(target_arch = "x86_64")]
pub(super) use vector::Columns;
/// Where the vector scan is not built, its buffers are none.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Debug, Default)]
pub(super) struct Columns;

/// Classes in one cell at most: every rank with every flag pattern.
const MAX_CLASSES: usize = MAX_RANKS << FLAG_BITS;

/// The sorted entries and what a scan needs to read them.
pub(super) struct Cells<'a> {
    pub keys: &'a [u64],
    pub entries: &'a [u32],
    pub ranks: &'a Ranks,
    /// Bit `b` of `wanted[a]`: pairs of classes a and b are wanted (`Ranks::pairs_wanted`).
    pub wanted: [u64; MAX_CLASSES],
}

impl<'a> Cells<'a> {
    pub fn new(keys: &'a [u64], entries: &'a [u32], ranks: &'a Ranks) -> Self {
        // Only the classes this frame's keys can hold: 8 for one rank, not all 64.
        let classes = 1 << ranks.class_bits();
        let mut wanted = [0u64; MAX_CLASSES];
        for (a, row) in wanted.iter_mut().enumerate().take(classes) {
            for b in 0..classes {
                *row |= u64::from(ranks.pairs_wanted(a as u64, b as u64)) << b;
            }
        }
        Cells {
            keys,
            entries,
            ranks,
            wanted,
        }
    }
}

/// Pairs written at `out[kept]` and kept when their AABBs overlap, with no branch on that (it
/// goes either way about as often); `reserve` makes room first. A pair is written as found and
/// put in order (lower index first) only when kept, in `finish`. The pairs are written past the
/// Vec's length, into its spare capacity, and the length is set once, in `finish`: filling the
/// room with zeros first (as `resize` does) was about 2 % of the surgical scene's frame.
struct Emitter<'a> {
    out: &'a mut Vec<Pair>,
    /// Every pair below `kept` has been written.
    kept: usize,
    counters: Counters,
}

impl<'a> Emitter<'a> {
    fn new(out: &'a mut Vec<Pair>) -> Self {
        out.clear();
        Emitter {
            out,
            kept: 0,
            counters: Counters::default(),
        }
    }

    /// Room for `n` more pairs in the spare capacity (`out`'s length stays 0 until `finish`).
    #[inline]
    fn reserve(&mut self, n: usize) {
        self.out.reserve(self.kept + n);
    }

    /// The room `reserve` made, from `kept` on.
    #[inline(always)]
    fn room(&mut self) -> &mut [MaybeUninit<Pair>] {
        &mut self.out.spare_capacity_mut()[self.kept..]
    }

    /// A visited pair, boxes `i` and `j`; room must have been reserved.
    #[inline(always)]
    fn pair(&mut self, boxes: &Frame, i: usize, j: usize) {
        self.counters.visits += 1;
        self.room()[0].write([i as u32, j as u32]);
        self.kept += usize::from(overlaps(&boxes.aabbs[i], &boxes.aabbs[j]));
    }

    /// The pairs of the cell's entry `p` with each later entry `q`, of which those with
    /// `wanted(q)` are visited; room must have been reserved. The scan's inner loop: one AABB
    /// compare and one store per pair, kept when wanted and overlapping, with no branch.
    #[inline(always)]
    fn row(&mut self, cell: &[CellEntry], p: usize, wanted: impl Fn(&CellEntry) -> bool) {
        let (a_id, reach) = (cell[p].id, cell[p].reach());
        let later = &cell[p + 1..];
        let out = &mut self.room()[..later.len()];
        let (mut k, mut visits) = (0, 0);
        for b in later {
            let w = wanted(b);
            out[k].write([a_id, b.id]);
            k += usize::from(w & b.within(&reach));
            visits += u64::from(w);
        }
        self.kept += k;
        self.counters.visits += visits;
    }

    /// The SAT decides on the pairs whose AABBs overlap, in vector lanes.
    fn finish(self, boxes: &Frame) -> Counters {
        let mut c = self.counters;
        // SAFETY: `reserve` made room for every pair written, and every pair below `kept` has
        // been written (`kept` only ever counts pairs already stored).
        unsafe { self.out.set_len(self.kept) };
        for p in self.out.iter_mut() {
            *p = ordered(p[0], p[1]);
        }
        c.sat_tests = self.kept as u64;
        retain_colliding(boxes, self.out);
        c
    }
}

/// A cell's entry as the scan reads it: the box, its class and its AABB side by side.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct CellEntry {
    /// The AABB as `[min, -max, 0, 0]`: two AABBs overlap when one's row is at most, lane by
    /// lane, the other's [`CellEntry::reach`]. Eight lanes compare at once in vector registers
    /// where six separate compares with their own flags cost several times more.
    bounds: [f64; 8],
    id: u32,
    class: u32,
}

impl CellEntry {
    /// Fills the entry in place: built elsewhere and copied, its 64-byte row would be read back
    /// whole right after being written in parts, which stalls the copy.
    #[inline(always)]
    fn set(&mut self, aabb: &Aabb, id: u32, class: u32) {
        let (l, h) = (aabb.min, aabb.max);
        self.bounds = [l[0], l[1], l[2], -h[0], -h[1], -h[2], 0.0, 0.0];
        self.id = id;
        self.class = class;
    }

    /// `[max, -min, 0, 0]`: what another entry's `bounds` must not exceed in any lane to overlap.
    #[inline(always)]
    fn reach(&self) -> [f64; 8] {
        let b = &self.bounds;
        [-b[3], -b[4], -b[5], -b[0], -b[1], -b[2], 0.0, 0.0]
    }

    /// Whether this entry's AABB overlaps the one whose [`CellEntry::reach`] is `reach`: exactly
    /// [`overlaps`] (negation is exact, and `x <= y` is `-y <= -x`), with no branch.
    #[inline(always)]
    fn within(&self, reach: &[f64; 8]) -> bool {
        self.bounds
            .iter()
            .zip(reach)
            .fold(true, |all, (b, r)| all & (b <= r))
    }
}

/// `Aabb::overlaps` without short-circuit branches.
#[inline(always)]
fn overlaps(a: &Aabb, b: &Aabb) -> bool {
    (a.min[0] <= b.max[0])
        & (b.min[0] <= a.max[0])
        & (a.min[1] <= b.max[1])
        & (b.min[1] <= a.max[1])
        & (a.min[2] <= b.max[2])
        & (b.min[2] <= a.max[2])
}

/// Examines the wanted home pairs inside the cells `runs` and puts the colliding ones in `out`,
/// on the instruction set `vectors` (one this CPU has; the grid takes the best). Unless the
/// mask is checked pair by pair, each entry meets eight later ones at a time with AVX-512 and
/// four with AVX2 (`vector`, with `columns` its buffers); otherwise it is [`scan_rows`]. Every
/// form visits, counts and keeps the same pairs in the same order.
pub(super) fn scan_cells(
    vectors: Vectors,
    cells: &Cells,
    runs: &[(u32, u32)],
    boxes: &Frame,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
    buffers: (&mut Vec<CellEntry>, &mut Columns),
) -> Counters {
    #[cfg(target_arch = "x86_64")]
    if !cells.ranks.pairwise {
        if let Some(c) = vector::on(vectors, cells, runs, boxes, out, buffers.1) {
            return c;
        }
    }
    scan_rows(cells, runs, boxes, mask, out, buffers.0)
}

/// [`scan_cells`], one pair per step.
///
/// Each cell's entries are first copied to `cell` with their classes and AABBs, so that a box's
/// meetings in its cell read one short stretch. Then every pair of the cell is tested, without a
/// branch, for being wanted (at home and allowed: the classes of both) and for overlapping
/// AABBs. Most pairs of a cell are wanted (three in four for all pairs on the surgical scene),
/// and a cell's entries fall into many short runs of one class: pairing whole runs of classes
/// cost more in loop overhead than the unwanted pairs cost here.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
pub(super) fn scan_rows(
    cells: &Cells,
    runs: &[(u32, u32)],
    boxes: &Frame,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
    cell: &mut Vec<CellEntry>,
) -> Counters {
    let ranks = cells.ranks;
    let class_mask = ranks.class_mask();
    let mut emit = Emitter::new(out);
    for &(s, e) in runs {
        let (s, e) = (s as usize, e as usize);
        let (keys, entries) = (&cells.keys[s..e], &cells.entries[s..e]);
        let n = entries.len();
        cell.resize(n, CellEntry::default());
        for ((e, &k), &id) in cell.iter_mut().zip(keys).zip(entries) {
            e.set(&boxes.aabbs[id as usize], id, (k & class_mask) as u32);
        }
        emit.reserve(n * (n - 1) / 2);
        for p in 0..n {
            let row = cells.wanted[cell[p].class as usize];
            let want = |b: &CellEntry| (row >> b.class) & 1 == 1;
            if ranks.pairwise {
                let g = boxes.groups[cell[p].id as usize];
                let allowed = |b: &CellEntry| mask.allows(g, boxes.groups[b.id as usize]);
                emit.row(cell, p, |b| want(b) && allowed(b));
            } else {
                emit.row(cell, p, want);
            }
        }
    }
    emit.finish(boxes)
}

/// The boxes `probes` (of the sparse group, not entered in the grid) each look up the occupied
/// cells they cover and meet there the entries with which they are at home and wanted. Boxes
/// covering too many cells go to `large` instead.
pub(super) fn probe(
    cells: &Cells,
    geometry: &GridGeometry,
    occupied: &Occupied,
    probes: impl Iterator<Item = usize>,
    boxes: &Frame,
    out: &mut Vec<Pair>,
    large: &mut Vec<u32>,
) -> Counters {
    let class_mask = cells.ranks.class_mask();
    let mut emit = Emitter::new(out);
    large.clear();
    for i in probes {
        // Outside the entered boxes' bounds there is nothing to meet. (A large entered box is
        // not in the bounds: it meets every box in `scan_large`.)
        if !overlaps(&boxes.aabbs[i], &occupied.bounds) {
            continue;
        }
        let (c0, c1) = geometry.range(&boxes.aabbs[i]);
        if GridGeometry::cells_in(c0, c1) > MAX_CELLS_PER_BOX {
            large.push(i as u32);
            continue;
        }
        let rank = cells.ranks.rank(i) << FLAG_BITS;
        for z in c0[2]..=c1[2] {
            for y in c0[1]..=c1[1] {
                for x in c0[0]..=c1[0] {
                    let run = occupied.entries(geometry.key([x, y, z]));
                    if run.is_empty() {
                        continue;
                    }
                    let class = rank | start_flags([x, y, z], c0);
                    emit.reserve(run.len());
                    for p in run {
                        if cells.ranks.pairs_wanted(class, cells.keys[p] & class_mask) {
                            emit.pair(boxes, i, cells.entries[p] as usize);
                        }
                    }
                }
            }
        }
    }
    emit.finish(boxes)
}

/// One flag per axis, set when a box whose cell range starts at `c0` starts in cell `c`.
#[inline]
pub(super) fn start_flags(c: [u64; 3], c0: [u64; 3]) -> u64 {
    u64::from(c[0] == c0[0]) | u64::from(c[1] == c0[1]) << 1 | u64::from(c[2] == c0[2]) << 2
}

/// Tests the large box `l` against every box, each pair of large boxes once.
pub(super) fn scan_large(
    l: usize,
    is_large: &[bool],
    boxes: &Frame,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
) -> Counters {
    let mut c = Counters::default();
    for (j, &j_large) in is_large.iter().enumerate() {
        if j == l || (j_large && j < l) || !mask.allows(boxes.groups[l], boxes.groups[j]) {
            continue;
        }
        c.visits += 1;
        if boxes.aabbs[l].overlaps(&boxes.aabbs[j]) {
            c.sat_tests += 1;
            if boxes.sat(l, j) {
                out.push(ordered(l as u32, j as u32));
            }
        }
    }
    c
}
