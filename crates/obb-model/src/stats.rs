//! Scene statistics: per-axis AABB overlap counts, the work of each broad phase, and collisions,
//! for all pairs and for each group pair.

use crate::engines::endpoints::count_axis_overlaps;
use crate::engines::{Counters, EngineKind};
use crate::groups::GroupMask;
use crate::prepared::Frame;
use std::collections::BTreeSet;

/// The broad phases compared in a stats row (brute's work is simply the number of pairs).
pub const STATS_ENGINES: [EngineKind; 4] = [
    EngineKind::Sap,
    EngineKind::ImprovedSap,
    EngineKind::Sweep,
    EngineKind::Grid,
];

/// One row: a set of box pairs (all, or one group pair) and what each engine does on it.
#[derive(Clone, Debug, PartialEq)]
pub struct StatsRow {
    pub mask: GroupMask,
    /// Box pairs in the set.
    pub pairs: u64,
    /// Pairs whose AABBs overlap on x, on y, on z.
    pub overlap: [u64; 3],
    /// Pairs whose AABBs overlap on all three axes.
    pub overlap_xyz: u64,
    /// Counters of each engine in `STATS_ENGINES`, in that order.
    pub engines: Vec<(EngineKind, Counters)>,
    /// Colliding pairs.
    pub collisions: u64,
}

/// Rows for all pairs, then for each group pair present in the scene.
pub fn scene_stats(boxes: &Frame) -> Vec<StatsRow> {
    let groups: BTreeSet<u32> = boxes.groups.iter().copied().collect();
    let size = |g: u32| boxes.groups.iter().filter(|&&x| x == g).count() as u64;
    let n = boxes.len() as u64;
    let mut masks = vec![(GroupMask::All, n * n.saturating_sub(1) / 2)];
    for &g in &groups {
        for &h in groups.range(g..) {
            let pairs = if g == h {
                size(g) * size(g).saturating_sub(1) / 2
            } else {
                size(g) * size(h)
            };
            masks.push((GroupMask::Pairs(vec![(g, h)]), pairs));
        }
    }
    let overlaps: [Vec<(GroupMask, u64)>; 3] =
        std::array::from_fn(|axis| count_axis_overlaps(boxes, axis, &masks));
    masks
        .into_iter()
        .enumerate()
        .map(|(row, (mask, pairs))| {
            let engines: Vec<(EngineKind, Counters)> = STATS_ENGINES
                .iter()
                .map(|&kind| {
                    let mut out = Vec::new();
                    (kind, kind.build().detect(boxes, &mask, &mut out))
                })
                .collect();
            let sap = engines[0].1;
            StatsRow {
                overlap: std::array::from_fn(|axis| overlaps[axis][row].1),
                overlap_xyz: sap.sat_tests,
                collisions: sap.pairs,
                engines,
                mask,
                pairs,
            }
        })
        .collect()
}
