//! Rigid bodies over a resident grid: each instrument's boxes are given once in its own frame,
//! and a frame brings only a pose per instrument. The boxes are kept in clusters of
//! `CLUSTER` consecutive boxes, each with the AABB of its boxes in the body's frame; a frame
//! places each cluster's bounds in the world, and only the boxes of clusters that may meet
//! something (the static boxes' bounds, or the bounds of another body the mask pairs with this
//! one) are placed and handed to `Resident` as its moving boxes. The others cannot be in a pair.
//!
//! Indices and pairs are `Resident`'s on the scene "static boxes, then every body's boxes
//! placed by its pose, body after body", so every other engine's on that scene.

use super::resident::Resident;
use crate::aabb::{Aabb, TINY, U};
use crate::engines::{Counters, Pair};
use crate::groups::GroupMask;
use crate::pose::Pose;
use crate::scene::Obb;
use std::ops::Range;

/// Boxes per cluster: small enough that a cluster's bounds stay close to its boxes on a
/// tessellated instrument, large enough that placing the bounds costs little beside the boxes.
const CLUSTER: usize = 16;

/// Clusters per super-cluster, whose bounds are placed first: a frame places the bounds of the
/// clusters of a super-cluster only when its bounds meet something.
const SUPER: usize = 16;

/// How much a placed cluster's bounds grow, relative to the magnitude of what they are computed
/// from: the rounding of `Pose::apply`, of `Aabb::of` on the placed box and of the bounds' own
/// arithmetic stay below 24u of it (docs/engines.md, "Rigid bodies").
const GROW: f64 = 64.0 * U;

/// Consecutive boxes of one body and the bounds of their AABBs in the body's frame.
#[derive(Clone, Debug, PartialEq)]
struct Cluster {
    boxes: Range<usize>,
    /// The boxes' local AABB union.
    union: Aabb,
    /// Center and half-extent of that union.
    center: [f64; 3],
    half: [f64; 3],
    /// Per local axis, the largest |coordinate| of that union: bounds every local quantity
    /// the placement multiplies by the rotation.
    reach: [f64; 3],
    /// Absolute growth for products that underflow: a box's half-lengths times the smallest
    /// subnormal, with room.
    floor: f64,
}

impl Cluster {
    fn of(boxes: &[Obb], range: Range<usize>) -> Cluster {
        let mut union = Aabb::EMPTY;
        let mut halves: f64 = 0.0;
        for b in &boxes[range.clone()] {
            union = union.union(&Aabb::of(b));
            halves = halves.max(b.half.iter().sum());
        }
        Cluster::bounding(range, union, 16.0 * TINY * (1.0 + halves))
    }

    /// The cluster of consecutive clusters' boxes (at least one cluster), from their bounds
    /// alone: the union of unions and the largest floor are exactly those `of` computes from
    /// the boxes (the floor grows with the half-lengths).
    fn merged(parts: &[Cluster]) -> Cluster {
        let range = parts[0].boxes.start..parts[parts.len() - 1].boxes.end;
        let union = parts.iter().fold(Aabb::EMPTY, |u, c| u.union(&c.union));
        let floor = parts.iter().fold(0.0, |f: f64, c| f.max(c.floor));
        Cluster::bounding(range, union, floor)
    }

    fn bounding(boxes: Range<usize>, union: Aabb, floor: f64) -> Cluster {
        Cluster {
            boxes,
            union,
            center: std::array::from_fn(|j| 0.5 * (union.min[j] + union.max[j])),
            half: std::array::from_fn(|j| 0.5 * (union.max[j] - union.min[j])),
            reach: std::array::from_fn(|j| union.min[j].abs().max(union.max[j].abs())),
            floor,
        }
    }

    /// World bounds holding the AABB `Aabb::of` gives each of the cluster's boxes placed by
    /// `pose.apply`.
    fn placed(&self, pose: &Pose) -> Aabb {
        let mut bounds = Aabb::EMPTY;
        for (x, row) in pose.rotation.iter().enumerate() {
            let t = pose.translation[x];
            let mut center = t;
            let mut extent = 0.0;
            let mut magnitude = t.abs();
            for (j, r) in row.iter().enumerate() {
                center += r * self.center[j];
                extent += r.abs() * self.half[j];
                magnitude += r.abs() * self.reach[j];
            }
            let w = extent + GROW * magnitude + self.floor;
            bounds.min[x] = center - w;
            bounds.max[x] = center + w;
        }
        bounds
    }
}

/// One body: its group, its boxes in its own frame, their clusters and super-clusters (super
/// `k` holds clusters `SUPER k..SUPER (k + 1)`).
#[derive(Clone, Debug)]
struct Body {
    group: u32,
    boxes: Vec<Obb>,
    clusters: Vec<Cluster>,
    supers: Vec<Cluster>,
}

impl Body {
    fn of(boxes: &[Obb]) -> Body {
        let clusters: Vec<Cluster> = (0..boxes.len())
            .step_by(CLUSTER)
            .map(|s| Cluster::of(boxes, s..(s + CLUSTER).min(boxes.len())))
            .collect();
        Body {
            group: Body::group_of(boxes),
            supers: clusters.chunks(SUPER).map(Cluster::merged).collect(),
            clusters,
            boxes: boxes.to_vec(),
        }
    }

    /// The group of the boxes, which must all be of one: the masks are decided per body, so
    /// a body of two groups would hide the pairs between them.
    fn group_of(boxes: &[Obb]) -> u32 {
        let group = boxes.first().map_or(0, |b| b.group);
        assert!(
            boxes.iter().all(|b| b.group == group),
            "a body's boxes are all of one group"
        );
        group
    }
}

#[derive(Debug, Default)]
pub struct RigidResident {
    resident: Resident,
    mask: GroupMask,
    bodies: Vec<Body>,
    /// Each super-cluster's placed bounds this frame, body after body.
    bounds: Vec<Aabb>,
    /// Each body's placed bounds this frame (the union of its super-clusters').
    body_bounds: Vec<Aabb>,
    /// The boxes handed to `Resident` this frame, and each one's index among all the bodies'.
    placed: Vec<Obb>,
    index: Vec<u32>,
    pairs: Vec<Pair>,
}

impl RigidResident {
    /// New static boxes and the mask every later frame uses (as `Resident::update_static`).
    pub fn update_static(&mut self, statics: &[Obb], mask: &GroupMask) -> Counters {
        self.mask = mask.clone();
        self.resident.update_static(statics, mask)
    }

    /// The bodies, each's boxes in its own frame, all of one group per body (panics
    /// otherwise). Their indices follow the static boxes, body after body.
    pub fn set_bodies<B: AsRef<[Obb]>>(&mut self, bodies: &[B]) {
        self.bodies = bodies.iter().map(|b| Body::of(b.as_ref())).collect();
    }

    /// New boxes for body `k` (in its own frame, as in `set_bodies`), in place: with the
    /// body's count unchanged nothing is allocated. Panics if there is no body `k`.
    pub fn set_body(&mut self, k: usize, boxes: &[Obb]) {
        let body = &mut self.bodies[k];
        if body.boxes.len() != boxes.len() {
            *body = Body::of(boxes);
            return;
        }
        body.group = Body::group_of(boxes);
        body.boxes.clone_from_slice(boxes);
        let Body {
            boxes,
            clusters,
            supers,
            ..
        } = body;
        for c in clusters.iter_mut() {
            *c = Cluster::of(boxes, c.boxes.clone());
        }
        for (s, parts) in supers.iter_mut().zip(clusters.chunks(SUPER)) {
            *s = Cluster::merged(parts);
        }
    }

    /// The boxes of the scene: the static ones and every body's.
    pub fn boxes(&self) -> usize {
        self.resident.statics() + self.bodies.iter().map(|b| b.boxes.len()).sum::<usize>()
    }

    /// The boxes placed and handed to the resident grid on the last frame.
    pub fn placed(&self) -> usize {
        self.placed.len()
    }

    /// The pairs of the scene "static boxes, then each body's boxes placed by `poses` (one per
    /// body, in order)", sorted ascending.
    pub fn detect(&mut self, poses: &[Pose], out: &mut Vec<Pair>) -> Counters {
        assert_eq!(poses.len(), self.bodies.len(), "one pose per body");
        self.bounds.clear();
        self.body_bounds.clear();
        for (body, pose) in self.bodies.iter().zip(poses) {
            let from = self.bounds.len();
            self.bounds
                .extend(body.supers.iter().map(|c| c.placed(pose)));
            let union = self.bounds[from..]
                .iter()
                .fold(Aabb::EMPTY, |u, b| u.union(b));
            self.body_bounds.push(union);
        }
        let statics = self.resident.static_bounds();
        let Self {
            mask,
            bodies,
            bounds,
            body_bounds,
            placed,
            index,
            ..
        } = self;
        placed.clear();
        index.clear();
        let (mut sup, mut first) = (0, 0);
        for (k, (body, pose)) in bodies.iter().zip(poses).enumerate() {
            // Whether placed bounds meet those of another body the mask pairs this one with.
            let meets_partner = |b: &Aabb| {
                bodies
                    .iter()
                    .zip(body_bounds.iter())
                    .enumerate()
                    .any(|(m, (other, ob))| {
                        m != k && mask.allows(body.group, other.group) && b.overlaps(ob)
                    })
            };
            let all = mask.allows(body.group, body.group);
            let meets = |b: &Aabb| all || b.overlaps(&statics) || meets_partner(b);
            for clusters in body.clusters.chunks(SUPER) {
                sup += 1;
                if !meets(&bounds[sup - 1]) {
                    continue;
                }
                for c in clusters {
                    if meets(&c.placed(pose)) {
                        for i in c.boxes.clone() {
                            placed.push(pose.apply(&body.boxes[i]));
                            index.push((first + i) as u32);
                        }
                    }
                }
            }
            first += body.boxes.len();
        }
        let counters = self.resident.detect(&self.placed, &mut self.pairs);
        // The placed boxes keep the bodies' order, so renumbering keeps the pairs sorted.
        let s = self.resident.statics() as u32;
        let index = &self.index;
        let at = |i: u32| {
            if i < s {
                i
            } else {
                s + index[(i - s) as usize]
            }
        };
        out.clear();
        out.extend(self.pairs.iter().map(|&[i, j]| [at(i), at(j)]));
        counters
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The placed bounds hold the AABB the engine computes for every placed box: boxes near
    /// and far from their body's origin, translations small and large, tilted rotations.
    #[test]
    fn placed_bounds_hold_every_placed_box_aabb() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut angle = || rng.random_range(-3.2..3.2);
        let rotations: Vec<Rotation3<f64>> = (0..50)
            .map(|_| Rotation3::from_euler_angles(angle(), angle(), angle()))
            .chain([Rotation3::identity()])
            .collect();
        for r in rotations {
            let m = r.matrix();
            for (far, shift) in [
                (1.0f64, 9e5f64),
                (9e5, 1.0),
                (1e-300, 1e-300),
                (1e-315, 1e-315),
                (3e5, 9e5),
            ] {
                let boxes: Vec<Obb> = (0..CLUSTER)
                    .map(|_| {
                        let c = std::array::from_fn(|_| rng.random_range(-far..far));
                        let h = std::array::from_fn(|_| rng.random_range(0.0..far.min(1.0)));
                        let turn = Rotation3::from_euler_angles(
                            rng.random_range(-3.2..3.2),
                            rng.random_range(-3.2..3.2),
                            rng.random_range(-3.2..3.2),
                        );
                        let a = turn.matrix();
                        Obb {
                            center: c,
                            axes: std::array::from_fn(|k| std::array::from_fn(|x| a[(x, k)])),
                            half: h,
                            group: 1,
                        }
                    })
                    .collect();
                let cluster = Cluster::of(&boxes, 0..boxes.len());
                let pose = Pose {
                    rotation: std::array::from_fn(|x| std::array::from_fn(|j| m[(x, j)])),
                    translation: std::array::from_fn(|_| rng.random_range(-shift..shift)),
                };
                let bounds = cluster.placed(&pose);
                for b in &boxes {
                    let a = Aabb::of(&pose.apply(b));
                    for x in 0..3 {
                        assert!(
                            bounds.min[x] <= a.min[x] && a.max[x] <= bounds.max[x],
                            "axis {x}: {a:?} outside {bounds:?}"
                        );
                    }
                }
            }
        }
    }

    /// A super-cluster merged from its clusters' bounds equals one computed from its boxes:
    /// whole and partial super-clusters, boxes of every size and far from the origin.
    #[test]
    fn merged_clusters_equal_the_cluster_of_their_boxes() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for n in [
            1,
            CLUSTER,
            CLUSTER * SUPER,
            CLUSTER * SUPER + 17,
            3 * CLUSTER * SUPER - 5,
        ] {
            let boxes: Vec<Obb> = (0..n)
                .map(|_| {
                    let c = std::array::from_fn(|_| rng.random_range(-9e5..9e5));
                    let h = std::array::from_fn(|_| rng.random_range(0.0..50.0));
                    Obb::aligned(c, h, 1)
                })
                .collect();
            let body = Body::of(&boxes);
            assert_eq!(body.supers.len(), n.div_ceil(CLUSTER * SUPER));
            for (k, s) in body.supers.iter().enumerate() {
                let range = k * CLUSTER * SUPER..((k + 1) * CLUSTER * SUPER).min(n);
                assert_eq!(*s, Cluster::of(&boxes, range), "n {n}, super {k}");
            }
        }
    }
}
