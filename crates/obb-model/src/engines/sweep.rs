//! Sort-and-sweep on one axis: the min end points sorted on the axis that emits the fewest
//! visits; for each box i, walk j while min_j <= max_i, filter on the other two axes.

use super::{ordered, Counters, Engine, EngineKind, Pair, PairSorter};
use crate::groups::GroupMask;
use crate::prepared::Frame;

#[derive(Debug, Default)]
pub struct Sweep {
    /// (min on the axis, box index), sorted.
    order: [Vec<(f64, u32)>; 3],
    sorter: PairSorter,
}

impl Sweep {
    fn sort_axis(&mut self, boxes: &Frame, axis: usize) {
        let order = &mut self.order[axis];
        order.clear();
        order.extend(
            boxes
                .aabbs
                .iter()
                .enumerate()
                .map(|(i, b)| (b.min[axis], i as u32)),
        );
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    }

    /// The exact number of pairs a sweep on `axis` walks: for each box, the mins after its own
    /// position that are <= its max.
    fn walk_count(&self, boxes: &Frame, axis: usize) -> u64 {
        let order = &self.order[axis];
        order
            .iter()
            .enumerate()
            .map(|(p, &(_, i))| {
                let max = boxes.aabbs[i as usize].max[axis];
                let end = p + 1 + order[p + 1..].partition_point(|&(m, _)| m <= max);
                (end - p - 1) as u64
            })
            .sum()
    }

    /// The axis the sweep uses for these boxes: the one with the fewest walked pairs.
    pub fn choose_axis(&mut self, boxes: &Frame) -> usize {
        for axis in 0..3 {
            self.sort_axis(boxes, axis);
        }
        (0..3)
            .min_by_key(|&axis| self.walk_count(boxes, axis))
            .expect("three axes")
    }
}

impl Engine for Sweep {
    fn kind(&self) -> EngineKind {
        EngineKind::Sweep
    }

    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        let axis = self.choose_axis(boxes);
        let (o1, o2) = ((axis + 1) % 3, (axis + 2) % 3);
        let order = &self.order[axis];
        let mut c = Counters::default();
        out.clear();
        for (p, &(_, i)) in order.iter().enumerate() {
            let (i, bi) = (i as usize, &boxes.aabbs[i as usize]);
            for &(min_j, j) in &order[p + 1..] {
                if min_j > bi.max[axis] {
                    break;
                }
                let j = j as usize;
                if !mask.allows(boxes.groups[i], boxes.groups[j]) {
                    continue;
                }
                c.visits += 1;
                let bj = &boxes.aabbs[j];
                if bi.overlaps_on(bj, o1) && bi.overlaps_on(bj, o2) {
                    c.sat_tests += 1;
                    if boxes.collide(i, j) {
                        out.push(ordered(i as u32, j as u32));
                    }
                }
            }
        }
        self.sorter.sort_dedup(out, boxes.len());
        c.pairs = out.len() as u64;
        c
    }
}
