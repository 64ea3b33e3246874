//! Per-frame preparation shared by every engine: each box's AABB, SAT form and group.

use crate::aabb::Aabb;
use crate::sat::{boxes_collide, SatBox};
use crate::scene::Obb;
use rayon::prelude::*;

/// Boxes below this count are prepared on one thread: below it, waking the pool costs more.
const PARALLEL_MIN: usize = 4096;

/// The boxes of one frame, ready for the broad and narrow phases. Buffers are reused.
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    pub aabbs: Vec<Aabb>,
    pub sat: Vec<SatBox>,
    pub groups: Vec<u32>,
}

impl Prepared {
    pub fn new(obbs: &[Obb]) -> Prepared {
        let mut p = Prepared::default();
        p.update(obbs);
        p
    }

    /// Recomputes everything from `obbs`, keeping the allocations.
    pub fn update(&mut self, obbs: &[Obb]) {
        let n = obbs.len();
        self.aabbs.resize(n, Aabb::default());
        self.sat.resize(n, SatBox::default());
        self.groups.clear();
        self.groups.extend(obbs.iter().map(|o| o.group));
        let one = |((aabb, sat), obb): ((&mut Aabb, &mut SatBox), &Obb)| {
            *aabb = Aabb::of(obb);
            *sat = SatBox::of(obb);
        };
        if n < PARALLEL_MIN {
            self.aabbs
                .iter_mut()
                .zip(self.sat.iter_mut())
                .zip(obbs)
                .for_each(one);
        } else {
            self.aabbs
                .par_iter_mut()
                .zip(self.sat.par_iter_mut())
                .zip(obbs.par_iter())
                .for_each(one);
        }
    }

    pub fn len(&self) -> usize {
        self.aabbs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.aabbs.is_empty()
    }

    /// The narrow phase every engine uses: closed AABB overlap, then the 15-axis SAT. Every
    /// engine reports exactly the pairs for which this is true (and the mask allows).
    #[inline]
    pub fn collide(&self, i: usize, j: usize) -> bool {
        self.aabbs[i].overlaps(&self.aabbs[j]) && boxes_collide(&self.sat[i], &self.sat[j])
    }
}
