//! The planner (`obb_model::fixed::plan`): its configuration takes every scene it was planned
//! for without a false negative, follows the aims in the stated direction, explains every key,
//! and refuses aims it cannot meet with a message.

use obb_model::fixed::accuracy::{differences, reference_pairs};
use obb_model::fixed::plan::{plan, Aims, PlanError};
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame};
use obb_model::generate::{surgical, uniform};
use obb_model::{GroupMask, Obb, Scene};

/// The planned configuration on `scene`: no pair of the f64 reference missed; its figures.
fn no_pair_missed(cfg: &HwConfig, scene: &Scene) -> (usize, usize) {
    let run = ModelFrame::new(scene, cfg)
        .expect("a planned configuration takes its scenes")
        .run();
    let reference = reference_pairs(scene, &cfg.groups);
    let (fp, missed) = differences(&run.pairs, &reference);
    assert!(missed.is_empty(), "missed {missed:?} with {cfg:?}");
    (run.pairs.len(), fp.len())
}

#[test]
fn a_plan_takes_its_scenes_and_meets_the_false_positive_aim() {
    let scenes = [surgical(1500, 3).unwrap(), uniform(800, 5, 0.1).unwrap()];
    for groups in [GroupMask::All, GroupMask::Cross] {
        let aims = Aims {
            groups: groups.clone(),
            ..Aims::default()
        };
        let p = plan(&scenes, &aims).unwrap();
        assert_eq!(p.cfg.groups, groups);
        // Capacity: the next power of two at or above 1.25 times the largest scene.
        assert_eq!(p.cfg.capacity, 2048);
        for (scene, figures) in scenes.iter().zip(&p.scenes) {
            let (pairs, fp) = no_pair_missed(&p.cfg, scene);
            assert_eq!((pairs, fp), (figures.pairs, figures.false_positives));
            assert!(fp as f64 <= aims.fp_rate * pairs.max(1) as f64, "{p:?}");
        }
        // Narrower by one bit, some scene misses the aim (or the width is the narrowest).
        if p.cfg.center_bits > 8 {
            let narrower = HwConfig {
                center_bits: p.cfg.center_bits - 1,
                key_bits: p.cfg.key_bits - 1,
                half_bits: p.cfg.half_bits.min(p.cfg.center_bits - 2),
                sat_bits: p.cfg.sat_bits - 1,
                // The sweep takes boxes of any size: the pairs are every broad phase's.
                broad_phase: BroadPhase::Sweep,
                lanes: 1,
                ..p.cfg.clone()
            }
            .fitted_all(&scenes);
            let worst = scenes
                .iter()
                .map(|s| {
                    let (pairs, fp) = no_pair_missed(&narrower, s);
                    fp as f64 / pairs.max(1) as f64
                })
                .fold(0.0, f64::max);
            assert!(
                worst > aims.fp_rate,
                "{} bits would do",
                narrower.center_bits
            );
        }
    }
}

#[test]
fn plans_follow_the_aims() {
    let scene = [surgical(3000, 7).unwrap()];
    let loose = plan(
        &scene,
        &Aims {
            fp_rate: 0.2,
            ..Aims::default()
        },
    )
    .unwrap();
    let strict = plan(
        &scene,
        &Aims {
            fp_rate: 0.0,
            ..Aims::default()
        },
    )
    .unwrap();
    assert!(loose.cfg.center_bits <= strict.cfg.center_bits);
    assert!(strict.scenes[0].false_positives <= loose.scenes[0].false_positives);
    // A higher frame rate takes no fewer lanes, and the lanes reach it where they can.
    let lanes = |rate_hz: f64| {
        let p = plan(
            &scene,
            &Aims {
                rate_hz: Some(rate_hz),
                ..Aims::default()
            },
        )
        .unwrap();
        assert_eq!(p.cfg.broad_phase, BroadPhase::Grid, "{}", p.summary());
        (p.cfg.lanes, p.scenes[0].clocks)
    };
    let (slow, clocks) = lanes(1.0);
    assert_eq!(slow, 1, "one lane reaches 1 Hz");
    // Just above what one lane reaches.
    let (fast, fast_clocks) = lanes(1.01e9 / (clocks as f64 * 4.0));
    assert!(fast > 1, "one lane does not reach the rate");
    assert!(fast_clocks < clocks);
    // A rate no core reaches: the plan says so, naming the rate it does reach.
    let beyond = plan(
        &scene,
        &Aims {
            rate_hz: Some(1e12),
            ..Aims::default()
        },
    )
    .unwrap();
    assert!(
        beyond.unmet.len() == 1 && beyond.unmet[0].contains("below the 1000000000000 Hz asked"),
        "{:?}",
        beyond.unmet
    );
    assert!(beyond.to_toml().contains("# Aim not met: "));
    assert!(loose.unmet.is_empty() && strict.unmet.is_empty());
    // Cross-group asks for fewer pairs: no more clocks than all pairs.
    let cross = plan(
        &scene,
        &Aims {
            groups: GroupMask::Cross,
            ..Aims::default()
        },
    )
    .unwrap();
    let all = plan(&scene, &Aims::default()).unwrap();
    assert!(cross.scenes[0].clocks <= all.scenes[0].clocks);
    assert!(cross.scenes[0].pairs < all.scenes[0].pairs);
    // One list for every group only where every group pair is wanted.
    assert!(cross.cfg.grid_group_lists, "{}", cross.to_toml());
    // All pairs: both list layouts are tried.
    let toml = all.to_toml();
    assert!(toml.contains("1 one list: "), "{toml}");
}

#[test]
fn every_key_is_explained_and_the_toml_reads_back() {
    let p = plan(&[surgical(600, 1).unwrap()], &Aims::default()).unwrap();
    let toml = p.to_toml();
    let back = HwConfig::parse(&toml, "plan").unwrap();
    assert_eq!(back, p.cfg);
    let lines: Vec<&str> = toml.lines().collect();
    for (k, line) in lines.iter().enumerate().filter(|(_, l)| l.contains(" = ")) {
        assert!(lines[k - 1].starts_with("# "), "`{line}` has no comment");
    }
    for key in [
        "center_bits",
        "lsb_mm",
        "capacity",
        "broad_phase",
        "lanes",
        "groups",
        "grid_group_lists",
    ] {
        let line = lines
            .iter()
            .position(|l| l.starts_with(&format!("{key} =")))
            .unwrap();
        assert!(
            !lines[line - 1].contains("not planned"),
            "{key} is planned: {}",
            lines[line - 1]
        );
    }
}

#[test]
fn far_coordinates_and_long_boxes_are_planned_for() {
    // A 150 mm shaft 100 m away touching a small box: the LSB grows to hold them, the cell to
    // hold the shaft; nothing is missed.
    let shaft = Obb::aligned([1e5, 0.0, 0.0], [75.0, 2.0, 2.0], 0);
    let touching = Obb::aligned([1e5 + 76.0, 0.0, 0.0], [1.0; 3], 1);
    let scene = Scene {
        obbs: vec![shaft, touching],
    };
    let p = plan(std::slice::from_ref(&scene), &Aims::default()).unwrap();
    let (pairs, _) = no_pair_missed(&p.cfg, &scene);
    assert_eq!(pairs, 1);
    assert!(p.cfg.lsb_mm * f64::from(1u32 << (p.cfg.center_bits - 1)) >= 2e5);
}

#[test]
fn aims_that_cannot_be_met_are_refused() {
    let s = [surgical(100, 1).unwrap()];
    let with = |f: fn(&mut Aims)| {
        let mut a = Aims::default();
        f(&mut a);
        plan(&s, &a).unwrap_err()
    };
    assert!(matches!(
        plan(&[], &Aims::default()),
        Err(PlanError::NoScene)
    ));
    assert!(matches!(with(|a| a.fp_rate = 1.5), PlanError::FpRate(_)));
    assert!(matches!(
        with(|a| a.rate_hz = Some(0.0)),
        PlanError::Rate(_)
    ));
    assert!(matches!(with(|a| a.period_ns = 0.5), PlanError::Period(_)));
    // A box of group 8: beyond the core's groups.
    let mut odd = s[0].clone();
    odd.obbs[0].group = 8;
    let err = plan(&[odd], &Aims::default()).unwrap_err().to_string();
    assert!(err.contains("scene 0") && err.contains("group"), "{err}");
}
