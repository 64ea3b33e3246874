//! All pairs: the reference every other engine is tested against.

use super::{Counters, Engine, EngineKind, Pair};
use crate::groups::GroupMask;
use crate::prepared::Frame;

#[derive(Debug, Default)]
pub struct Brute;

impl Engine for Brute {
    fn kind(&self) -> EngineKind {
        EngineKind::Brute
    }

    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters {
        out.clear();
        let mut c = Counters::default();
        let n = boxes.len();
        for i in 0..n {
            for j in i + 1..n {
                if !mask.allows(boxes.groups[i], boxes.groups[j]) {
                    continue;
                }
                c.visits += 1;
                c.sat_tests += 1;
                if boxes.collide(i, j) {
                    out.push([i as u32, j as u32]);
                }
            }
        }
        c.pairs = out.len() as u64;
        c
    }
}
