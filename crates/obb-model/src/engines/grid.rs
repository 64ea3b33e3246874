//! Uniform-grid broad phase on a radix sort of cell keys.
//!
//! Each box is entered in every cell its AABB covers; the (cell key, box) entries are sorted by a
//! stable radix sort, so a cell's boxes lie together in ascending index order. A pair meeting in
//! a cell is examined there, and emitted only from the cell that holds the lower corner of the
//! two AABBs' intersection, which both AABBs cover: each overlapping pair is found exactly once.
//! The work follows the real overlaps instead of one axis's projection (docs/engines.md).

use super::{ordered, Counters, Engine, EngineKind, Pair, PairSorter};
use crate::aabb::Aabb;
use crate::groups::GroupMask;
use crate::prepared::Prepared;
use crate::radix::{bits_for, RadixSorter};
use crate::sat::boxes_collide;
use rayon::prelude::*;

/// A box covering more cells than this is not entered in the grid but tested against every box:
/// one huge box must not fill memory with cell entries.
const MAX_CELLS_PER_BOX: u64 = 64;
/// Cells per axis at most (keys stay below 2^60).
const MAX_CELLS_PER_AXIS: u64 = 1 << 20;
/// Cell edge as a multiple of the median AABB edge: the measured sweet spot between entries per
/// box and pairs per cell (docs/engines.md).
const CELL_PER_MEDIAN_EDGE: f64 = 2.0;
/// Cell runs are split into this many chunks of equal pair work per thread.
const CHUNKS_PER_THREAD: usize = 8;
/// A cell entry holds the box index in its low bits and, above them, one flag per axis: set when
/// the box's cell range starts in this cell on that axis.
const INDEX_BITS: u32 = 29;
const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;
const ALL_AXES: u32 = 0b111 << INDEX_BITS;
/// Largest grid (in cells) for which an occupancy bitmap is kept (4 MiB of bits).
const MAX_BITMAP_CELLS: u64 = 1 << 25;

/// The grid's geometry for one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridGeometry {
    pub origin: [f64; 3],
    pub cell: f64,
    /// Multiplier turning a coordinate offset into a cell coordinate (1 / cell).
    pub inv: f64,
    pub dims: [u64; 3],
}

impl GridGeometry {
    /// Cell coordinate of `x` on `axis`. Monotone in `x`, so a box's cell range covers the cell
    /// of any point inside it.
    #[inline]
    fn coord(&self, x: f64, axis: usize) -> u64 {
        ((x - self.origin[axis]) * self.inv) as u64
    }

    #[inline]
    fn key(&self, c: [u64; 3]) -> u64 {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// Sets origin and dims for cells of edge `cell` over `lo..=hi`, enlarging the cell when the
    /// extent would need more than `MAX_CELLS_PER_AXIS` cells.
    fn fit(lo: [f64; 3], hi: [f64; 3], cell: f64) -> GridGeometry {
        let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
        let cell = cell.max(extent / (MAX_CELLS_PER_AXIS - 2) as f64);
        let g = GridGeometry {
            origin: lo,
            cell,
            inv: 1.0 / cell,
            dims: [1; 3],
        };
        GridGeometry {
            dims: std::array::from_fn(|a| g.coord(hi[a], a) + 1),
            ..g
        }
    }
}

/// Cell edge from the boxes: `CELL_PER_MEDIAN_EDGE` times the median of each AABB's mean edge.
fn choose_cell(aabbs: &[Aabb], scratch: &mut Vec<f64>) -> f64 {
    scratch.clear();
    scratch.extend(
        aabbs
            .iter()
            .map(|b| ((b.max[0] - b.min[0]) + (b.max[1] - b.min[1]) + (b.max[2] - b.min[2])) / 3.0),
    );
    let mid = scratch.len() / 2;
    let (_, median, _) = scratch.select_nth_unstable_by(mid, f64::total_cmp);
    let cell = *median * CELL_PER_MEDIAN_EDGE;
    // Boxes of zero size give a zero median: any positive cell is then correct.
    if cell > 0.0 && cell.is_finite() {
        cell
    } else {
        1.0
    }
}

/// Uniform-grid engine. `cell` fixes the cell edge; `None` chooses it from the scene each frame.
#[derive(Debug)]
pub struct Grid {
    cell: Option<f64>,
    geometry: GridGeometry,
    keys: Vec<u64>,
    entries: Vec<u32>,
    large: Vec<u32>,
    is_large: Vec<bool>,
    /// (start, end) of each cell holding two or more entries.
    runs: Vec<(u32, u32)>,
    /// Chunk boundaries in `runs`, cut at equal pair work.
    cuts: Vec<usize>,
    chunk_pairs: Vec<Vec<Pair>>,
    scratch: Vec<f64>,
    /// Cells occupied by boxes outside the sparse group (see `build`).
    occupied: Vec<u64>,
    group_sizes: Vec<(u32, usize)>,
    radix: RadixSorter<u32>,
    sorter: PairSorter,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            cell: None,
            geometry: GridGeometry::default(),
            keys: Vec::new(),
            entries: Vec::new(),
            large: Vec::new(),
            is_large: Vec::new(),
            runs: Vec::new(),
            cuts: Vec::new(),
            chunk_pairs: Vec::new(),
            scratch: Vec::new(),
            occupied: Vec::new(),
            group_sizes: Vec::new(),
            radix: RadixSorter::new(11),
            sorter: PairSorter::default(),
        }
    }
}

/// What the grid built in its last detection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridStats {
    pub geometry: GridGeometry,
    /// Cell entries (box, cell) in the grid.
    pub entries: usize,
    /// Boxes tested against every box instead of entered in the grid.
    pub large: usize,
    /// Most boxes in one cell.
    pub max_per_cell: usize,
}

impl Grid {
    /// A grid with a fixed cell edge, which must be a positive finite length.
    pub fn with_cell(cell: f64) -> Result<Grid, String> {
        if !(cell > 0.0 && cell.is_finite()) {
            return Err(format!(
                "grid cell edge must be a positive length, got {cell}"
            ));
        }
        Ok(Grid {
            cell: Some(cell),
            ..Grid::default()
        })
    }

    pub fn stats(&self) -> GridStats {
        GridStats {
            geometry: self.geometry,
            entries: self.keys.len(),
            large: self.large.len(),
            max_per_cell: self
                .runs
                .iter()
                .map(|&(s, e)| (e - s) as usize)
                .max()
                .unwrap_or(usize::from(!self.keys.is_empty())),
        }
    }

    /// The most populous group, if the scene has more than one.
    fn largest_group(&mut self, boxes: &Prepared) -> Option<u32> {
        self.group_sizes.clear();
        for &g in &boxes.groups {
            match self.group_sizes.iter_mut().find(|(h, _)| *h == g) {
                Some((_, n)) => *n += 1,
                None => self.group_sizes.push((g, 1)),
            }
            // Many distinct groups: not the tissue-and-instruments shape this is for.
            if self.group_sizes.len() > 64 {
                return None;
            }
        }
        let &(g0, _) = self
            .group_sizes
            .iter()
            .max_by_key(|(g, n)| (*n, std::cmp::Reverse(*g)))?;
        (self.group_sizes.len() > 1).then_some(g0)
    }

    /// Enters the boxes whose group passes `pick` in the cells their AABBs cover (only in
    /// occupied cells when `only_occupied`), or in the large list when they cover too many.
    fn enter(&mut self, boxes: &Prepared, pick: impl Fn(u32) -> bool, only_occupied: bool) {
        let g = self.geometry;
        for (i, b) in boxes.aabbs.iter().enumerate() {
            if !pick(boxes.groups[i]) {
                continue;
            }
            let c0 = [
                g.coord(b.min[0], 0),
                g.coord(b.min[1], 1),
                g.coord(b.min[2], 2),
            ];
            let c1 = [
                g.coord(b.max[0], 0),
                g.coord(b.max[1], 1),
                g.coord(b.max[2], 2),
            ];
            let cells = (c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1);
            if cells > MAX_CELLS_PER_BOX {
                self.large.push(i as u32);
                self.is_large[i] = true;
                continue;
            }
            for z in c0[2]..=c1[2] {
                for y in c0[1]..=c1[1] {
                    for x in c0[0]..=c1[0] {
                        let key = g.key([x, y, z]);
                        if only_occupied
                            && self.occupied[(key / 64) as usize] & (1 << (key % 64)) == 0
                        {
                            continue;
                        }
                        let starts = u32::from(x == c0[0])
                            | u32::from(y == c0[1]) << 1
                            | u32::from(z == c0[2]) << 2;
                        self.keys.push(key);
                        self.entries.push(i as u32 | starts << INDEX_BITS);
                    }
                }
            }
        }
    }

    /// Enters every box in its cells (or in the large list) and sorts the entries by cell.
    fn build(&mut self, boxes: &Prepared, mask: &GroupMask) {
        let aabbs = &boxes.aabbs;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for b in aabbs {
            for (a, (l, h)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                *l = l.min(b.min[a]);
                *h = h.max(b.max[a]);
            }
        }
        let cell = match self.cell {
            Some(c) => c,
            None => choose_cell(aabbs, &mut self.scratch),
        };
        let g = GridGeometry::fit(lo, hi, cell);
        self.geometry = g;
        self.keys.clear();
        self.entries.clear();
        self.large.clear();
        self.is_large.clear();
        self.is_large.resize(aabbs.len(), false);
        // When the mask excludes pairs inside the largest group (tissue, for cross-group
        // detection), a box of that group can only pair with a box of another group, in a cell
        // that box covers: enter the other groups first, mark their cells, and enter the largest
        // group's boxes only where a cell is marked. Exact, and it leaves out the tissue-only cells.
        let cells = g.dims[0] * g.dims[1] * g.dims[2];
        let sparse = self
            .largest_group(boxes)
            .filter(|&g0| !mask.allows(g0, g0) && cells <= MAX_BITMAP_CELLS);
        self.occupied.clear();
        if let Some(g0) = sparse {
            self.occupied.resize(cells.div_ceil(64) as usize, 0);
            self.enter(boxes, |grp| grp != g0, false);
            for &k in &self.keys {
                self.occupied[(k / 64) as usize] |= 1 << (k % 64);
            }
            self.enter(boxes, |grp| grp == g0, true);
        } else {
            self.enter(boxes, |_| true, false);
        }
        let key_bits = bits_for(cells - 1);
        self.radix.sort(&mut self.keys, &mut self.entries, key_bits);
        self.runs.clear();
        let mut start = 0;
        let mut work = 0;
        for p in 1..=self.keys.len() {
            if p == self.keys.len() || self.keys[p] != self.keys[start] {
                if p - start >= 2 {
                    self.runs.push((start as u32, p as u32));
                    work += (p - start) * (p - start - 1) / 2;
                }
                start = p;
            }
        }
        // Cut the runs into chunks of about equal pair work: dense cells (an instrument's) lie
        // together in key order and would otherwise load one thread.
        let chunks = rayon::current_num_threads() * CHUNKS_PER_THREAD;
        let target = work.div_ceil(chunks).max(1);
        self.cuts.clear();
        self.cuts.push(0);
        let mut acc = 0;
        for (r, &(s, e)) in self.runs.iter().enumerate() {
            let len = (e - s) as usize;
            acc += len * (len - 1) / 2;
            if acc >= target {
                self.cuts.push(r + 1);
                acc = 0;
            }
        }
        if *self.cuts.last().expect("starts with 0") != self.runs.len() {
            self.cuts.push(self.runs.len());
        }
    }
}

/// Examines the pairs inside the cells `runs`, appending the colliding ones to `out`.
/// `candidates` counts each pair once, in its home cell: the cell holding the lower corner of the
/// two boxes' cell ranges' intersection, where on every axis one of the two ranges starts. That
/// is the cell of the lower corner of the AABBs' intersection (cell coordinates are monotone).
fn scan_cells(
    entries: &[u32],
    runs: &[(u32, u32)],
    boxes: &Prepared,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
) -> Counters {
    let mut c = Counters::default();
    out.clear();
    for &(s, e) in runs {
        let cell = &entries[s as usize..e as usize];
        for (p, &ei) in cell.iter().enumerate() {
            let i = (ei & INDEX_MASK) as usize;
            let (bi, gi) = (&boxes.aabbs[i], boxes.groups[i]);
            for &ej in &cell[p + 1..] {
                // Once only: skip the pair unless this is its home cell.
                if (ei | ej) & ALL_AXES != ALL_AXES {
                    continue;
                }
                let j = (ej & INDEX_MASK) as usize;
                if !mask.allows(gi, boxes.groups[j]) {
                    continue;
                }
                c.candidates += 1;
                if !bi.overlaps(&boxes.aabbs[j]) {
                    continue;
                }
                // The AABBs overlap: this is `Prepared::collide` without repeating that check.
                c.sat += 1;
                if boxes_collide(&boxes.sat[i], &boxes.sat[j]) {
                    // Ascending within a cell unless boxes were entered in two rounds.
                    out.push(ordered(i, j));
                }
            }
        }
    }
    c
}

/// Tests the large box `l` against every box, each pair of large boxes once.
fn scan_large(
    l: usize,
    is_large: &[bool],
    boxes: &Prepared,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
) -> Counters {
    let mut c = Counters::default();
    for (j, &j_large) in is_large.iter().enumerate() {
        if j == l || (j_large && j < l) || !mask.allows(boxes.groups[l], boxes.groups[j]) {
            continue;
        }
        c.candidates += 1;
        if boxes.aabbs[l].overlaps(&boxes.aabbs[j]) {
            c.sat += 1;
            if boxes_collide(&boxes.sat[l], &boxes.sat[j]) {
                out.push(ordered(l, j));
            }
        }
    }
    c
}

impl Engine for Grid {
    fn kind(&self) -> EngineKind {
        EngineKind::Grid
    }

    fn detect(&mut self, boxes: &Prepared, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        out.clear();
        if boxes.is_empty() {
            self.keys.clear();
            self.runs.clear();
            self.large.clear();
            return Counters::default();
        }
        self.build(boxes, mask);
        let used = self.cuts.len() - 1;
        if self.chunk_pairs.len() < used + 1 {
            self.chunk_pairs.resize_with(used + 1, Vec::new);
        }
        let (cell_outs, large_out) = self.chunk_pairs.split_at_mut(used);
        let (cuts, runs, entries) = (&self.cuts, &self.runs, &self.entries);
        let mut c = cell_outs
            .par_iter_mut()
            .enumerate()
            .map(|(k, o)| scan_cells(entries, &runs[cuts[k]..cuts[k + 1]], boxes, mask, o))
            .reduce(Counters::default, |mut a, b| {
                a += b;
                a
            });
        let large_out = &mut large_out[0];
        large_out.clear();
        for &l in &self.large {
            c += scan_large(l as usize, &self.is_large, boxes, mask, large_out);
        }
        for o in cell_outs.iter() {
            out.extend_from_slice(o);
        }
        out.extend_from_slice(large_out);
        self.sorter.sort_dedup(out, boxes.len());
        c.pairs = out.len() as u64;
        c
    }
}
