//! The step both vector scans take (`vector`, `corner`): one entry's AABB against `W` entries
//! of the columns (`super::super::columns`), six vector compares, and the pairs whose AABBs
//! overlap compressed in a register and stored whole (the lanes past the kept ones are
//! overwritten by the next step).

use crate::engines::Pair;
use crate::simd::{Isa, LaneMask, Lanes, Mask};

/// The columns' addresses, taken once per scan. (No closures or slices in the steps: a closure
/// would be compiled without the instruction set, and a slice's bounds would be checked.)
#[derive(Clone, Copy)]
pub(super) struct ColumnPtrs {
    bounds: [*const f64; 6],
    ids: *const u64,
}

/// An entry as the steps compare it, each value in every lane: its AABB's bounds, and its box
/// in the low half of a pair.
pub(super) struct Own<I: Isa<W>, const W: usize> {
    bounds: [I::F; 6],
    first: I::U,
}

impl ColumnPtrs {
    pub fn new(bounds: [&[f64]; 6], ids: &[u64]) -> Self {
        ColumnPtrs {
            bounds: bounds.map(<[f64]>::as_ptr),
            ids: ids.as_ptr(),
        }
    }

    /// Entry `p`. SAFETY: `p` must be inside the columns.
    #[inline(always)]
    pub unsafe fn own<I: Isa<W>, const W: usize>(self, isa: I, p: usize) -> Own<I, W> {
        let mut bounds = [isa.splat(0.0); 6];
        for (own, column) in bounds.iter_mut().zip(&self.bounds) {
            *own = isa.splat(*column.add(p));
        }
        Own {
            bounds,
            first: isa.splat_u64(*self.ids.add(p) >> 32),
        }
    }

    /// The pairs of `own` with the entries from `q` on the lanes `lanes` whose AABBs overlap
    /// it, as `overlaps` compares them (false on NaN), stored at `out`; returns how many.
    /// SAFETY: the `W` entries from `q` must be inside the columns (with their padding), and
    /// `W` pairs from `out` writable.
    #[inline(always)]
    pub unsafe fn keep<I: Isa<W>, const W: usize>(
        self,
        isa: I,
        own: &Own<I, W>,
        lanes: Mask<I, W>,
        q: usize,
        out: *mut Pair,
    ) -> usize {
        let mut keep = lanes;
        for axis in 0..3 {
            let (min, max) = (self.bounds[axis], self.bounds[3 + axis]);
            keep = keep & isa.load(min.add(q)).le(own.bounds[3 + axis]);
            keep = keep & own.bounds[axis].le(isa.load(max.add(q)));
        }
        let keep = keep.bits();
        let pairs = own.first | isa.load_u64(self.ids.add(q));
        isa.compress_store(keep, pairs, out.cast());
        keep.count_ones() as usize
    }
}
