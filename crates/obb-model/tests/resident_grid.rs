//! The CPU engine's resident grid (static boxes entered once, moving boxes probing each frame)
//! finds brute force's pairs on the scene "static boxes, then moving boxes", frame after frame.

use obb_model::engines::Resident;
use obb_model::generate::SurgicalMotion;
use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared};

fn brute(scene: &[Obb], mask: &GroupMask) -> Vec<[u32; 2]> {
    let mut prepared = Prepared::default();
    let frame = prepared.update(scene);
    detect(EngineKind::Brute, &frame, mask).0
}

/// Each frame's pairs against brute force, the static boxes replaced on every tissue update.
fn check(
    statics_and_moving: impl Iterator<Item = (Option<Vec<Obb>>, Vec<Obb>)>,
    mask: &GroupMask,
) -> usize {
    let mut resident = Resident::default();
    let mut statics = Vec::new();
    let mut pairs = Vec::new();
    let mut found = 0;
    for (k, (new_statics, moving)) in statics_and_moving.enumerate() {
        if let Some(s) = new_statics {
            statics = s;
            resident.update_static(&statics, mask);
        }
        let counters = resident.detect(&moving, &mut pairs);
        let want = brute(&[statics.clone(), moving].concat(), mask);
        assert_eq!(pairs, want, "frame {k}, mask {mask}");
        assert_eq!(counters.pairs, want.len() as u64);
        found += want.len();
    }
    found
}

#[test]
fn the_moving_surgical_scene_frame_by_frame() {
    let motion = SurgicalMotion::new(700, 3).unwrap();
    for mask in ["cross", "all", "0-1", "1-2"] {
        let mask: GroupMask = mask.parse().unwrap();
        let frames = (0..2000).step_by(20).map(|k| {
            let f = motion.frame(k);
            let (tissue, moving): (Vec<Obb>, Vec<Obb>) =
                f.obbs.into_iter().partition(|b| b.group == 0);
            (f.replace.contains(&0).then_some(tissue), moving)
        });
        assert!(check(frames, &mask) > 0, "{mask}: some pairs");
    }
}

/// A static box and a moving box each too large for the cells, boxes outside the static
/// grid's bounds, no moving boxes, and no static boxes.
#[test]
fn large_boxes_far_boxes_and_empty_sides() {
    let small = |x: f64, group: u32| Obb::aligned([x, 0.0, 0.0], [0.5, 0.5, 0.5], group);
    let statics: Vec<Obb> = (0..50)
        .map(|k| small(k as f64 * 0.8, 0))
        .chain([Obb::aligned([20.0, 0.0, 0.0], [30.0, 0.2, 0.2], 0)])
        .collect();
    let moving = vec![
        small(3.1, 1),
        small(-40.0, 1),
        Obb::aligned([10.0, 0.0, 0.3], [25.0, 0.1, 0.4], 2),
        small(200.0, 2),
    ];
    for mask in [GroupMask::Cross, GroupMask::All] {
        let frames = [
            (Some(statics.clone()), moving.clone()),
            (None, Vec::new()),
            (Some(Vec::new()), moving.clone()),
            (Some(statics.clone()), moving.clone()),
        ];
        assert!(check(frames.into_iter(), &mask) > 0);
    }
}

/// Static boxes spread thinly over a wide space: the grid has more cells than an occupancy
/// bitmap is kept for (2^25), so cells are found by a binary search; the same pairs.
#[test]
fn sparse_statics_over_a_wide_grid() {
    let statics: Vec<Obb> = (0..60)
        .map(|k| {
            let t = k as f64 * 17.0;
            Obb::aligned([t, 0.5 * t, 1000.0 - t], [0.05, 0.05, 0.05], 0)
        })
        .collect();
    let moving: Vec<Obb> = (0..60)
        .map(|k| {
            let t = k as f64 * 17.0 + 0.06 * (k % 3) as f64;
            Obb::aligned([t, 0.5 * t, 1000.0 - t], [0.04, 0.04, 0.04], 1 + k % 2)
        })
        .collect();
    for mask in [GroupMask::Cross, GroupMask::All] {
        let frames = [(Some(statics.clone()), moving.clone())];
        assert!(check(frames.into_iter(), &mask) > 10);
    }
}
