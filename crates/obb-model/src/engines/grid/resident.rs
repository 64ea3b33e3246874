//! Resident static boxes, as the core keeps the tissue: the static boxes (the tissue) are
//! prepared and entered in a grid of their own once per update; a frame brings only the moving
//! boxes (the instruments), which probe that grid, and meet each other in a `Grid` of their own.
//!
//! Indices: the static boxes are 0..S, the moving ones S.. in the order given, as in a scene
//! that lists the static group first. The pairs are those of every other engine on that scene:
//! closed AABB overlap and the SAT, each pair once (a static-moving pair is taken in its home
//! cell, the cell of the lower corner of the two AABBs' intersection, which both cover).

use super::geometry::{choose_cell, GridGeometry, RESIDENT_CELL_PER_MEDIAN_EDGE};
use super::occupied::Occupied;
use super::{Grid, MAX_BITMAP_CELLS, MAX_CELLS_PER_BOX};
use crate::aabb::Aabb;
use crate::engines::{Counters, Engine, Pair};
use crate::groups::GroupMask;
use crate::prepared::Prepared;
use crate::sat::{boxes_collide, Slack};
use crate::scene::Obb;

#[derive(Debug, Default)]
pub struct Resident {
    mask: GroupMask,
    statics: Vec<Obb>,
    aabbs: Vec<Aabb>,
    slack: Vec<Slack>,
    /// The union of the entered static boxes' AABBs.
    bounds: Aabb,
    /// The union of every static box's AABB, the large ones' too.
    all_bounds: Aabb,
    geometry: GridGeometry,
    /// Each static box's first cell on each axis (a coordinate is below 2^21).
    first_cells: Vec<[u32; 3]>,
    /// (cell key, static box), sorted by key.
    entries: Vec<(u64, u32)>,
    /// Where each occupied cell's entries lie in `entries`, when the grid has at most
    /// `MAX_BITMAP_CELLS` cells; else not indexed, and a cell is found by a binary search (a
    /// probe's lookups are most of a haptic frame's time).
    occupied: Occupied,
    /// Static boxes covering more than `MAX_CELLS_PER_BOX` cells: met by every moving box.
    large: Vec<u32>,
    /// The pairs among the static boxes the mask allows, found on update.
    static_pairs: Vec<Pair>,
    moving: Prepared,
    grid: Grid,
    moving_pairs: Vec<Pair>,
}

impl Resident {
    /// New static boxes and the mask every later frame uses: prepares and enters them, and finds
    /// the pairs among them.
    pub fn update_static(&mut self, statics: &[Obb], mask: &GroupMask) -> Counters {
        self.mask = mask.clone();
        self.statics.clear();
        self.statics.extend_from_slice(statics);
        let mut prepared = Prepared::default();
        let frame = prepared.update(&self.statics);
        let counters = self.grid.detect(&frame, mask, &mut self.static_pairs);
        self.aabbs.clear();
        self.aabbs.extend_from_slice(frame.aabbs);
        self.slack.clear();
        self.slack.extend_from_slice(frame.slack);
        let mut scratch = Vec::new();
        let cell = if statics.is_empty() {
            1.0
        } else {
            choose_cell(&self.aabbs, RESIDENT_CELL_PER_MEDIAN_EDGE, &mut scratch)
        };
        self.geometry = GridGeometry::fit(frame.bounds.min, frame.bounds.max, cell);
        self.all_bounds = frame.bounds;
        self.entries.clear();
        self.large.clear();
        self.first_cells.clear();
        self.bounds = Aabb::EMPTY;
        for (j, b) in self.aabbs.iter().enumerate() {
            let (c0, c1) = self.geometry.range(b);
            self.first_cells.push(c0.map(|c| c as u32));
            if GridGeometry::cells_in(c0, c1) > MAX_CELLS_PER_BOX {
                self.large.push(j as u32);
                continue;
            }
            self.bounds = self.bounds.union(b);
            for z in c0[2]..=c1[2] {
                for y in c0[1]..=c1[1] {
                    for x in c0[0]..=c1[0] {
                        self.entries.push((self.geometry.key([x, y, z]), j as u32));
                    }
                }
            }
        }
        self.entries.sort_unstable();
        self.occupied.clear();
        let cells = self.geometry.dims.iter().product::<u64>();
        if cells <= MAX_BITMAP_CELLS {
            let entry_cells = self.entries.iter().map(|e| e.0);
            self.occupied.index(entry_cells, cells, self.bounds);
        }
        counters
    }

    /// The number of static boxes.
    pub fn statics(&self) -> usize {
        self.statics.len()
    }

    /// The union of the static boxes' AABBs (`Aabb::EMPTY` for none): a moving box whose AABB
    /// misses it meets no static box.
    pub fn static_bounds(&self) -> Aabb {
        if self.statics.is_empty() {
            Aabb::EMPTY
        } else {
            self.all_bounds
        }
    }

    /// The pairs of the scene "static boxes, then `moving`", sorted ascending.
    pub fn detect(&mut self, moving: &[Obb], out: &mut Vec<Pair>) -> Counters {
        let s = self.statics.len() as u32;
        let frame = self.moving.update(moving);
        // The moving boxes' own pairs: `Grid` returns at once when no two of them may meet
        // (two instruments apart), most of a haptic frame's work otherwise.
        let mut counters = self.grid.detect(&frame, &self.mask, &mut self.moving_pairs);
        out.clear();
        out.extend_from_slice(&self.static_pairs);
        counters.pairs += self.static_pairs.len() as u64;
        let from = out.len();
        for (i, (m, a)) in moving.iter().zip(frame.aabbs).enumerate() {
            let ms = &frame.slack[i];
            let meet = |j: u32, counters: &mut Counters, out: &mut Vec<Pair>| {
                let ju = j as usize;
                counters.visits += 1;
                if self.mask.allows(self.statics[ju].group, m.group) && self.aabbs[ju].overlaps(a) {
                    counters.sat_tests += 1;
                    if boxes_collide(&self.statics[ju], &self.slack[ju], m, ms) {
                        counters.pairs += 1;
                        out.push([j, s + i as u32]);
                    }
                }
            };
            for &j in &self.large {
                meet(j, &mut counters, out);
            }
            if !a.overlaps(&self.bounds) {
                continue;
            }
            let g = &self.geometry;
            let (first, c1) = g.range(a);
            let last = g.dims.map(|d| d - 1);
            let (c0, c1): ([u64; 3], [u64; 3]) = (
                std::array::from_fn(|k| first[k].min(last[k])),
                std::array::from_fn(|k| c1[k].min(last[k])),
            );
            if GridGeometry::cells_in(c0, c1) > MAX_CELLS_PER_BOX {
                // A moving box larger than the cells it would look up: every static box.
                for j in 0..s {
                    if !self.large.contains(&j) {
                        meet(j, &mut counters, out);
                    }
                }
                continue;
            }
            for z in c0[2]..=c1[2] {
                for y in c0[1]..=c1[1] {
                    for x in c0[0]..=c1[0] {
                        for &(_, j) in cell(&self.entries, &self.occupied, g.key([x, y, z])) {
                            // Home cell: where the intersection's lower corner lies. The cell
                            // coordinate is monotone, so that is the larger of the two boxes'
                            // first cells on each axis.
                            let b = &self.first_cells[j as usize];
                            let home: [u64; 3] =
                                std::array::from_fn(|k| first[k].max(u64::from(b[k])));
                            if home == [x, y, z] {
                                meet(j, &mut counters, out);
                            }
                        }
                    }
                }
            }
        }
        // Static-moving pairs come out by moving box: sort them by static box.
        out[from..].sort_unstable();
        if !self.static_pairs.is_empty() {
            // Two sorted runs (the static pairs, the static-moving pairs): the stable sort
            // merges natural runs, in linear time.
            out.sort();
        }
        out.extend(self.moving_pairs.iter().map(|&[i, j]| [s + i, s + j]));
        counters
    }
}

/// The static boxes entered in cell `key`: `entries` sorted by key, `occupied` their index or
/// not indexed.
#[inline]
fn cell<'a>(entries: &'a [(u64, u32)], occupied: &Occupied, key: u64) -> &'a [(u64, u32)] {
    if occupied.is_indexed() {
        &entries[occupied.entries(key)]
    } else {
        let start = entries.partition_point(|e| e.0 < key);
        let end = start + entries[start..].partition_point(|e| e.0 == key);
        &entries[start..end]
    }
}
