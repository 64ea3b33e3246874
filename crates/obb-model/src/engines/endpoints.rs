//! The paper's per-axis endpoint arrays (its SAP steps 1 and 2): min and max of every AABB on one
//! axis, tagged with the box index and a min/max flag, sorted.

use crate::groups::GroupMask;
use crate::prepared::Frame;
use std::collections::HashMap;

#[derive(Clone, Copy, Debug)]
pub(crate) struct Endpoint {
    pub value: f64,
    pub index: u32,
    pub is_max: bool,
}

/// Fills `out` with the 2N endpoints on `axis`, sorted by value; at equal values a min comes
/// before a max (closed intervals: touching boxes overlap), then by box index.
pub(crate) fn sorted_endpoints(boxes: &Frame, axis: usize, out: &mut Vec<Endpoint>) {
    out.clear();
    for (i, b) in boxes.aabbs.iter().enumerate() {
        out.push(Endpoint {
            value: b.min[axis],
            index: i as u32,
            is_max: false,
        });
        out.push(Endpoint {
            value: b.max[axis],
            index: i as u32,
            is_max: true,
        });
    }
    out.sort_unstable_by(|a, b| {
        a.value
            .total_cmp(&b.value)
            .then(a.is_max.cmp(&b.is_max))
            .then(a.index.cmp(&b.index))
    });
}

/// For each mask, the number of pairs it allows whose intervals overlap on `axis` (one sweep
/// over the sorted end points with an active list, as in the paper's SAP step 3).
pub(crate) fn count_axis_overlaps(
    boxes: &Frame,
    axis: usize,
    masks: &[(GroupMask, u64)],
) -> Vec<(GroupMask, u64)> {
    let mut endpoints = Vec::new();
    sorted_endpoints(boxes, axis, &mut endpoints);
    // Pair counts by (group, group) of the active box and the arriving one.
    let mut by_groups: HashMap<(u32, u32), u64> = HashMap::new();
    let mut active: HashMap<u32, u64> = HashMap::new();
    for e in &endpoints {
        let g = boxes.groups[e.index as usize];
        if e.is_max {
            *active.get_mut(&g).expect("a box leaves after it entered") -= 1;
        } else {
            for (&h, &count) in &active {
                *by_groups.entry((g.min(h), g.max(h))).or_default() += count;
            }
            *active.entry(g).or_default() += 1;
        }
    }
    masks
        .iter()
        .map(|(mask, _)| {
            let total = by_groups
                .iter()
                .filter(|((g, h), _)| mask.allows(*g, *h))
                .map(|(_, c)| c)
                .sum();
            (mask.clone(), total)
        })
        .collect()
}
