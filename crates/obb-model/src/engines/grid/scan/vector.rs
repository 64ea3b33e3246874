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

use super::step::ColumnPtrs;
use super::{Cells, Emitter};
use crate::engines::grid::columns::{ColumnSlices, EntryColumns};
use crate::engines::{Counters, Pair};
use crate::prepared::Frame;
use crate::simd::{compile_for_each_isa, Isa, LaneMask};

/// One cell's entries as columns (`EntryColumns`), with each entry's class. Kept between
/// cells and frames.
#[derive(Debug, Default)]
pub(in crate::engines::grid) struct Columns {
    entries: EntryColumns,
    class: Vec<u64>,
}

/// The columns as slices (`ColumnSlices`), taken once per scan.
struct Cell<'a> {
    columns: ColumnSlices<'a>,
    class: &'a mut [u64],
}

impl Columns {
    /// Room for cells of `len` entries, as slices.
    fn cell(&mut self, len: usize) -> Cell<'_> {
        let columns = self.entries.room(len);
        if self.class.len() < columns.ids.len() {
            self.class.resize(columns.ids.len(), 0);
        }
        Cell {
            columns,
            class: &mut self.class,
        }
    }
}

impl Cell<'_> {
    /// The entries `entries` (with their keys) as columns, and their classes.
    #[inline(always)]
    fn fill(&mut self, keys: &[u64], entries: &[u32], boxes: &Frame, class_mask: u64) {
        self.columns.fill(entries, boxes.aabbs);
        let class = &mut self.class[..entries.len()];
        for (class, &k) in class.iter_mut().zip(keys) {
            *class = k & class_mask;
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
        let class = &*cell.class;
        let columns = &cell.columns;
        let columns = ColumnPtrs::new(columns.bounds.each_ref().map(|b| &**b), columns.ids);
        let (out, mut kept) = (emit.out.as_mut_ptr(), emit.kept);
        for p in 0..n {
            let wanted = isa.splat_u64(cells.wanted[class[p] as usize]);
            // SAFETY: `p` is an entry of the cell, inside the columns.
            let own = unsafe { columns.own(isa, p) };
            let mut visits = 0;
            for q in (p + 1..n).step_by(W) {
                // SAFETY: the columns hold `n` entries and their padding, so the `W` from
                // `q < n` are inside them; the step writes `W` pairs at `kept`, and `reserve`
                // made room for every pair of the cell and `W` more.
                unsafe {
                    // Wanted: bit `class[q]` of this entry's row of `Cells::wanted`.
                    let their = isa.load_u64(class.as_ptr().add(q));
                    let want = isa.bit(wanted, their) & isa.first(n - q);
                    visits += want.bits().count_ones();
                    kept += columns.keep(isa, &own, want, q, out.add(kept));
                }
            }
            emit.counters.visits += u64::from(visits);
        }
        emit.kept = kept;
    }
    emit.finish(boxes)
}
