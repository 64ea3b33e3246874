//! [`super::scan_cells`] with each row's later entries taken several at a time, written once
//! over the vector instruction set ([`Isa`]): eight with AVX-512, four with AVX2.
//!
//! The scalar scan tests one pair per step: one AABB compare of eight lanes, one class test and
//! one store, about eight operations a pair. Here a cell's entries are laid out as columns (each
//! AABB bound, the class and the id in an array of their own), so that one step compares an
//! entry with `W` later ones: six vector compares, one shift for the classes, and the kept
//! pairs compressed in a register and stored whole (the lanes past the kept ones are
//! overwritten by the next step). Every pair is visited, counted and kept exactly as the scalar
//! scan does, in the same order, which the tests check.

use super::{Cells, Emitter};
use crate::engines::{Counters, Pair};
use crate::prepared::Frame;
use crate::simd::{compile_for_each_isa, Isa, LaneMask, Lanes, MAX_WIDTH};

/// One cell's entries as columns, padded by [`MAX_WIDTH`] so that a step past the last entry
/// reads inside the arrays (its lanes are masked off). Kept between cells and frames.
#[derive(Debug, Default)]
pub(in crate::engines::grid) struct Columns {
    /// Each entry's AABB: `min` per axis, then `max` per axis.
    bounds: [Vec<f64>; 6],
    /// Each entry's box in the high half of a 64-bit pair, as `[first, id]` is laid out.
    ids: Vec<u64>,
    /// Each entry's class.
    class: Vec<u64>,
}

/// The columns' values as slices, taken once per scan: read through the Vecs, each value's
/// address would be loaded again after every store of pairs (which might alias them).
struct Cell<'a> {
    bounds: [&'a mut [f64]; 6],
    ids: &'a mut [u64],
    class: &'a mut [u64],
}

impl Columns {
    /// Room for cells of `len` entries, as slices.
    fn cell(&mut self, len: usize) -> Cell<'_> {
        let len = len + MAX_WIDTH;
        if self.ids.len() < len {
            for column in &mut self.bounds {
                column.resize(len, 0.0);
            }
            self.ids.resize(len, 0);
            self.class.resize(len, 0);
        }
        let [b0, b1, b2, b3, b4, b5] = &mut self.bounds;
        Cell {
            bounds: [b0, b1, b2, b3, b4, b5].map(|b| &mut b[..]),
            ids: &mut self.ids,
            class: &mut self.class,
        }
    }
}

impl Cell<'_> {
    /// The entries `entries` (with their keys) as columns. Each column is cut to the cell's
    /// length first, so that no store checks its index.
    #[inline(always)]
    fn fill(&mut self, keys: &[u64], entries: &[u32], boxes: &Frame, class_mask: u64) {
        let n = entries.len();
        let (keys, ids, class) = (&keys[..n], &mut self.ids[..n], &mut self.class[..n]);
        let [x0, y0, z0, x1, y1, z1] = &mut self.bounds;
        let bounds = [x0, y0, z0, x1, y1, z1].map(|b| &mut b[..n]);
        for e in 0..n {
            let aabb = &boxes.aabbs[entries[e] as usize];
            for axis in 0..3 {
                bounds[axis][e] = aabb.min[axis];
                bounds[3 + axis][e] = aabb.max[axis];
            }
            ids[e] = u64::from(entries[e]) << 32;
            class[e] = keys[e] & class_mask;
        }
    }
}

compile_for_each_isa!(scan_cells(
    cells: &Cells,
    runs: &[(u32, u32)],
    boxes: &Frame,
    out: &mut Vec<Pair>,
    columns: &mut Columns,
) -> Counters);

/// [`super::scan_cells`] for a mask told apart by ranks alone (not `Ranks::pairwise`), `W`
/// later entries a step.
#[inline(always)]
fn scan_cells<I: Isa<W>, const W: usize>(
    isa: I,
    cells: &Cells,
    runs: &[(u32, u32)],
    boxes: &Frame,
    out: &mut Vec<Pair>,
    columns: &mut Columns,
) -> Counters {
    debug_assert!(!cells.ranks.pairwise);
    let class_mask = cells.ranks.class_mask();
    let mut emit = Emitter::new(out);
    let longest = runs.iter().map(|&(s, e)| (e - s) as usize).max();
    let mut cell = columns.cell(longest.unwrap_or(0));
    for &(s, e) in runs {
        let (s, e) = (s as usize, e as usize);
        let (keys, entries) = (&cells.keys[s..e], &cells.entries[s..e]);
        let n = entries.len();
        cell.fill(keys, entries, boxes, class_mask);
        // Each step stores `W` pairs whole, of which those kept come first.
        emit.reserve(n * (n - 1) / 2 + W);
        let (bounds, ids, class) = (&cell.bounds, &*cell.ids, &*cell.class);
        let (out, mut kept) = (emit.out.as_mut_ptr(), emit.kept);
        for p in 0..n {
            let wanted = isa.splat_u64(cells.wanted[class[p] as usize]);
            let first = isa.splat_u64(u64::from(entries[p]));
            let mut own = [isa.splat(0.0); 6];
            for (own, column) in own.iter_mut().zip(bounds) {
                *own = isa.splat(column[p]);
            }
            let mut visits = 0;
            for q in (p + 1..n).step_by(W) {
                // SAFETY: the columns hold `n + MAX_WIDTH` values, so the `W` from `q < n` are
                // inside them; the store writes `W` pairs at `kept`, and `reserve` made room
                // for every pair of the cell and `W` more.
                unsafe {
                    // Wanted: bit `class[q]` of this entry's row of `Cells::wanted`.
                    let their = isa.load_u64(class.as_ptr().add(q));
                    let want = isa.bit(wanted, their) & isa.first(n - q);
                    // Overlapping on every axis: the other's min at most this max, and this
                    // min at most the other's max, as `overlaps` compares (false on NaN). (No
                    // closure for the loads: it would be compiled without the instruction set.)
                    let mut keep = want;
                    for axis in 0..3 {
                        let (min, max) = (bounds[axis].as_ptr(), bounds[3 + axis].as_ptr());
                        keep = keep & isa.load(min.add(q)).le(own[3 + axis]);
                        keep = keep & own[axis].le(isa.load(max.add(q)));
                    }
                    let (want, keep) = (want.bits(), keep.bits());
                    visits += want.count_ones();
                    let pairs = first | isa.load_u64(ids.as_ptr().add(q));
                    isa.compress_store(keep, pairs, out.add(kept).cast());
                    kept += keep.count_ones() as usize;
                }
            }
            emit.counters.visits += u64::from(visits);
        }
        emit.kept = kept;
    }
    emit.finish(boxes)
}
