//! Uniform-grid broad phase on a radix sort of cell keys.
//!
//! Each box is entered in every cell its AABB covers; the (cell key, box) entries are sorted by a
//! stable radix sort, so a cell's boxes lie together. A pair meeting in a cell is examined there,
//! and emitted only from its home cell, the cell that holds the lower corner of the two AABBs'
//! intersection, which both AABBs cover: each overlapping pair is found exactly once.
//! The work follows the real overlaps instead of one axis's projection (docs/engines.md).
//!
//! Below the cell, a key holds a box's class: its group's rank (when the mask tells groups
//! apart) and three flags, one per axis, set when the box's cell range starts in this cell on
//! that axis. A pair is in its home cell exactly when, on every axis, one of the two starts
//! there. The scan tests every pair of a cell, without a branch, for being wanted (its two
//! classes' flags cover all three axes and the mask allows their ranks) and for overlapping
//! AABBs: only the wanted pairs count as visits, and each overlapping pair is kept once.
//!
//! When every pair is wanted and the boxes are of similar sizes, the grid takes the *corner*
//! layout instead (`corner`): cells a little larger than the largest AABB, each box entered
//! once, in the cell of its AABB's lower corner, and each cell meeting itself and 13 of its
//! neighbours.
//!
//! When the mask excludes the pairs inside the largest group (tissue, for cross-group
//! detection), only the other groups are entered and sorted; each box of the largest group then
//! probes the cells it covers (see `Grid::build`).
//!
//! When the mask tells groups apart, a box whose AABB meets none of the bounds (the union of the
//! AABBs) of the groups the mask pairs it with has no pair, and is not entered: cross-group on
//! the surgical scene, all but a few dozen of the instruments' 7,500 boxes (`Ranks::may_pair`).

mod columns;
mod corner;
mod geometry;
mod occupied;
mod ranks;
mod resident;
mod rigid;
mod scan;
mod slab;
mod warm;

pub use geometry::GridGeometry;
pub use resident::Resident;
pub use rigid::RigidResident;

use super::{threads, Counters, Engine, EngineKind, Pair, PairSorter};
use crate::aabb::Aabb;
use crate::groups::GroupMask;
use crate::prepared::Frame;
use crate::radix::bits_for;
use crate::simd::Vectors;
use corner::{Corner, CornerCell};
use geometry::{choose_cell, CELL_PER_MEDIAN_EDGE, PROBING_CELL_PER_MEDIAN_EDGE};
use occupied::Occupied;
use ranks::Ranks;
use rayon::prelude::*;
use scan::{probe, scan_cells, scan_corner, scan_large, CellEntry, Cells, Columns};
use slab::{Layout, Slab};

/// A box covering more cells than this is not entered in the grid but tested against every box:
/// one huge box must not fill memory with cell entries.
const MAX_CELLS_PER_BOX: u64 = 64;
/// The pair work is split into this many chunks per thread.
const CHUNKS_PER_THREAD: usize = 8;
/// The three start flags in the low bits of a key.
const FLAG_BITS: u32 = 3;
const ALL_STARTS: u64 = 0b111;
/// Largest grid (in cells) for which an occupancy bitmap is kept (4 MiB of bits, and as many
/// rank words): the probing needs it.
const MAX_BITMAP_CELLS: u64 = 1 << 25;
/// Below this much pair work (cell entries, plus the boxes that probe), the scan and the
/// probing run on the calling thread: handing a few hundred boxes' work to another thread costs
/// more than the work, and a haptic frame's tail latency suffers most from it (the other core
/// may be busy, and a worker woken for each frame competes with the caller).
const PARALLEL_MIN_WORK: usize = 4096;

/// One parallel task's buffers, kept between frames. Aligned to two cache lines so that tasks
/// running side by side do not write to one line (the Vecs' lengths change as they fill).
#[derive(Debug, Default)]
#[repr(align(128))]
struct Task {
    /// Its colliding pairs.
    pairs: Vec<Pair>,
    /// The probing boxes it found too large.
    large: Vec<u32>,
    /// The entries of the cell being scanned, as rows and as columns (see `scan_cells`).
    cell: Vec<CellEntry>,
    columns: Columns,
}

/// Uniform-grid engine. `cell` fixes the cell edge; `None` chooses it from the scene each frame.
#[derive(Debug, Default)]
pub struct Grid {
    cell: Option<f64>,
    /// Never the corner layout (the tests of the regular layout's scan set it).
    regular_only: bool,
    /// The corner layout's buffers, and whether the last detection used it.
    corner: Corner,
    cornered: bool,
    geometry: GridGeometry,
    ranks: Ranks,
    keys: Vec<u64>,
    entries: Vec<u32>,
    large: Vec<u32>,
    is_large: Vec<bool>,
    /// The large boxes' colliding pairs.
    large_pairs: Vec<Pair>,
    /// (start, end) of each cell holding two or more entries of wanted pairs.
    runs: Vec<(u32, u32)>,
    /// Chunk boundaries in `runs`, cut at equal pair work.
    cuts: Vec<usize>,
    /// The group that probes instead of being entered, when there is one.
    prober: Option<u32>,
    tasks: Vec<Task>,
    scratch: Vec<f64>,
    /// Where each occupied cell's entries start, when a group probes.
    occupied: Occupied,
    /// The grid's z slabs, one per thread at most.
    slabs: Vec<Slab>,
    /// The threads the scan and the probing run on this frame: 1 below `PARALLEL_MIN_WORK`.
    threads: usize,
    /// Sampled z layers, to place the slabs.
    layers: Vec<u64>,
    sorter: PairSorter,
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
    /// Whether the corner layout took the detection (one entry per box, `corner`).
    pub corner: bool,
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
        if self.cornered {
            return GridStats {
                geometry: self.corner.geometry,
                entries: self.corner.len(),
                large: 0,
                max_per_cell: self.corner.max_per_cell(),
                corner: true,
            };
        }
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
            corner: false,
        }
    }

    /// Enters the boxes in their cells (or in the large list), sorts the entries by key, and
    /// finds the cells with pairs to examine, in slabs of z layers on all threads.
    /// `self.ranks` must be up to date for `boxes` and the mask.
    fn build(&mut self, boxes: &Frame, cell: f64) {
        let aabbs = boxes.aabbs;
        let g = GridGeometry::fit(boxes.bounds.min, boxes.bounds.max, cell);
        self.geometry = g;
        // When the mask excludes pairs inside the largest group, a box of that group only pairs
        // with boxes of other groups, in cells they cover: enter only the other groups, and let
        // each box of the largest group probe the occupied cells it covers. The largest group is
        // then neither entered nor sorted, which is most of the work for cross-group detection.
        let cells = g.dims[0] * g.dims[1] * g.dims[2];
        let class_bits = self.ranks.class_bits();
        let prober = self.ranks.sparse.filter(|_| cells <= MAX_BITMAP_CELLS);
        self.prober = prober;
        let layout = Layout {
            geometry: &self.geometry,
            ranks: &self.ranks,
            boxes,
            prober,
            key_bits: bits_for(cells - 1) + class_bits,
        };
        let threads = threads();
        slab::place(&mut self.slabs, threads, &layout, &mut self.layers);
        let ranks = &self.ranks;
        match &mut self.slabs[..] {
            // One slab (one thread) is built here and its buffers handed over: a parallel
            // iterator would still ask rayon for the current pool's size, which starts rayon's
            // global pool on a thread outside any pool.
            [only] => {
                only.build(&layout);
                only.publish_whole(&mut self.keys, &mut self.entries, ranks);
            }
            slabs => {
                slabs.par_iter_mut().for_each(|s| s.build(&layout));
                let total = slabs.iter().map(Slab::len).sum();
                self.keys.resize(total, 0);
                self.entries.resize(total, 0);
                slab::for_each_part(
                    slabs,
                    &mut self.keys,
                    &mut self.entries,
                    0,
                    &|s, k, e, offset| s.publish(k, e, offset, ranks),
                );
            }
        }
        let total = self.keys.len();
        self.large.clear();
        self.is_large.clear();
        self.is_large.resize(aabbs.len(), false);
        self.runs.clear();
        for s in &self.slabs {
            for &l in &s.large {
                self.is_large[l as usize] = true;
            }
            self.large.extend_from_slice(&s.large);
            self.runs.extend_from_slice(&s.runs);
        }
        self.occupied.clear();
        if prober.is_some() {
            let bounds = self
                .slabs
                .iter()
                .fold(Aabb::EMPTY, |b, s| b.union(&s.bounds));
            let entry_cells = self.keys.iter().map(|k| k >> class_bits);
            self.occupied.index(entry_cells, cells, bounds);
        }
        let work = total + prober.map_or(0, |_| aabbs.len());
        self.threads = if work < PARALLEL_MIN_WORK { 1 } else { threads };
        let pairs = |&(s, e): &(u32, u32)| {
            let len = (e - s) as usize;
            len * (len - 1) / 2
        };
        cut_by_work(&self.runs, pairs, self.threads, &mut self.cuts);
    }

    /// The cell edge of the regular layout: fixed, or a multiple of the median AABB edge.
    fn regular_cell(&mut self, aabbs: &[Aabb]) -> f64 {
        match self.cell {
            Some(c) => c,
            None => {
                let factor = match self.ranks.sparse {
                    Some(_) => PROBING_CELL_PER_MEDIAN_EDGE,
                    None => CELL_PER_MEDIAN_EDGE,
                };
                choose_cell(aabbs, factor, &mut self.scratch)
            }
        }
    }

    /// The frame in the corner layout, when every pair is wanted, the cell edge is chosen, and
    /// the largest AABB is at most `corner::MAX_EDGE_PER_MEDIAN` median edges (the regular
    /// cell, `cell`, is `CELL_PER_MEDIAN_EDGE` of them); else `None`.
    fn detect_corner(&mut self, boxes: &Frame, cell: f64, out: &mut Vec<Pair>) -> Option<Counters> {
        let all_wanted = self.ranks.bits == 0 && !self.ranks.pairwise;
        if self.regular_only || self.cell.is_some() || !all_wanted {
            return None;
        }
        let max_edge = cell * (corner::MAX_EDGE_PER_MEDIAN / CELL_PER_MEDIAN_EDGE);
        let geometry = Corner::fit(boxes, max_edge)?;
        self.cornered = true;
        let threads = match boxes.len() {
            n if n < PARALLEL_MIN_WORK => 1,
            _ => threads(),
        };
        Some(match threads {
            1 => self.corner_frame(boxes, geometry, threads, out),
            // The frame's parallel phases alternate with serial stretches: with a worker kept
            // warm (`warm`), the surgical scene's frame on 2 threads took 1.85 to 2.04 ms
            // (median 2.01) where it took 2.25 to 3.21 (2.35), ten rounds each in turn.
            _ => warm::while_warm(|| self.corner_frame(boxes, geometry, threads, out)),
        })
    }

    /// The frame in the corner layout of `geometry`, on `threads` threads.
    fn corner_frame(
        &mut self,
        boxes: &Frame,
        geometry: GridGeometry,
        threads: usize,
        out: &mut Vec<Pair>,
    ) -> Counters {
        self.corner.build(boxes, geometry, threads);
        cut_by_work(
            &self.corner.cells,
            CornerCell::work,
            threads,
            &mut self.cuts,
        );
        let n_tasks = self.cuts.len() - 1;
        if self.tasks.len() < n_tasks {
            self.tasks.resize_with(n_tasks, Default::default);
        }
        let (corner, cuts, vectors) = (&self.corner, &self.cuts, Vectors::detected());
        let run = |(t, task): (usize, &mut Task)| {
            let cells = &corner.cells[cuts[t]..cuts[t + 1]];
            scan_corner(vectors, corner, cells, boxes, &mut task.pairs)
        };
        let mut c = run_tasks(&mut self.tasks[..n_tasks], threads, run);
        let runs = self.tasks[..n_tasks].iter().map(|t| &t.pairs[..]);
        self.sorter.sort_dedup_runs(runs, out, boxes.len());
        c.pairs = out.len() as u64;
        c
    }
}

/// Runs `run` on each task (with its index), on all threads when `threads` is above 1, and
/// sums their counters.
fn run_tasks<F>(tasks: &mut [Task], threads: usize, run: F) -> Counters
where
    F: Fn((usize, &mut Task)) -> Counters + Send + Sync,
{
    let add = |mut a: Counters, b: Counters| {
        a += b;
        a
    };
    if threads > 1 {
        tasks
            .par_iter_mut()
            .enumerate()
            .map(run)
            .reduce(Counters::default, add)
    } else {
        tasks
            .iter_mut()
            .enumerate()
            .map(run)
            .fold(Counters::default(), add)
    }
}

/// Cuts `items` into chunks of about equal `work` for `threads` threads, as the indices where
/// each chunk starts and the end: dense cells lie together in key order and would otherwise
/// load one thread.
fn cut_by_work<T>(items: &[T], work: impl Fn(&T) -> usize, threads: usize, cuts: &mut Vec<usize>) {
    let total: usize = items.iter().map(&work).sum();
    let target = total.div_ceil(threads * CHUNKS_PER_THREAD).max(1);
    cuts.clear();
    cuts.push(0);
    let mut acc = 0;
    for (r, item) in items.iter().enumerate() {
        acc += work(item);
        if acc >= target {
            cuts.push(r + 1);
            acc = 0;
        }
    }
    if *cuts.last().expect("starts with 0") != items.len() {
        cuts.push(items.len());
    }
}

impl Engine for Grid {
    fn kind(&self) -> EngineKind {
        EngineKind::Grid
    }

    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        out.clear();
        if !boxes.is_empty() {
            self.ranks.update(boxes, mask);
        }
        self.cornered = false;
        if boxes.is_empty() || !self.ranks.any_pair() {
            self.keys.clear();
            self.runs.clear();
            self.large.clear();
            return Counters::default();
        }
        let cell = self.regular_cell(boxes.aabbs);
        if let Some(c) = self.detect_corner(boxes, cell, out) {
            return c;
        }
        self.build(boxes, cell);
        // Tasks: the cell chunks, then (when a group probes) equal ranges of box indices.
        let cell_tasks = self.cuts.len() - 1;
        let probe_tasks = match self.prober {
            Some(_) => self.threads * CHUNKS_PER_THREAD,
            None => 0,
        };
        let n_tasks = cell_tasks + probe_tasks;
        if self.tasks.len() < n_tasks {
            self.tasks.resize_with(n_tasks, Default::default);
        }
        let cells = Cells::new(&self.keys, &self.entries, &self.ranks);
        let vectors = Vectors::detected();
        let (cuts, runs, geometry, occupied) =
            (&self.cuts, &self.runs, &self.geometry, &self.occupied);
        let (prober, probe_len) = (self.prober, boxes.len().div_ceil(probe_tasks.max(1)));
        let run = |(t, task): (usize, &mut Task)| {
            let Task {
                pairs,
                large,
                cell,
                columns,
            } = task;
            large.clear();
            if t < cell_tasks {
                let runs = &runs[cuts[t]..cuts[t + 1]];
                let buffers = (cell, columns);
                return scan_cells(vectors, &cells, runs, boxes, mask, pairs, buffers);
            }
            let first = ((t - cell_tasks) * probe_len).min(boxes.len());
            let last = (first + probe_len).min(boxes.len());
            let pick = |i: &usize| Some(boxes.groups[*i]) == prober;
            probe(
                &cells,
                geometry,
                occupied,
                (first..last).filter(pick),
                boxes,
                pairs,
                large,
            )
        };
        let mut c = run_tasks(&mut self.tasks[..n_tasks], self.threads, run);
        for task in &self.tasks[..n_tasks] {
            for &l in &task.large {
                self.is_large[l as usize] = true;
                self.large.push(l);
            }
        }
        self.large_pairs.clear();
        for &l in &self.large {
            let is_large = &self.is_large;
            c += scan_large(l as usize, is_large, boxes, mask, &mut self.large_pairs);
        }
        let tasks = self.tasks[..n_tasks].iter().map(|t| &t.pairs[..]);
        let runs = tasks.chain(std::iter::once(&self.large_pairs[..]));
        self.sorter.sort_dedup_runs(runs, out, boxes.len());
        c.pairs = out.len() as u64;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{surgical, uniform};
    use crate::prepared::Prepared;
    use crate::scene::Obb;

    /// The scans' test scenes: dense, sparse and grouped, of boxes of similar sizes.
    fn scan_scenes() -> [Vec<Obb>; 3] {
        [
            surgical(6000, 3).expect("valid size").obbs,
            uniform(3000, 5, 8.0).expect("valid size").obbs,
            uniform(3000, 6, 0.5).expect("valid size").obbs,
        ]
    }

    /// Scans every cell of the grid `detect` built on `obbs` with the one-pair scan and with
    /// each form this CPU has, and returns each scan's pairs (as found, before the pair sort)
    /// and counters, the one-pair scan's first.
    fn every_scan(obbs: &[Obb], mask: &GroupMask) -> Vec<(Vec<Pair>, Counters)> {
        let mut prepared = Prepared::default();
        let boxes = prepared.update(obbs);
        let mut grid = Grid {
            regular_only: true,
            ..Grid::default()
        };
        let mut pairs = Vec::new();
        grid.detect(&boxes, mask, &mut pairs);
        let cells = Cells::new(&grid.keys, &grid.entries, &grid.ranks);
        let (mut cell, mut columns) = (Vec::new(), Columns::default());
        let mut rows = Vec::new();
        let row_counters = scan::scan_rows(&cells, &grid.runs, &boxes, mask, &mut rows, &mut cell);
        let mut scans = vec![(rows, row_counters)];
        for &vectors in Vectors::available() {
            let mut any = Vec::new();
            let buffers = (&mut cell, &mut columns);
            let counters = scan_cells(vectors, &cells, &grid.runs, &boxes, mask, &mut any, buffers);
            scans.push((any, counters));
        }
        scans
    }

    /// Every form of the scan this CPU has (eight entries a step with AVX-512, four with AVX2)
    /// visits, counts and keeps the same pairs in the same order as the one-pair scan, on dense,
    /// sparse and grouped scenes with every kind of mask; and it found pairs, so the comparison
    /// says something.
    #[test]
    fn vector_scan_equals_the_row_scan() {
        let scenes = scan_scenes();
        let masks = [
            GroupMask::All,
            GroupMask::Cross,
            GroupMask::Pairs(vec![(0, 1), (1, 1), (2, 2)]),
        ];
        for (s, obbs) in scenes.iter().enumerate() {
            for mask in &masks {
                let scans = every_scan(obbs, mask);
                let rows = &scans[0];
                for (any, vectors) in scans[1..].iter().zip(Vectors::available()) {
                    assert_eq!(rows, any, "scene {s}, mask {mask}, {vectors:?}");
                }
                if *mask == GroupMask::All {
                    assert!(rows.0.len() > 100, "scene {s} has pairs to compare");
                }
            }
        }
    }

    /// The corner layout's scan, in every form this CPU has, meets, counts and keeps the same
    /// pairs in the same order as its portable form, on dense and sparse scenes.
    #[test]
    fn corner_scan_forms_agree() {
        let scenes = scan_scenes();
        for (s, obbs) in scenes.iter().enumerate() {
            let mut prepared = Prepared::default();
            let boxes = prepared.update(obbs);
            let mut grid = Grid::default();
            grid.detect(&boxes, &GroupMask::All, &mut Vec::new());
            assert!(
                grid.cornered,
                "scene {s}: boxes of similar sizes, every pair wanted"
            );
            let scan = |vectors| {
                let mut pairs = Vec::new();
                let cells = &grid.corner.cells;
                let c = scan_corner(vectors, &grid.corner, cells, &boxes, &mut pairs);
                (pairs, c)
            };
            let portable = scan(Vectors::Portable);
            assert!(portable.0.len() > 100, "scene {s} has pairs to compare");
            for &vectors in Vectors::available() {
                assert_eq!(scan(vectors), portable, "scene {s}, {vectors:?}");
            }
        }
    }

    /// The corner layout enters each box once, and only when every pair is wanted and no box
    /// is much larger than the median; otherwise the regular layout takes the frame.
    #[test]
    fn corner_layout_is_taken_for_similar_boxes_and_every_pair() {
        let mut obbs = surgical(2000, 3).expect("valid size").obbs;
        let layout = |obbs: &[Obb], mask: &GroupMask| {
            let mut prepared = Prepared::default();
            let boxes = prepared.update(obbs);
            let mut grid = Grid::default();
            grid.detect(&boxes, mask, &mut Vec::new());
            let stats = grid.stats();
            (stats.corner, stats.entries)
        };
        assert_eq!(layout(&obbs, &GroupMask::All), (true, obbs.len()));
        assert!(!layout(&obbs, &GroupMask::Cross).0, "cross-group probes");
        let pairs = GroupMask::Pairs(vec![(0, 0), (1, 2)]);
        assert!(!layout(&obbs, &pairs).0, "a mask telling groups apart");
        obbs[7].half = [40.0, 1.0, 1.0];
        assert!(!layout(&obbs, &GroupMask::All).0, "one box far larger");
    }
}
