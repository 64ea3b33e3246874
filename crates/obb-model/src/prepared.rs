//! Per-frame preparation shared by every engine: each box's AABB and SAT slack, and its group.

use crate::aabb::Aabb;
use crate::sat::{boxes_collide, Slack};
use crate::scene::Obb;
use rayon::prelude::*;

/// Boxes below this count are prepared on one thread: below it, waking the pool costs more.
const PARALLEL_MIN: usize = 4096;
/// Boxes per parallel task.
const CHUNK: usize = 1024;

/// The per-box buffers of one frame, reused from frame to frame. The boxes themselves are not
/// copied: the SAT reads them from the scene, which keeps the per-frame writes small (they, not
/// the arithmetic, bound this pass).
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    aabbs: Vec<Aabb>,
    slack: Vec<Slack>,
    groups: Vec<u32>,
}

/// One frame's boxes, ready for the broad and narrow phases.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    pub obbs: &'a [Obb],
    pub aabbs: &'a [Aabb],
    pub slack: &'a [Slack],
    pub groups: &'a [u32],
    /// The union of the AABBs (`Aabb::EMPTY` for no boxes).
    pub bounds: Aabb,
}

/// Prepares one run of boxes and returns the union of their AABBs: one read of each box serves
/// every per-box quantity.
fn prepare(obbs: &[Obb], aabbs: &mut [Aabb], slack: &mut [Slack], groups: &mut [u32]) -> Aabb {
    let mut bounds = Aabb::EMPTY;
    for (((obb, aabb), slack), group) in obbs.iter().zip(aabbs).zip(slack).zip(groups) {
        *aabb = Aabb::of(obb);
        *slack = Slack::of(obb);
        *group = obb.group;
        bounds = bounds.union(aabb);
    }
    bounds
}

impl Prepared {
    /// Recomputes everything from `obbs`, keeping the allocations.
    pub fn update<'a>(&'a mut self, obbs: &'a [Obb]) -> Frame<'a> {
        let n = obbs.len();
        self.aabbs.resize(n, Aabb::default());
        self.slack.resize(n, Slack::default());
        self.groups.resize(n, 0);
        let bounds = if n < PARALLEL_MIN {
            prepare(obbs, &mut self.aabbs, &mut self.slack, &mut self.groups)
        } else {
            obbs.par_chunks(CHUNK)
                .zip(self.aabbs.par_chunks_mut(CHUNK))
                .zip(self.slack.par_chunks_mut(CHUNK))
                .zip(self.groups.par_chunks_mut(CHUNK))
                .map(|(((o, a), s), g)| prepare(o, a, s, g))
                .reduce(|| Aabb::EMPTY, |a, b| a.union(&b))
        };
        Frame {
            obbs,
            aabbs: &self.aabbs,
            slack: &self.slack,
            groups: &self.groups,
            bounds,
        }
    }
}

impl Frame<'_> {
    pub fn len(&self) -> usize {
        self.obbs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.obbs.is_empty()
    }

    /// The 15-axis SAT on boxes `i` and `j`, without the AABB check.
    #[inline]
    pub fn sat(&self, i: usize, j: usize) -> bool {
        boxes_collide(&self.obbs[i], &self.slack[i], &self.obbs[j], &self.slack[j])
    }

    /// The narrow phase every engine uses: closed AABB overlap, then the 15-axis SAT. Every
    /// engine reports exactly the pairs for which this is true (and the mask allows).
    #[inline]
    pub fn collide(&self, i: usize, j: usize) -> bool {
        self.aabbs[i].overlaps(&self.aabbs[j]) && self.sat(i, j)
    }
}
