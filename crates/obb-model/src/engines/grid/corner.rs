//! The lower-corner layout: one entry per box, in the cell of its AABB's lower corner, with
//! cells a little larger than the largest AABB. Two boxes whose AABBs overlap then have their
//! lower corners in the same cell or in neighbouring ones, so each cell meets itself and 13 of
//! its 26 neighbours (one of each opposite pair), and every overlapping pair is met exactly
//! once: no start flags and no home-cell test. With the keys running x fastest, the cells a
//! cell meets lie in five stretches of the sorted entries (`CornerCell`).
//!
//! The grid takes this layout when every pair is wanted and the boxes are of similar sizes
//! (`Corner::fit`): on the surgical scene it enters 17,500 entries where the regular layout
//! enters 33,652, and meets 343,170 pairs where that visits 504,329 (docs/engines.md).

use super::columns::{ColumnSlices, EntryColumns};
use super::geometry::GridGeometry;
use super::occupied::Occupied;
use super::MAX_BITMAP_CELLS;
use crate::aabb::Aabb;
use crate::prepared::Frame;
use rayon::prelude::*;

/// The corner layout is taken when its cell edge (the largest AABB extent) is at most this
/// many median AABB edges: the pairs met grow with the cell's volume. On the surgical scene
/// the cell is 2.04 median edges and its entries meet 343,170 pairs; in cells 1.5 times as
/// large they would meet 758,197, more than the regular layout's 504,329.
pub(super) const MAX_EDGE_PER_MEDIAN: f64 = 3.0;
/// The cell edge is the largest AABB extent grown by this fraction, so that rounding cannot
/// put two overlapping boxes' corners two cells apart (`Corner::fit`).
const EDGE_GROWTH: f64 = 1.0 / 1024.0;
/// Cells per axis at most: the scaled coordinates stay below 2^20, which the growth's
/// argument needs, and the keys below 2^60.
const MAX_CELLS_PER_AXIS: u64 = 1 << 20;
/// On several threads, each task of the build takes at least this many boxes or cells: fewer
/// cost more to hand over than to do.
const BUILD_CHUNK: usize = 2048;

/// One occupied cell: its entries, and the stretches of sorted entries they meet. Entry `p`
/// meets the later entries of its cell and those of the next cell on x (one stretch, `p + 1 ..
/// next_end`), and, for each `(dy, dz)` of `ROWS`, the entries of the three cells `x - 1 ..= x
/// + 1` of that row (`rows`).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct CornerCell {
    pub start: u32,
    pub end: u32,
    pub next_end: u32,
    pub rows: [(u32, u32); 4],
}

/// The neighbouring rows of cells a cell meets: with `(1, 0)` for its own row (through
/// `next_end`), one of each opposite pair of the 26 neighbours.
const ROWS: [(u64, i64); 4] = [(1, -1), (1, 0), (1, 1), (0, 1)];

impl CornerCell {
    /// Pairs its entries meet.
    pub fn work(&self) -> usize {
        let n = (self.end - self.start) as usize;
        let own = (self.next_end - self.start) as usize;
        let rows: usize = self.rows.iter().map(|&(a, b)| (b - a) as usize).sum();
        n * (own + rows) - n * (n + 1) / 2
    }
}

/// The layout's buffers, kept between frames.
#[derive(Debug, Default)]
pub(super) struct Corner {
    pub geometry: GridGeometry,
    /// Each box's cell, and its place among the occupied cells.
    keys: Vec<u64>,
    ordinals: Vec<u32>,
    /// The boxes, sorted by cell.
    entries: Vec<u32>,
    /// Each occupied cell's key, in order, and the next place of each as the entries are
    /// placed.
    cell_keys: Vec<u64>,
    next: Vec<u32>,
    /// The sorted entries' AABBs and boxes.
    pub columns: EntryColumns,
    occupied: Occupied,
    pub cells: Vec<CornerCell>,
}

impl Corner {
    /// The layout's geometry for `boxes`, when its cell edge is at most `max_edge`, positive
    /// and normal, and the grid fits the occupancy bitmap; else `None`.
    ///
    /// Why no overlapping pair is missed: on each axis, AABBs that overlap have lower corners
    /// `v_a <= v_b` at most one extent apart, and the computed extents are within `u` of the
    /// exact ones, so `v_b - v_a <= (1 + u) e` for the largest computed extent `e`
    /// (`Frame::widest`). The scaled coordinate `fl(fl(v - o) · fl(1/E))` is within `3u`
    /// (relative) of `(v - o)/E`, and below 2^20, so the two scaled corners differ by at most
    /// `(1 + u)/(1 + 2^-10) + 6u · 2^20 < 1`: their cells (the floors) are the same or
    /// neighbours. The offset `v - o` is never negative, as `o` is the least corner.
    pub fn fit(boxes: &Frame, max_edge: f64) -> Option<GridGeometry> {
        let (largest, bounds) = (boxes.widest, &boxes.bounds);
        let cell = largest + largest * EDGE_GROWTH;
        if !(cell >= f64::MIN_POSITIVE && cell <= max_edge) {
            return None;
        }
        let inv = 1.0 / cell;
        let mut dims = [0u64; 3];
        for (x, d) in dims.iter_mut().enumerate() {
            let span = (bounds.max[x] - bounds.min[x]) * inv;
            if span.is_nan() || span >= (MAX_CELLS_PER_AXIS - 3) as f64 {
                return None;
            }
            // One cell of padding on each side: a neighbour's key never wraps into another row.
            *d = span as u64 + 3;
        }
        // One more cell than the grid: the stretches' ends look up keys up to the grid's size.
        let cells = dims[0] * dims[1] * dims[2] + 1;
        (cells <= MAX_BITMAP_CELLS).then_some(GridGeometry {
            origin: bounds.min,
            cell,
            inv,
            dims,
        })
    }

    /// Enters each box in the cell of its AABB's lower corner, sorts the entries by cell (a
    /// counting sort over the occupied cells, the order of the boxes kept within a cell) into
    /// their columns, and finds each occupied cell's stretches. All but the sort run on
    /// `threads` threads.
    pub fn build(&mut self, boxes: &Frame, g: GridGeometry, threads: usize) {
        self.geometry = g;
        let [nx, ny, nz] = g.dims;
        // Through i64, which converts at half the cost of u64: the offset is never negative.
        let cell_of = |b: &Aabb, x: usize| ((b.min[x] - g.origin[x]) * g.inv) as i64 as u64 + 1;
        self.keys.resize(boxes.len(), 0);
        on_chunks(threads, &mut self.keys, |at, keys| {
            for (k, b) in keys.iter_mut().zip(&boxes.aabbs[at..]) {
                *k = (cell_of(b, 2) * ny + cell_of(b, 1)) * nx + cell_of(b, 0);
            }
        });
        sort(self, nx * ny * nz + 1);
        // The columns, written in order: placed straight from the counting sort, the columns'
        // megabyte was written at random and took longer.
        let columns = self.columns.room(self.entries.len());
        fill_on(threads, columns, &self.entries, boxes.aabbs);
        self.cells
            .resize(self.cell_keys.len(), CornerCell::default());
        let (cell_keys, occupied) = (&self.cell_keys, &self.occupied);
        on_chunks(threads, &mut self.cells, |at, cells| {
            find_stretches(cell_keys, occupied, at, cells, (nx, nx * ny));
        });
    }

    /// Entries in the grid.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Most boxes in one cell.
    pub fn max_per_cell(&self) -> usize {
        let most = self.cells.iter().map(|c| c.end - c.start).max();
        most.unwrap_or(0) as usize
    }
}

/// The counting sort of `corner.keys` over a grid of `cells` cells (the last never occupied):
/// each box at the next place of its cell in `entries`. Compiled with the popcount instruction
/// where the CPU has it (`find_stretches`).
#[multiversion::multiversion(targets("x86_64+popcnt"))]
fn sort(corner: &mut Corner, cells: u64) {
    let Corner {
        keys,
        ordinals,
        entries,
        cell_keys,
        next,
        occupied,
        ..
    } = corner;
    occupied.count(keys, cells, ordinals);
    let starts = occupied.starts();
    next.clear();
    next.extend_from_slice(&starts[..starts.len() - 1]);
    cell_keys.clear();
    cell_keys.resize(next.len(), 0);
    entries.resize(keys.len(), 0);
    for (i, (&k, &cell)) in keys.iter().zip(&*ordinals).enumerate() {
        let cell = cell as usize;
        entries[next[cell] as usize] = i as u32;
        next[cell] += 1;
        cell_keys[cell] = k;
    }
}

/// Runs `f(at, chunk)` on chunks of `out` (`at` where each starts) on all threads when
/// `threads` is above 1 and `out` is long enough to share, else on `out` whole.
fn on_chunks<T: Send>(threads: usize, out: &mut [T], f: impl Fn(usize, &mut [T]) + Sync) {
    if threads > 1 && out.len() >= 2 * BUILD_CHUNK {
        let chunk = out.len().div_ceil(threads).max(BUILD_CHUNK);
        out.par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(c, out)| f(c * chunk, out));
    } else {
        f(0, out);
    }
}

/// Fills `columns` with `entries` (`ColumnSlices::fill`), in halves on all threads when
/// `threads` is above 1 and there are entries enough to share.
fn fill_on(threads: usize, mut columns: ColumnSlices, entries: &[u32], aabbs: &[Aabb]) {
    if threads < 2 || entries.len() < 2 * BUILD_CHUNK {
        return columns.fill(entries, aabbs);
    }
    let mid = entries.len() / 2;
    let ((a, b), (ea, eb)) = (columns.split_at(mid), entries.split_at(mid));
    let half = threads / 2;
    rayon::join(
        || fill_on(half, a, ea, aabbs),
        || fill_on(threads - half, b, eb, aabbs),
    );
}

/// The stretches (`CornerCell`) of the occupied cells from the `at`-th, whose keys are
/// `cell_keys[at..]`, into `cells`. Each stretch end is a rank in the occupancy bitmap:
/// compiled with the popcount instruction where the CPU has it, as without it `count_ones` is
/// a dozen instructions.
#[multiversion::multiversion(targets("x86_64+popcnt"))]
fn find_stretches(
    cell_keys: &[u64],
    occupied: &Occupied,
    at: usize,
    cells: &mut [CornerCell],
    (row, layer): (u64, u64),
) {
    let starts = occupied.starts();
    for (r, (cell, &k)) in cells.iter_mut().zip(&cell_keys[at..]).enumerate() {
        let r = at + r;
        let mut rows = [(0, 0); 4];
        for (stretch, &(dy, dz)) in rows.iter_mut().zip(&ROWS) {
            let mid = (k + dy * row).wrapping_add_signed(dz * layer as i64);
            let from = |key| starts[occupied.ordinal(key)];
            *stretch = (from(mid - 1), from(mid + 2));
        }
        *cell = CornerCell {
            start: starts[r],
            end: starts[r + 1],
            next_end: starts[occupied.ordinal(k + 2)],
            rows,
        };
    }
}
