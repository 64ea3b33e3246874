//! Axis-aligned bounds of an OBB, rounded outward so that they contain the box exactly.

use crate::scene::Obb;

/// A closed axis-aligned box `[min, max]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// Unit roundoff of f64 (2^-53).
pub const U: f64 = f64::EPSILON / 2.0;

impl Aabb {
    /// The AABB of an OBB: per world axis x, `e_x = Σ_k half_k |axes_k,x|` is the exact half-extent
    /// of the box's projection, whatever the axes (they need not be orthonormal). The computed sum
    /// has relative error at most γ₃ < 4u; scaling by (1 + 8u) and stepping the end points one ulp
    /// outward makes the stored bounds contain the exact ones (docs/sat.md, "AABBs").
    pub fn of(obb: &Obb) -> Aabb {
        let mut min = [0.0; 3];
        let mut max = [0.0; 3];
        for x in 0..3 {
            let e = obb.half[0] * obb.axes[0][x].abs()
                + obb.half[1] * obb.axes[1][x].abs()
                + obb.half[2] * obb.axes[2][x].abs();
            let e = e * (1.0 + 8.0 * U);
            // `+ 0.0` turns -0.0 into +0.0, so that sorting by total order (which puts -0.0
            // first) agrees with `<=` on touching end points.
            min[x] = (obb.center[x] - e).next_down() + 0.0;
            max[x] = (obb.center[x] + e).next_up() + 0.0;
        }
        Aabb { min, max }
    }

    /// Closed-interval overlap on world axis `x`: touching counts.
    #[inline]
    pub fn overlaps_on(&self, other: &Aabb, x: usize) -> bool {
        self.min[x] <= other.max[x] && other.min[x] <= self.max[x]
    }

    /// Closed-interval overlap on all three axes.
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.overlaps_on(other, 0) && self.overlaps_on(other, 1) && self.overlaps_on(other, 2)
    }
}
