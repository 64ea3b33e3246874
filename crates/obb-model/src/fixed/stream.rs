//! The order the host streams a frame's boxes in. The core takes the boxes in the order they
//! come and reports a pair by the boxes' places in the stream, so the order is the host's to
//! choose, and it sets the grid's clocks: a box's walk runs at most `cycles::GRID_CREDITS`
//! boxes behind its load, so a run of boxes that each meet many others (a jaw in the tissue,
//! whose boxes follow each other in the scene) holds the load while the walker catches up, and
//! the rest of the frame loads with the walker idle. Interleaved (box 0, `ways`, 2 `ways`, ...,
//! then box 1, 1 + `ways`, ...) such a run is spread over the whole stream, and the walk
//! overlaps the load.

use crate::scene::Scene;

/// Ways of the interleave the host uses for haptic frames (`obbcd cosim --interleave`). On the
/// surgical scene's instruments (7,500 boxes, runs of up to some hundreds that meet the tissue)
/// 16 and 64 ways give haptic frames within 1% of each other and 256 ways some 5% more
/// (README, "Resident tissue").
pub const STREAM_WAYS: usize = 16;

/// The stream order of `n` boxes in `ways` ways (1, or 0: the scene's order): the k-th box streamed
/// is box `order[k]` of the scene, so a pair the core reports as (`kept` + k, ...) in a haptic
/// frame that follows `kept` resident boxes is the scene's box `order[k]`.
pub fn interleaved(n: usize, ways: usize) -> Vec<usize> {
    let ways = ways.max(1);
    (0..ways).flat_map(|w| (w..n).step_by(ways)).collect()
}

/// `scene`'s boxes in the order `interleaved` gives them.
pub fn interleave(scene: &Scene, ways: usize) -> Scene {
    Scene {
        obbs: interleaved(scene.obbs.len(), ways)
            .into_iter()
            .map(|i| scene.obbs[i].clone())
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::interleaved;

    #[test]
    fn interleaved_is_a_permutation_in_ways() {
        assert_eq!(interleaved(7, 3), [0, 3, 6, 1, 4, 2, 5]);
        assert_eq!(interleaved(4, 1), [0, 1, 2, 3]);
        assert_eq!(interleaved(2, 16), [0, 1]);
        assert!(interleaved(0, 16).is_empty());
        let mut all = interleaved(1000, 16);
        all.sort_unstable();
        assert_eq!(all, (0..1000).collect::<Vec<_>>());
    }
}
