//! Sorted entries as columns, as the vector scans read them `W` at a time (the regular layout's
//! `scan::vector`, the corner layout's `scan::corner`): each AABB bound in an array of its own,
//! `min` per axis then `max` per axis, and each entry's box in the high half of a u64, as a
//! pair `[first, id]` is laid out. The arrays are padded by `MAX_WIDTH`, so that a step past
//! the last entry reads inside them (its lanes are masked off).

use crate::aabb::Aabb;
use crate::simd::MAX_WIDTH;

/// The columns' arrays, kept between frames. They only grow.
#[derive(Debug, Default)]
pub(super) struct EntryColumns {
    bounds: [Vec<f64>; 6],
    ids: Vec<u64>,
}

/// The columns as slices, taken once per scan: read through the Vecs, each value's address
/// would be loaded again after every store of pairs (which might alias them).
pub(super) struct ColumnSlices<'a> {
    pub bounds: [&'a mut [f64]; 6],
    pub ids: &'a mut [u64],
}

impl EntryColumns {
    /// Room for `len` entries and the padding, as slices.
    pub fn room(&mut self, len: usize) -> ColumnSlices<'_> {
        let len = len + MAX_WIDTH;
        if self.ids.len() < len {
            for column in &mut self.bounds {
                column.resize(len, 0.0);
            }
            self.ids.resize(len, 0);
        }
        ColumnSlices {
            bounds: self.bounds.each_mut().map(|b| &mut b[..]),
            ids: &mut self.ids,
        }
    }

    /// The bound columns, in the order of `ColumnSlices::bounds`.
    pub fn bounds(&self) -> [&[f64]; 6] {
        self.bounds.each_ref().map(|b| &b[..])
    }

    pub fn ids(&self) -> &[u64] {
        &self.ids
    }
}

impl<'a> ColumnSlices<'a> {
    /// The columns' first `mid` entries, and the rest.
    pub fn split_at(self, mid: usize) -> (ColumnSlices<'a>, ColumnSlices<'a>) {
        let [b0, b1, b2, b3, b4, b5] = self.bounds.map(|b| b.split_at_mut(mid));
        let (ids0, ids1) = self.ids.split_at_mut(mid);
        let first = ColumnSlices {
            bounds: [b0.0, b1.0, b2.0, b3.0, b4.0, b5.0],
            ids: ids0,
        };
        let rest = ColumnSlices {
            bounds: [b0.1, b1.1, b2.1, b3.1, b4.1, b5.1],
            ids: ids1,
        };
        (first, rest)
    }

    /// Writes the AABBs and boxes of `entries` from the start of the columns. Each column is
    /// cut to the entries' count first, so that no store checks its index.
    #[inline(always)]
    pub fn fill(&mut self, entries: &[u32], aabbs: &[Aabb]) {
        let n = entries.len();
        let ids = &mut self.ids[..n];
        let [x0, y0, z0, x1, y1, z1] = &mut self.bounds;
        let (x0, y0, z0) = (&mut x0[..n], &mut y0[..n], &mut z0[..n]);
        let (x1, y1, z1) = (&mut x1[..n], &mut y1[..n], &mut z1[..n]);
        for (p, &e) in entries.iter().enumerate() {
            let b = &aabbs[e as usize];
            (x0[p], y0[p], z0[p]) = (b.min[0], b.min[1], b.min[2]);
            (x1[p], y1[p], z1[p]) = (b.max[0], b.max[1], b.max[2]);
            ids[p] = u64::from(e) << 32;
        }
    }
}
