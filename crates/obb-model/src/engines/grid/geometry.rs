//! Where the cells are: origin, edge and dimensions, and the choice of the edge.

use crate::aabb::Aabb;

/// Cells per axis at most (keys stay below 2^60).
const MAX_CELLS_PER_AXIS: u64 = 1 << 20;
/// The smallest cell edge, the smallest normal f64 (2^-1022): its inverse is finite. Below it
/// (boxes of subnormal size) `1 / cell` would be infinite and every box would cover 2^63 cells.
const MIN_CELL: f64 = f64::MIN_POSITIVE;
/// Cell edge as a multiple of the median AABB edge, for a grid whose cells are scanned pair by
/// pair: the measured sweet spot between entries per box and pairs per cell (docs/engines.md).
pub(super) const CELL_PER_MEDIAN_EDGE: f64 = 5.0;
/// The same when a group probes: larger cells mean fewer entries to enter and sort, and fewer
/// cells for each probing box to look up, while the pairs examined grow more slowly.
pub(super) const PROBING_CELL_PER_MEDIAN_EDGE: f64 = 4.0;
/// The same for the resident grid, which only moving boxes probe (`Resident`): a haptic frame
/// enters and sorts nothing, and each moving box meets every entry of the cells it covers, so
/// smaller cells pay.
pub(super) const RESIDENT_CELL_PER_MEDIAN_EDGE: f64 = 3.0;
/// The median edge is taken over at most this many boxes, evenly spaced in the scene.
const CELL_SAMPLE: usize = 4096;

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
    /// of any point inside it. Through i64: the conversion to u64 costs twice as much, and a cell
    /// coordinate is below 2^21 (a point below the origin would give 0 either way).
    #[inline]
    pub(super) fn coord(&self, x: f64, axis: usize) -> u64 {
        (((x - self.origin[axis]) * self.inv) as i64).max(0) as u64
    }

    /// The cell ranges `(first, last)` of `b` on each axis.
    #[inline]
    pub(super) fn range(&self, b: &Aabb) -> ([u64; 3], [u64; 3]) {
        (
            [
                self.coord(b.min[0], 0),
                self.coord(b.min[1], 1),
                self.coord(b.min[2], 2),
            ],
            [
                self.coord(b.max[0], 0),
                self.coord(b.max[1], 1),
                self.coord(b.max[2], 2),
            ],
        )
    }

    /// [`GridGeometry::range`] with the six coordinates in one AVX-512 vector: one subtraction,
    /// one product and one conversion where `range` takes six of each with their saturation
    /// checks (two fifths of the entering's time). Each lane rounds as `coord` does; a lane
    /// below the origin or NaN is 0 in both (the lane's `max` with 0 gives 0 for those), and the
    /// two differ only for a coordinate past 2^63, far beyond the grid's 2^20 cells an axis.
    #[cfg(target_arch = "x86_64")]
    #[inline]
    #[target_feature(enable = "avx512f,avx512dq,avx512vl")]
    pub(super) fn range_avx512(&self, b: &Aabb) -> ([u64; 3], [u64; 3]) {
        use std::arch::x86_64::*;
        let o = &self.origin;
        let origin = _mm512_setr_pd(o[0], o[1], o[2], 0.0, o[0], o[1], o[2], 0.0);
        // SAFETY: each load reads the three f64 of one array (the fourth lane is masked off).
        let (min, max) = unsafe {
            (
                _mm256_maskz_loadu_pd(0b111, b.min.as_ptr()),
                _mm256_maskz_loadu_pd(0b111, b.max.as_ptr()),
            )
        };
        let x = _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(min), max);
        let scaled = _mm512_mul_pd(_mm512_sub_pd(x, origin), _mm512_set1_pd(self.inv));
        let cells = _mm512_cvttpd_epi64(_mm512_max_pd(scaled, _mm512_setzero_pd()));
        let mut c = [0u64; 8];
        // SAFETY: `c` holds the eight lanes.
        unsafe { _mm512_storeu_si512(c.as_mut_ptr().cast(), cells) };
        ([c[0], c[1], c[2]], [c[4], c[5], c[6]])
    }

    /// [`GridGeometry::range`] in two AVX2 vectors, one for `min` and one for `max`: one
    /// subtraction, one product and one conversion each where `range` takes three of each with
    /// their saturation checks. Each lane rounds as `coord` does; a lane below the origin or NaN
    /// is 0 in both (the lane's `max` with 0 gives 0 for those). The conversion is to 32 bits,
    /// so a lane is first clamped to `i32::MAX`: the two differ only for a coordinate past
    /// 2^31 cells, far beyond the grid's 2^20 cells an axis. (The entering, which uses it, only
    /// meets boxes inside the bounds the grid was fit to.)
    #[cfg(target_arch = "x86_64")]
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn range_avx2(&self, b: &Aabb) -> ([u64; 3], [u64; 3]) {
        use std::arch::x86_64::*;
        let o = &self.origin;
        let origin = _mm256_setr_pd(o[0], o[1], o[2], 0.0);
        let (inv, zero) = (_mm256_set1_pd(self.inv), _mm256_setzero_pd());
        let top = _mm256_set1_pd(f64::from(i32::MAX));
        let three = _mm256_setr_epi64x(-1, -1, -1, 0);
        let mut c = [0i32; 8];
        for (end, out) in [&b.min, &b.max].into_iter().zip(c.chunks_exact_mut(4)) {
            // SAFETY: the load reads the three f64 of `end` (the fourth lane is masked off);
            // the store writes the four i32 of `out`.
            unsafe {
                let x = _mm256_maskload_pd(end.as_ptr(), three);
                let scaled = _mm256_mul_pd(_mm256_sub_pd(x, origin), inv);
                let clamped = _mm256_min_pd(_mm256_max_pd(scaled, zero), top);
                _mm_storeu_si128(out.as_mut_ptr().cast(), _mm256_cvttpd_epi32(clamped));
            }
        }
        let cell = |k: usize| c[k] as u64;
        ([cell(0), cell(1), cell(2)], [cell(4), cell(5), cell(6)])
    }

    /// Cells in the range `c0..=c1` (from `range`).
    #[inline]
    pub(super) fn cells_in(c0: [u64; 3], c1: [u64; 3]) -> u64 {
        (c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1)
    }

    #[inline]
    pub(super) fn key(&self, c: [u64; 3]) -> u64 {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// Sets origin and dims for cells of edge `cell` over `lo..=hi`, enlarging the cell when the
    /// extent would need more than `MAX_CELLS_PER_AXIS` cells, or when it is below `MIN_CELL`.
    pub(super) fn fit(lo: [f64; 3], hi: [f64; 3], cell: f64) -> GridGeometry {
        let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
        let cell = cell
            .max(extent / (MAX_CELLS_PER_AXIS - 2) as f64)
            .max(MIN_CELL);
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

/// Cell edge from the boxes: `factor` (one of the `*_CELL_PER_MEDIAN_EDGE`) times the median of
/// each AABB's mean edge, over an evenly spaced sample of at most `CELL_SAMPLE` boxes.
pub(super) fn choose_cell(aabbs: &[Aabb], factor: f64, scratch: &mut Vec<f64>) -> f64 {
    scratch.clear();
    scratch.extend(
        aabbs
            .iter()
            .step_by(aabbs.len().div_ceil(CELL_SAMPLE).max(1))
            .map(|b| ((b.max[0] - b.min[0]) + (b.max[1] - b.min[1]) + (b.max[2] - b.min[2])) / 3.0),
    );
    let mid = scratch.len() / 2;
    let (_, median, _) = scratch.select_nth_unstable_by(mid, f64::total_cmp);
    let cell = *median * factor;
    // Boxes of zero size give a zero median: any positive cell is then correct.
    if cell > 0.0 && cell.is_finite() {
        cell
    } else {
        1.0
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A coordinate in cells from the origin: inside the grid, below the origin, far past it
    /// (up to 2^31 cells, and up to 2^62), or not a number.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            4 => -3.0..40.0f64,
            1 => -1e300..-1.0f64,
            1 => 40.0..2.1e9f64,
            1 => 40.0..4e18f64,
            1 => Just(f64::NAN),
            1 => Just(f64::NEG_INFINITY),
        ]
    }

    proptest! {
        /// The vector cell ranges are the scalar one, lane by lane, wherever they are meant to
        /// agree (every coordinate below 2^63 cells for AVX-512, below 2^31 for AVX2), including
        /// points below the origin and NaN.
        #[test]
        fn vector_range_is_the_scalar_range(
            cells in proptest::array::uniform6(coordinate()),
            origin in proptest::array::uniform3(-1e3..1e3f64),
            cell in 1e-3..1e3f64,
        ) {
            let g = GridGeometry { origin, cell, inv: 1.0 / cell, dims: [40; 3] };
            let at = |k: usize| origin[k % 3] + cells[k] * cell;
            let b = Aabb { min: [at(0), at(1), at(2)], max: [at(3), at(4), at(5)] };
            let scalar = g.range(&b);
            if is_x86_feature_detected!("avx512f")
                && is_x86_feature_detected!("avx512dq")
                && is_x86_feature_detected!("avx512vl")
            {
                // SAFETY: checked above that this CPU has the features.
                prop_assert_eq!(unsafe { g.range_avx512(&b) }, scalar);
            }
            // The 32-bit form agrees below 2^31 cells.
            let in_i32 = scalar.0.iter().chain(&scalar.1).all(|&c| c < i32::MAX as u64);
            if is_x86_feature_detected!("avx2") && in_i32 {
                // SAFETY: checked above that this CPU has the feature.
                prop_assert_eq!(unsafe { g.range_avx2(&b) }, scalar);
            }
        }
    }
}
