//! Rigid bodies over the resident grid: instruments given once in their own frame and moved by a
//! pose find brute force's pairs on the scene "static boxes, then each body's boxes placed by
//! its pose" (`Pose::apply`), while only the clusters near something are placed.

use nalgebra::Rotation3;
use obb_model::engines::RigidResident;
use obb_model::generate::SurgicalMotion;
use obb_model::pose::Pose;
use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn brute(scene: &[Obb], mask: &GroupMask) -> Vec<[u32; 2]> {
    let mut prepared = Prepared::default();
    let frame = prepared.update(scene);
    detect(EngineKind::Brute, &frame, mask).0
}

/// The scene as brute force sees it: the static boxes, then every body placed by its pose.
fn placed(statics: &[Obb], bodies: &[Vec<Obb>], poses: &[Pose]) -> Vec<Obb> {
    let mut scene = statics.to_vec();
    for (body, pose) in bodies.iter().zip(poses) {
        scene.extend(body.iter().map(|b| pose.apply(b)));
    }
    scene
}

#[test]
fn the_moving_surgical_scene_as_rigid_grippers() {
    let motion = SurgicalMotion::new(700, 3).unwrap();
    let bodies = motion.bodies();
    let moving: usize = bodies.iter().map(Vec::len).sum();
    for mask in ["cross", "all", "0-1", "1-2"] {
        let mask: GroupMask = mask.parse().unwrap();
        let mut engine = RigidResident::default();
        engine.set_bodies(&bodies);
        let mut statics = Vec::new();
        let (mut pairs, mut found, mut fewest) = (Vec::new(), 0, usize::MAX);
        for k in (0..2000).step_by(10) {
            if let Some(t) = motion.tissue(k) {
                statics = t;
                engine.update_static(&statics, &mask);
            }
            let poses = motion.poses(k);
            let counters = engine.detect(&poses, &mut pairs);
            let want = brute(&placed(&statics, &bodies, &poses), &mask);
            assert_eq!(pairs, want, "frame {k}, mask {mask}");
            assert_eq!(counters.pairs, want.len() as u64);
            found += want.len();
            fewest = fewest.min(engine.placed());
        }
        assert!(found > 0, "{mask}: some pairs");
        if mask != GroupMask::All {
            // The grippers' upper parts, and whole grippers when they are up, stay unplaced.
            assert!(
                fewest < moving / 2,
                "{mask}: placed at least {fewest} of {moving}"
            );
        }
    }
}

fn random_box(rng: &mut ChaCha8Rng, center: [f64; 3], size: f64, group: u32) -> Obb {
    let r = Rotation3::from_euler_angles(
        rng.random_range(-3.2..3.2),
        rng.random_range(-3.2..3.2),
        rng.random_range(-3.2..3.2),
    );
    let m = r.matrix();
    Obb {
        center,
        axes: std::array::from_fn(|k| std::array::from_fn(|x| m[(x, k)])),
        half: std::array::from_fn(|_| rng.random_range(0.0..size)),
        group,
    }
}

/// Bodies of tilted boxes turned by random rotations about far-away origins (so that the
/// placement multiplies large coordinates), over a static layer, pair for pair with brute force.
#[test]
fn rotated_bodies_far_from_their_origin() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for scale in [1.0, 1e3, 1e5] {
        let statics: Vec<Obb> = (0..300)
            .map(|_| {
                let c = [
                    rng.random_range(-8.0..8.0),
                    rng.random_range(-8.0..8.0),
                    0.0,
                ];
                random_box(&mut rng, c, 0.6, 0)
            })
            .collect();
        // Each body lies around its own far origin `o`: its boxes are at o + (small offset).
        let origins = [[scale, -scale, 0.5 * scale], [-scale, 0.3 * scale, scale]];
        let bodies: Vec<Vec<Obb>> = origins
            .iter()
            .zip([1, 2])
            .map(|(o, g)| {
                (0..150)
                    .map(|_| {
                        let c = std::array::from_fn(|x| o[x] + rng.random_range(-3.0..3.0));
                        random_box(&mut rng, c, 0.5, g)
                    })
                    .collect()
            })
            .collect();
        for mask in [GroupMask::Cross, GroupMask::All] {
            let mut engine = RigidResident::default();
            engine.set_bodies(&bodies);
            engine.update_static(&statics, &mask);
            let mut pairs = Vec::new();
            let mut found = 0;
            for _ in 0..40 {
                // Each pose brings its body's origin near the static layer's middle.
                let poses: Vec<Pose> = origins
                    .iter()
                    .map(|o| {
                        let r = Rotation3::from_euler_angles(
                            rng.random_range(-3.2..3.2),
                            rng.random_range(-3.2..3.2),
                            rng.random_range(-3.2..3.2),
                        );
                        let m = r.matrix();
                        let pose = Pose {
                            rotation: std::array::from_fn(|x| std::array::from_fn(|j| m[(x, j)])),
                            translation: [0.0; 3],
                        };
                        let ro = pose.rotate(o);
                        let target = [
                            rng.random_range(-4.0..4.0),
                            rng.random_range(-4.0..4.0),
                            1.0,
                        ];
                        Pose {
                            translation: std::array::from_fn(|x| target[x] - ro[x]),
                            ..pose
                        }
                    })
                    .collect();
                engine.detect(&poses, &mut pairs);
                let want = brute(&placed(&statics, &bodies, &poses), &mask);
                assert_eq!(pairs, want, "scale {scale}, mask {mask}");
                found += want.len();
            }
            assert!(found > 0, "scale {scale}, {mask}: some pairs");
        }
    }
}

/// A body's box placed exactly against a static box (touching faces, at large coordinates, the
/// contact decided by the last bit): the rigid engine agrees with brute force either way.
#[test]
fn touching_faces_at_large_coordinates() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mask = GroupMask::Cross;
    let mut touching = 0;
    for _ in 0..400 {
        let x0: f64 = rng.random_range(-9e5..9e5);
        let h: f64 = rng.random_range(0.01..2.0);
        let statics = vec![Obb::aligned([x0, 0.0, 0.0], [h, h, h], 0)];
        // The body's box sits at `a` in its own frame, far from its origin or near it; the pose
        // moves it to x0 + 2h, touching, or a few ulps nearer or farther.
        let a: f64 = if rng.random_bool(0.5) {
            rng.random_range(-9e5..9e5)
        } else {
            rng.random_range(-1.0..1.0)
        };
        let body = vec![vec![Obb::aligned([a, 0.0, 0.0], [h, h, h], 1)]];
        let nudge = rng.random_range(-8..=8) as f64 * f64::EPSILON / 4.0;
        let pose = Pose::translation([(x0 + 2.0 * h) * (1.0 + nudge) - a, 0.3 * h, -0.2 * h]);
        let mut engine = RigidResident::default();
        engine.set_bodies(&body);
        engine.update_static(&statics, &mask);
        let mut pairs = Vec::new();
        engine.detect(&[pose], &mut pairs);
        let want = brute(&placed(&statics, &body, &[pose]), &mask);
        assert_eq!(pairs, want, "x0 {x0}, h {h}, a {a}");
        touching += want.len();
    }
    assert!(touching > 100, "many of them touch: {touching}");
}

#[test]
#[should_panic(expected = "a body's boxes are all of one group")]
fn a_body_of_two_groups_is_refused() {
    let b = |g| Obb::aligned([0.0; 3], [1.0; 3], g);
    RigidResident::default().set_bodies(&[vec![b(1), b(2)]]);
}
