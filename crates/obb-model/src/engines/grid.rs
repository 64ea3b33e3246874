//! Uniform-grid broad phase on a radix sort of cell keys.
//!
//! Each box is entered in every cell its AABB covers; the (cell key, box) entries are sorted by a
//! stable radix sort, so a cell's boxes lie together in ascending index order. A pair meeting in
//! a cell is examined there, and emitted only from the cell that holds the lower corner of the
//! two AABBs' intersection, which both AABBs cover: each overlapping pair is found exactly once.
//! The work follows the real overlaps instead of one axis's projection (docs/engines.md).

use super::{Counters, Engine, EngineKind, Pair, PairSorter};
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
/// Cell runs are split into this many work chunks per thread, to even out the load.
const CHUNKS_PER_THREAD: usize = 8;

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

    #[inline]
    fn decode(&self, key: u64) -> [u64; 3] {
        let xy = self.dims[0] * self.dims[1];
        [
            key % self.dims[0],
            (key / self.dims[0]) % self.dims[1],
            key / xy,
        ]
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
    chunk_pairs: Vec<Vec<Pair>>,
    scratch: Vec<f64>,
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
            chunk_pairs: Vec::new(),
            scratch: Vec::new(),
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

    /// Enters every box in its cells (or in the large list) and sorts the entries by cell.
    fn build(&mut self, boxes: &Prepared) {
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
        for (i, b) in aabbs.iter().enumerate() {
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
                        self.keys.push(g.key([x, y, z]));
                        self.entries.push(i as u32);
                    }
                }
            }
        }
        let key_bits = bits_for(g.dims[0] * g.dims[1] * g.dims[2] - 1);
        self.radix.sort(&mut self.keys, &mut self.entries, key_bits);
        self.runs.clear();
        let mut start = 0;
        for p in 1..=self.keys.len() {
            if p == self.keys.len() || self.keys[p] != self.keys[start] {
                if p - start >= 2 {
                    self.runs.push((start as u32, p as u32));
                }
                start = p;
            }
        }
    }
}

/// Examines the pairs inside the cells `runs`, appending the colliding ones to `out`.
fn scan_cells(
    g: &GridGeometry,
    keys: &[u64],
    entries: &[u32],
    runs: &[(u32, u32)],
    boxes: &Prepared,
    mask: &GroupMask,
    out: &mut Vec<Pair>,
) -> Counters {
    let mut c = Counters::default();
    out.clear();
    for &(s, e) in runs {
        let (s, e) = (s as usize, e as usize);
        let here = g.decode(keys[s]);
        for p in s..e {
            let i = entries[p] as usize;
            let (bi, gi) = (&boxes.aabbs[i], boxes.groups[i]);
            for &j in &entries[p + 1..e] {
                let j = j as usize;
                if !mask.allows(gi, boxes.groups[j]) {
                    continue;
                }
                c.candidates += 1;
                let bj = &boxes.aabbs[j];
                if !bi.overlaps(bj) {
                    continue;
                }
                // Once only: the lower corner of the intersection must lie in this cell.
                let lower_here = (0..3).all(|a| g.coord(bi.min[a].max(bj.min[a]), a) == here[a]);
                if !lower_here {
                    continue;
                }
                // The AABBs overlap: this is `Prepared::collide` without repeating that check.
                c.sat += 1;
                if boxes_collide(&boxes.sat[i], &boxes.sat[j]) {
                    out.push([i as u32, j as u32]);
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
                out.push(super::ordered(l, j));
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
        self.build(boxes);
        let chunks = (rayon::current_num_threads() * CHUNKS_PER_THREAD).max(1);
        let per_chunk = self.runs.len().div_ceil(chunks).max(1);
        let used = self.runs.len().div_ceil(per_chunk);
        if self.chunk_pairs.len() < used + 1 {
            self.chunk_pairs.resize_with(used + 1, Vec::new);
        }
        let (cell_outs, large_out) = self.chunk_pairs.split_at_mut(used);
        let (g, keys, entries) = (&self.geometry, &self.keys, &self.entries);
        let mut c = cell_outs
            .par_iter_mut()
            .zip(self.runs.par_chunks(per_chunk))
            .map(|(o, runs)| scan_cells(g, keys, entries, runs, boxes, mask, o))
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
