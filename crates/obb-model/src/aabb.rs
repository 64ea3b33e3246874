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

/// The smallest positive f64 (2^-1074, subnormal): the absolute error a product may lose when
/// it underflows is half of it.
pub const TINY: f64 = f64::from_bits(1);

/// Added to every AABB half-extent: it covers what the three products of `e_x` lose when they
/// underflow (at most 2^-1075 each), which the relative widening does not (docs/sat.md, "AABBs").
pub(crate) const EXTENT_FLOOR: f64 = 4.0 * TINY;

/// `d` moved outward (`dir` -1 down, +1 up) by `2u·|d|`, which is at least one ulp of `d`, so
/// that the result lies beyond the exact value that `d` rounds; `+ 0.0` turns -0.0 into +0.0.
/// Unlike `next_down`/`next_up` it has no branch on the sign, which is unpredictable for
/// coordinates around the origin (docs/sat.md, "AABBs").
#[inline(always)]
fn outward(d: f64, dir: f64) -> f64 {
    d + dir * (d.abs() * (2.0 * U)) + 0.0
}

impl Aabb {
    /// The AABB of an OBB: per world axis x, `e_x = Σ_k half_k |axes_k,x|` is the exact half-extent
    /// of the box's projection, whatever the axes (they need not be orthonormal). The computed sum
    /// has relative error at most γ₃ < 4u, plus 2^-1075 per product that underflows; scaling by
    /// (1 + 8u), adding `EXTENT_FLOOR` and stepping the end points one ulp outward makes the
    /// stored bounds contain the exact ones (docs/sat.md, "AABBs").
    pub fn of(obb: &Obb) -> Aabb {
        let mut min = [0.0; 3];
        let mut max = [0.0; 3];
        for x in 0..3 {
            let e = obb.half[0] * obb.axes[0][x].abs()
                + obb.half[1] * obb.axes[1][x].abs()
                + obb.half[2] * obb.axes[2][x].abs();
            let e = e * (1.0 + 8.0 * U) + EXTENT_FLOOR;
            // `+ 0.0` turns -0.0 into +0.0, so that sorting by total order (which puts -0.0
            // first) agrees with `<=` on touching end points.
            min[x] = outward(obb.center[x] - e, -1.0);
            max[x] = outward(obb.center[x] + e, 1.0);
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

    /// The empty box: the identity of `union`.
    pub const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    /// The smallest box holding all of `aabbs` (`EMPTY` for none): four unions side by side,
    /// so that each waits on the one four boxes back rather than on the last.
    pub fn union_of(aabbs: &[Aabb]) -> Aabb {
        let mut acc = [Aabb::EMPTY; 4];
        let quads = aabbs.chunks_exact(4);
        let rest = quads.remainder();
        for quad in quads {
            for (acc, b) in acc.iter_mut().zip(quad) {
                *acc = acc.union(b);
            }
        }
        let all = rest.iter().fold(acc[0].union(&acc[1]), |u, b| u.union(b));
        all.union(&acc[2].union(&acc[3]))
    }

    /// The smallest box holding both. Plain compares rather than `f64::min`, whose NaN handling
    /// costs two more instructions on the chain of a fold over every box (validated boxes hold
    /// no NaN).
    #[inline]
    pub fn union(&self, other: &Aabb) -> Aabb {
        let lo = |a: f64, b: f64| if b < a { b } else { a };
        let hi = |a: f64, b: f64| if b > a { b } else { a };
        Aabb {
            min: std::array::from_fn(|x| lo(self.min[x], other.min[x])),
            max: std::array::from_fn(|x| hi(self.max[x], other.max[x])),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{outward, Aabb};
    use proptest::prelude::*;

    proptest! {
        /// The branch-free outward step is at least the one-ulp step it replaces, for every
        /// finite value, so the stored bounds still contain the exact ones (docs/sat.md).
        #[test]
        fn outward_steps_at_least_one_ulp(bits in any::<u64>()) {
            let d = f64::from_bits(bits);
            prop_assume!(d.is_finite() && d.abs() <= 1e300);
            let (down, up) = (outward(d, -1.0), outward(d, 1.0));
            prop_assert!(down <= d.next_down() || (d.abs() < f64::MIN_POSITIVE && down <= d));
            prop_assert!(up >= d.next_up() || (d.abs() < f64::MIN_POSITIVE && up >= d));
            prop_assert!(down.to_bits() != (-0.0f64).to_bits() && up.to_bits() != (-0.0f64).to_bits());
        }
    }

    #[test]
    fn union_of_is_the_fold_of_unions() {
        let boxes: Vec<Aabb> = (0..9)
            .map(|k| {
                let c = [k as f64 * 1.5 - 6.0, (k * k % 7) as f64, -(k as f64)];
                Aabb {
                    min: c.map(|x| x - 0.5),
                    max: c.map(|x| x + 0.25 * k as f64),
                }
            })
            .collect();
        for n in 0..=boxes.len() {
            let fold = boxes[..n].iter().fold(Aabb::EMPTY, |u, b| u.union(b));
            assert_eq!(Aabb::union_of(&boxes[..n]), fold, "{n} boxes");
        }
    }

    #[test]
    fn outward_at_binade_edges() {
        for k in [-1000, -60, -1, 0, 1, 52, 60] {
            let p = 2f64.powi(k);
            for d in [
                p,
                -p,
                p.next_down(),
                -p.next_down(),
                p.next_up(),
                -p.next_up(),
            ] {
                assert!(outward(d, -1.0) <= d.next_down(), "{d:e}");
                assert!(outward(d, 1.0) >= d.next_up(), "{d:e}");
            }
        }
    }
}
