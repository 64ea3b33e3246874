//! The peer we measure against: parry3d (f32), its BVH broad phase and its cuboid-cuboid test.

use obb_model::{GroupMask, Pair, Scene};
use parry3d::bounding_volume::Aabb;
use parry3d::math::{Mat3, Pose, Rot3, Vector};
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use parry3d::query::details::intersection_test_cuboid_cuboid;
use parry3d::shape::Cuboid;

/// A scene converted to parry's types (the conversion is loading, not detection).
pub struct ParryScene {
    poses: Vec<Pose>,
    cuboids: Vec<Cuboid>,
    groups: Vec<u32>,
}

impl ParryScene {
    pub fn new(scene: &Scene) -> ParryScene {
        let v = |r: [f64; 3]| Vector::new(r[0] as f32, r[1] as f32, r[2] as f32);
        ParryScene {
            poses: scene
                .obbs
                .iter()
                .map(|o| {
                    let m = Mat3::from_cols(v(o.axes[0]), v(o.axes[1]), v(o.axes[2]));
                    Pose::from_parts(v(o.center), Rot3::from_mat3(&m))
                })
                .collect(),
            cuboids: scene.obbs.iter().map(|o| Cuboid::new(v(o.half))).collect(),
            groups: scene.obbs.iter().map(|o| o.group).collect(),
        }
    }

    /// One frame: AABBs, BVH build, self-traversal and the cuboid test, on one thread.
    pub fn detect(&self, mask: &GroupMask, out: &mut Vec<Pair>) {
        out.clear();
        let aabbs: Vec<Aabb> = self
            .cuboids
            .iter()
            .zip(&self.poses)
            .map(|(c, p)| c.aabb(p))
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &aabbs);
        let mut workspace = BvhWorkspace::default();
        bvh.traverse_bvtt_single_tree::<false>(&mut workspace, &mut |a, b| {
            let (a, b) = (a.min(b) as usize, a.max(b) as usize);
            if !mask.allows(self.groups[a], self.groups[b]) {
                return;
            }
            let pos12 = self.poses[a].inv_mul(&self.poses[b]);
            if intersection_test_cuboid_cuboid(&pos12, &self.cuboids[a], &self.cuboids[b]) {
                out.push([a as u32, b as u32]);
            }
        });
        out.sort_unstable();
    }
}
