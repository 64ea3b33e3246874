//! Every engine reports exactly brute force's pairs, on random and degenerate scenes.

use crate::common;

use obb_model::engines::{Grid, GridStats};
use obb_model::generate::{surgical, uniform};
use obb_model::{detect, Engine, EngineKind, Frame, GroupMask, Pair, Prepared, Scene};
use proptest::prelude::*;

fn check_all_engines(scene: &Scene, mask: &GroupMask) {
    scene.validate().expect("generated scenes are valid");
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&scene.obbs);
    let (reference, rc) = detect(EngineKind::Brute, &boxes, mask);
    assert_eq!(rc.pairs as usize, reference.len());
    for p in &reference {
        assert!(p[0] < p[1]);
    }
    assert!(
        reference.windows(2).all(|w| w[0] < w[1]),
        "sorted, no repeats"
    );
    let n = boxes.len();
    let overlapping = (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .filter(|&(i, j)| mask.allows(boxes.groups[i], boxes.groups[j]))
        .filter(|&(i, j)| boxes.aabbs[i].overlaps(&boxes.aabbs[j]))
        .count() as u64;
    for kind in EngineKind::ALL {
        let (pairs, c) = detect(kind, &boxes, mask);
        assert_eq!(
            pairs, reference,
            "{kind} differs from brute with mask {mask}"
        );
        assert_eq!(c.pairs as usize, pairs.len(), "{kind} counts its pairs");
        assert!(
            c.sat_tests >= c.pairs,
            "{kind}: every pair went through the SAT"
        );
        if matches!(kind, EngineKind::Sap | EngineKind::Sweep | EngineKind::Grid) {
            // These broad phases send each AABB-overlapping pair to the SAT exactly once.
            assert_eq!(
                c.sat_tests, overlapping,
                "{kind}: SAT calls with mask {mask}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn engines_equal_brute(scene in common::scene(48), mask in common::mask()) {
        check_all_engines(&scene, &mask);
    }

    /// A fixed cell edge far from the chosen one must not change the result: tiny cells push
    /// boxes (entered or probing) to the large list, huge cells put everything in one cell.
    #[test]
    fn grid_cell_size_does_not_matter(scene in common::scene(32), mask in common::mask(), cell in prop_oneof![Just(0.05), Just(0.7), Just(3.0), Just(100.0)]) {
        let mut prepared = Prepared::default();
        let boxes = prepared.update(&scene.obbs);
        // sweep equals brute on every other test scene, and is much faster on these.
        let (reference, _) = detect(EngineKind::Sweep, &boxes, &mask);
        let mut grid = Grid::with_cell(cell).unwrap();
        let mut out = Vec::new();
        grid.detect(&boxes, &mask, &mut out);
        prop_assert_eq!(out, reference);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Boxes of one size on a lattice, spaced at their edge (faces touching), a hair closer or
    /// a hair apart, turned a little or not: every AABB is as large as the largest, so the
    /// grid takes the corner layout, with neighbours' lower corners about one cell edge apart.
    /// A box of the same size at `anchor` lattice steps below it sets where the cells start,
    /// so the lattice falls anywhere in them. The pairs and SAT tests equal brute force's.
    #[test]
    fn corner_layout_on_touching_lattices(
        half in prop_oneof![Just(0.5), Just(0.3), Just(1.7), Just(1e-3)],
        gap in prop_oneof![Just(1.0), Just(1.0 - 1e-12), Just(1.0 + 1e-12), Just(0.999), Just(1.001)],
        turn in prop_oneof![Just(0.0), -0.2..0.2f64],
        origin in prop::array::uniform3(-1e3..1e3f64),
        anchor in prop::array::uniform3(1.0..9.0f64),
    ) {
        let axes = common::axes_of([1.0, turn, 0.5 * turn, 0.0]);
        let step = 2.0 * half * gap;
        let place = |at: [f64; 3]| obb_model::Obb {
            center: std::array::from_fn(|x| origin[x] + at[x] * step),
            axes,
            half: [half; 3],
            group: 0,
        };
        let mut obbs: Vec<_> = (0..150)
            .map(|i| place([i % 6, i / 6 % 5, i / 30].map(f64::from)))
            .collect();
        obbs.push(place(anchor.map(|a| -a)));
        let scene = Scene { obbs };
        let mut prepared = Prepared::default();
        let (stats, _) = grid_on(&prepared.update(&scene.obbs), &GroupMask::All);
        prop_assert!(stats.corner, "boxes of one size take the corner layout");
        check_all_engines(&scene, &GroupMask::All);
    }
}

#[test]
fn every_box_overlapping_every_other() {
    // 60 boxes around one point: all 1,770 pairs collide.
    let obbs = (0..60)
        .map(|i| {
            let q = [1.0, i as f64 * 0.1, 0.3, -0.2];
            obb_model::Obb {
                center: [0.01 * i as f64, 0.0, -0.005 * i as f64],
                axes: common::axes_of(q),
                half: [1.0, 0.5, 0.25],
                group: i % 3,
            }
        })
        .collect();
    let scene = Scene { obbs };
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&scene.obbs);
    let (pairs, _) = detect(EngineKind::Grid, &boxes, &GroupMask::All);
    assert_eq!(pairs.len(), 60 * 59 / 2);
    check_all_engines(&scene, &GroupMask::All);
    check_all_engines(&scene, &GroupMask::Cross);
}

#[test]
fn empty_and_single_box_scenes() {
    for n in 0..2 {
        let scene = Scene {
            obbs: (0..n)
                .map(|_| obb_model::Obb::aligned([0.0; 3], [1.0; 3], 0))
                .collect(),
        };
        check_all_engines(&scene, &GroupMask::All);
    }
}

#[test]
fn generated_scenes_agree() {
    // A 1,000-box surgical scene has tissue, shaft and jaw contacts; uniform scenes at two densities.
    check_all_engines(&surgical(1000, 3).unwrap(), &GroupMask::All);
    check_all_engines(&surgical(1000, 3).unwrap(), &GroupMask::Cross);
    check_all_engines(&uniform(1500, 5, 0.3).unwrap(), &GroupMask::All);
    check_all_engines(&uniform(800, 6, 2.0).unwrap(), &GroupMask::All);
}

#[test]
fn engines_keep_no_state_between_frames() {
    // The same engine object on two different scenes, then the first again.
    let a = surgical(700, 1).unwrap();
    let b = uniform(900, 2, 0.5).unwrap();
    for kind in EngineKind::ALL {
        let mut engine = kind.build();
        let mut boxes = Prepared::default();
        let mut out = Vec::new();
        let mut results = Vec::new();
        for s in [&a, &b, &a] {
            let frame = boxes.update(&s.obbs);
            engine.detect(&frame, &GroupMask::All, &mut out);
            results.push(out.clone());
        }
        assert_eq!(results[0], results[2], "{kind} repeats itself");
        let fresh = detect(kind, &Prepared::default().update(&b.obbs), &GroupMask::All).0;
        assert_eq!(results[1], fresh, "{kind} after another scene");
    }
}

#[test]
fn grid_slabs_do_not_matter() {
    // The grid splits its cells into one z slab per thread (for scenes of a few hundred boxes
    // or more), and builds the corner layout in chunks: any number of slabs or chunks must give
    // the reference pairs and the same counters, with boxes spanning slab boundaries, large
    // boxes covering many slabs, and probing masks.
    // 8,000 boxes, so that even the 1,600 entered when group 0 probes fill several slabs.
    let mut spanning = uniform(8000, 9, 2.0).unwrap();
    spanning.obbs[17] = obb_model::Obb::aligned([0.0; 3], [40.0, 3.0, 60.0], 1);
    spanning.obbs[1200] = obb_model::Obb::aligned([5.0, 5.0, -20.0], [12.0, 12.0, 80.0], 2);
    for (i, o) in spanning.obbs.iter_mut().enumerate() {
        o.group = (i % 5 == 0) as u32;
    }
    let surgery = surgical(3000, 4).unwrap();
    // Boxes of similar sizes, all pairs: the corner layout, built in chunks on each thread.
    let similar = uniform(8000, 9, 0.05).unwrap();
    for (scene, mask) in [
        (&similar, GroupMask::All),
        (&spanning, GroupMask::All),
        (&spanning, GroupMask::Cross),
        (&surgery, GroupMask::All),
        (&surgery, GroupMask::Cross),
    ] {
        let mut prepared = Prepared::default();
        let boxes = prepared.update(&scene.obbs);
        // sweep equals brute on every other test scene, and is much faster on these.
        let (reference, _) = detect(EngineKind::Sweep, &boxes, &mask);
        grid_gives_on_threads(&boxes, &mask, &reference, &[1, 2, 3, 7]);
    }
    let mut prepared = Prepared::default();
    let (stats, _) = grid_on(&prepared.update(&similar.obbs), &GroupMask::All);
    assert!(stats.corner, "the similar boxes take the corner layout");
}

/// What a new grid builds on `boxes` for `mask`, and its pairs.
fn grid_on(boxes: &Frame, mask: &GroupMask) -> (GridStats, Vec<Pair>) {
    let mut grid = Grid::default();
    let mut pairs = Vec::new();
    grid.detect(boxes, mask, &mut pairs);
    (grid.stats(), pairs)
}

/// The grid, on a pool of each of `threads`, gives `reference` and the same counters.
fn grid_gives_on_threads(boxes: &Frame, mask: &GroupMask, reference: &[Pair], threads: &[usize]) {
    let mut first = None;
    for &threads in threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut grid = Grid::default();
        let mut pairs = Vec::new();
        let c = pool.install(|| grid.detect(boxes, mask, &mut pairs));
        assert_eq!(pairs, reference, "{threads} threads, mask {mask}");
        let first = first.get_or_insert(c);
        assert_eq!(
            (c.sat_tests, c.pairs),
            (first.sat_tests, first.pairs),
            "{threads} threads"
        );
    }
}

#[test]
fn grid_leaves_out_boxes_far_from_their_partner_groups() {
    // Three groups in separate clusters, 100 mm apart on x, except 20 boxes of group 1 left in
    // group 0's cluster: a box meeting none of the bounds of the groups the mask pairs it with
    // has no pair, and the grid does not enter it. Every mask must still give brute's pairs, on
    // one thread and on two (slabs).
    let mut scene = uniform(3000, 11, 2.0).unwrap();
    let mut bridges = 0;
    for (i, o) in scene.obbs.iter_mut().enumerate() {
        o.group = (i % 3) as u32;
        if o.group == 1 && bridges < 20 {
            bridges += 1;
            continue;
        }
        o.center[0] += 100.0 * f64::from(o.group);
    }
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&scene.obbs);
    for mask in ["cross", "0-1", "1-2", "0-0,1-2", "0-1,1-1", "all"] {
        let mask: GroupMask = mask.parse().unwrap();
        check_all_engines(&scene, &mask);
        let (reference, _) = detect(EngineKind::Brute, &boxes, &mask);
        grid_gives_on_threads(&boxes, &mask, &reference, &[1, 2]);
    }
    // With `0-1`, group 0 probes and only group 1's boxes near it are entered (group 2 pairs
    // with nothing): the 20 left in group 0's cluster, each in a few cells, not all 1,000.
    let (stats, pairs) = grid_on(&boxes, &"0-1".parse().unwrap());
    let entries = stats.entries;
    assert!(entries > 0 && entries < 200, "{entries} entries");
    assert!(!pairs.is_empty(), "the bridging boxes collide with group 0");
}
