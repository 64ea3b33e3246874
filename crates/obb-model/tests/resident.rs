//! Resident groups (`resident_groups`): an update frame loads every box, the resident groups'
//! first; each haptic frame after it streams only the other groups' boxes, which meet the
//! resident ones in the lists the update left. A haptic frame reports exactly what a frame
//! loading every box reports, less the pairs of two resident groups (the update's), and never
//! misses a pair of the f64 reference.

use obb_model::fixed::accuracy::{differences, reference_pairs};
use obb_model::fixed::stream::{interleave, STREAM_WAYS};
use obb_model::fixed::{HwConfig, ModelFrame, QuantizeError};
use obb_model::generate::surgical;
use obb_model::{GroupMask, Scene};

/// The surgical scene's tissue (group 0) and instruments, the instruments moved by `step` mm
/// per frame `k` (towards and into the tissue, and along it).
fn instruments_at(scene: &Scene, k: usize, step: f64) -> Scene {
    let mut moved = Scene {
        obbs: scene
            .obbs
            .iter()
            .filter(|o| o.group != 0)
            .cloned()
            .collect(),
    };
    for o in &mut moved.obbs {
        let d = [0.5 * step, -0.3 * step, -0.2 * step];
        for (c, d) in o.center.iter_mut().zip(d) {
            *c += k as f64 * d;
        }
    }
    moved
}

fn tissue(scene: &Scene) -> Scene {
    Scene {
        obbs: scene
            .obbs
            .iter()
            .filter(|o| o.group == 0)
            .cloned()
            .collect(),
    }
}

fn joined(a: &Scene, b: &Scene) -> Scene {
    Scene {
        obbs: a.obbs.iter().chain(&b.obbs).cloned().collect(),
    }
}

fn resident_cfg(groups: GroupMask) -> HwConfig {
    HwConfig {
        groups,
        resident_groups: vec![0],
        ..HwConfig::default()
    }
}

#[test]
fn haptic_frames_report_what_whole_frames_report_less_the_resident_pairs() {
    let scene = surgical(3000, 11).unwrap();
    for groups in [GroupMask::Cross, GroupMask::All] {
        let cfg = resident_cfg(groups.clone());
        let whole = HwConfig {
            resident_groups: Vec::new(),
            ..cfg.clone()
        };
        let update = ModelFrame::new(&scene, &cfg).unwrap();
        let n_tissue = tissue(&scene).obbs.len();
        assert_eq!(update.resident_boxes(), n_tissue);
        let mut last = update.clone();
        for k in 1..=4 {
            // Every other frame streams the instruments interleaved.
            let moved = instruments_at(&scene, k, 0.4);
            let streamed = match k % 2 {
                0 => interleave(&moved, STREAM_WAYS),
                _ => moved,
            };
            let haptic = last.haptic(&streamed).unwrap();
            assert_eq!(haptic.resident, Some(n_tissue));
            let got = haptic.run();
            // The same boxes loaded whole, in the same order: its pairs but the tissue's own.
            let all = joined(&tissue(&scene), &streamed);
            let want: Vec<_> = ModelFrame::new(&all, &whole)
                .unwrap()
                .run()
                .pairs
                .into_iter()
                .filter(|p| p[1] as usize >= n_tissue)
                .collect();
            assert_eq!(got.pairs, want, "{groups} frame {k}");
            // And nothing of the f64 reference is missed.
            let reference: Vec<_> = reference_pairs(&all, &groups)
                .into_iter()
                .filter(|p| p[1] as usize >= n_tissue)
                .collect();
            let (_, missed) = differences(&got.pairs, &reference);
            assert!(missed.is_empty(), "{groups} frame {k}: missed {missed:?}");
            // Each pair met once, and only streamed boxes are loaded.
            assert_eq!(got.reported(), got.pairs.len() as u64);
            assert!(got.cycles.load < streamed.obbs.len() as u64 + 100);
            last = haptic;
        }
    }
}

#[test]
fn an_update_frame_clears_the_lists_first_and_reports_every_pair() {
    let scene = surgical(3000, 11).unwrap();
    let cfg = resident_cfg(GroupMask::All);
    let plain = HwConfig {
        resident_groups: Vec::new(),
        ..cfg.clone()
    };
    let update = ModelFrame::new(&scene, &cfg).unwrap().run();
    let whole = ModelFrame::new(&scene, &plain).unwrap().run();
    assert_eq!(update.pairs, whole.pairs);
    assert_eq!(update.work.visits, whole.work.visits);
    // The clear before the load adds its clocks (2^grid_hash_bits) to the frame.
    assert_eq!(
        update.cycles.total,
        whole.cycles.total + (1 << cfg.grid_hash_bits)
    );
}

#[test]
fn resident_boxes_out_of_place_are_refused() {
    let scene = surgical(700, 2).unwrap();
    let cfg = resident_cfg(GroupMask::Cross);
    // An update frame loads the resident group first.
    let mut shuffled = scene.clone();
    shuffled.obbs.rotate_left(scene.obbs.len() - 10);
    match ModelFrame::new(&shuffled, &cfg) {
        Err(e @ QuantizeError::ResidentOrder { .. }) => {
            assert!(e.to_string().contains("resident"), "{e}")
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    // A haptic frame streams no resident box.
    let update = ModelFrame::new(&scene, &cfg).unwrap();
    match update.haptic(&scene) {
        Err(e @ QuantizeError::ResidentStreamed { index: 0, group: 0 }) => {
            assert!(e.to_string().contains("haptic"), "{e}")
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    // Nor more boxes than the capacity, the resident ones included.
    let small = HwConfig {
        capacity: 512,
        ..cfg.clone()
    };
    let tissue_only = tissue(&scene);
    let update = ModelFrame::new(&tissue_only, &small).unwrap();
    let many = instruments_at(&scene, 0, 0.0);
    assert!(matches!(
        update.haptic(&many),
        Err(QuantizeError::Capacity { .. })
    ));
    // A key naming a group without lists, or another broad phase, is refused.
    for bad in [
        HwConfig {
            resident_groups: vec![3],
            ..HwConfig::default()
        },
        HwConfig {
            resident_groups: vec![0],
            broad_phase: obb_model::fixed::BroadPhase::Sweep,
            ..HwConfig::default()
        },
    ] {
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("resident_groups"), "{e}");
    }
}

/// The figures of the surgical scene (printed; `--nocapture`): the update frame's clocks and
/// the haptic frames', with one walker lane and with two, the instruments streamed in the
/// scene's order and interleaved; where the visits are in the scene's order.
#[test]
fn surgical_haptic_frame_figures() {
    let scene = surgical(17_500, 1).unwrap();
    for lanes in [1, 2] {
        let cfg = HwConfig {
            lanes,
            ..resident_cfg(GroupMask::Cross)
        };
        let update = ModelFrame::new(&scene, &cfg).unwrap();
        let u = update.run();
        eprintln!(
            "{lanes} lane(s), update: {:?}, {} pairs",
            u.cycles,
            u.pairs.len()
        );
        for k in 0..3 {
            let moved = instruments_at(&scene, k, 0.4);
            let spread = interleave(&moved, STREAM_WAYS);
            let mut clocks = Vec::new();
            for (order, streamed) in [("scene order", &moved), ("interleaved", &spread)] {
                let haptic = update.haptic(streamed).unwrap();
                let h = haptic.run();
                eprintln!(
                    "{lanes} lane(s), haptic {k}, {order}: {:?}, {} visits, {} pairs",
                    h.cycles,
                    h.work.visits,
                    h.pairs.len()
                );
                assert!(h.cycles.total < u.cycles.total);
                clocks.push(h.cycles.total);
                if k == 0 && order == "scene order" {
                    // The visits per eighth of the stream: the jaws come in two runs.
                    let walk = haptic.grid_walk(&cfg.groups);
                    let n = walk.visits.len();
                    let mut eighths = [0usize; 8];
                    for (i, &v) in walk.visits.iter().enumerate() {
                        eighths[i * 8 / n] += v;
                    }
                    eprintln!("{lanes} lane(s), visits per eighth of the stream: {eighths:?}");
                }
            }
            // Spread over the stream, the jaws' visits overlap the load.
            assert!(clocks[1] < clocks[0], "{clocks:?}");
        }
    }
}
