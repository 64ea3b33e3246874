//! The paper's conventional sweep and prune, its four steps: per-axis endpoint arrays, sort,
//! traversal with an active list, and the search for the pairs common to the three axes.

use super::endpoints::{sorted_endpoints, Endpoint};
use super::{ordered, Counters, Engine, EngineKind, Pair, PairSorter};
use crate::groups::GroupMask;
use crate::prepared::Frame;

#[derive(Debug, Default)]
pub struct Sap {
    endpoints: Vec<Endpoint>,
    active: Vec<u32>,
    /// Position of each box in `active` while it is there.
    slot: Vec<usize>,
    axis_pairs: [Vec<Pair>; 3],
    sorter: PairSorter,
}

impl Sap {
    /// Step 3 on one axis: every pair whose intervals overlap, each once.
    fn traverse(&mut self, boxes: &Frame, mask: &GroupMask, axis: usize) {
        sorted_endpoints(boxes, axis, &mut self.endpoints);
        self.active.clear();
        self.slot.clear();
        self.slot.resize(boxes.len(), 0);
        let pairs = &mut self.axis_pairs[axis];
        pairs.clear();
        for e in &self.endpoints {
            let i = e.index as usize;
            if e.is_max {
                let at = self.slot[i];
                self.active.swap_remove(at);
                if let Some(&moved) = self.active.get(at) {
                    self.slot[moved as usize] = at;
                }
            } else {
                for &k in &self.active {
                    if mask.allows(boxes.groups[i], boxes.groups[k as usize]) {
                        pairs.push(ordered(i as u32, k));
                    }
                }
                self.slot[i] = self.active.len();
                self.active.push(e.index);
            }
        }
    }
}

impl Engine for Sap {
    fn kind(&self) -> EngineKind {
        EngineKind::Sap
    }

    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        let mut c = Counters::default();
        for axis in 0..3 {
            self.traverse(boxes, mask, axis);
            c.visits += self.axis_pairs[axis].len() as u64;
            self.sorter
                .sort_dedup(&mut self.axis_pairs[axis], boxes.len());
        }
        // Step 4: the pairs found on all three axes, by merging the three sorted lists.
        out.clear();
        let [x, y, z] = &self.axis_pairs;
        let (mut iy, mut iz) = (0, 0);
        for p in x {
            while iy < y.len() && y[iy] < *p {
                iy += 1;
            }
            while iz < z.len() && z[iz] < *p {
                iz += 1;
            }
            if y.get(iy) == Some(p) && z.get(iz) == Some(p) {
                c.sat_tests += 1;
                if boxes.collide(p[0] as usize, p[1] as usize) {
                    out.push(*p);
                }
            }
        }
        c.pairs = out.len() as u64;
        c
    }
}
