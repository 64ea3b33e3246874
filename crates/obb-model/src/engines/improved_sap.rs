//! The paper's Algorithm 2 as written: on each axis independently, every box whose endpoint lies
//! between an OBB's min and its max endpoint is sent to the SAT. A pair can be sent up to six
//! times (two endpoints on each of three axes); duplicates are removed from the final result
//! only, and `sat` counts every call.

use super::endpoints::{sorted_endpoints, Endpoint};
use super::{ordered, Counters, Engine, EngineKind, Pair, PairSorter};
use crate::groups::GroupMask;
use crate::prepared::Frame;

#[derive(Debug, Default)]
pub struct ImprovedSap {
    endpoints: Vec<Endpoint>,
    sorter: PairSorter,
}

impl Engine for ImprovedSap {
    fn kind(&self) -> EngineKind {
        EngineKind::ImprovedSap
    }

    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        let mut c = Counters::default();
        out.clear();
        for axis in 0..3 {
            sorted_endpoints(boxes, axis, &mut self.endpoints);
            for (p, e) in self.endpoints.iter().enumerate() {
                if e.is_max {
                    continue;
                }
                let i = e.index as usize;
                // Walk to this box's own max endpoint; every index met goes to the SAT.
                for other in &self.endpoints[p + 1..] {
                    let j = other.index as usize;
                    if j == i {
                        break;
                    }
                    if !mask.allows(boxes.groups[i], boxes.groups[j]) {
                        continue;
                    }
                    c.visits += 1;
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
