//! `SurgicalMotion`: the surgical scene moving as a haptic loop sees it. Frames come at 1 kHz;
//! every frame moves the two grippers, every 40th (25 Hz) also brings a new tissue surface.
//!
//! The grippers run a 2 s cycle: down 6 mm into the tissue (0.4 s), along it 8 mm out and back
//! (1.2 s, each on its own heading, their jaw tips following the surface), and up out of it
//! (0.4 s). The tissue breathes: its dome rises and falls 1.5 mm at 0.25 Hz while its ripples
//! drift. Frame 0 is the still scene with the grippers 6 mm up.

use super::surgical::{parts, tissue, Surface, TISSUE_HALF_THICKNESS};
use super::GenerateError;
use crate::mesh::quad_box;
use crate::pose::Pose;
use crate::scene::Obb;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Haptic frames a second.
pub const HAPTIC_HZ: f64 = 1000.0;
/// A new tissue surface every this many haptic frames (25 Hz).
pub const TISSUE_EVERY: usize = 40;
/// Haptic frames in one gripper cycle.
const CYCLE: usize = 2000;
/// How high above its resting depth a gripper starts and ends its cycle, in mm.
const LIFT: f64 = 6.0;
/// How far a gripper slides along the tissue, in mm.
const SLIDE: f64 = 8.0;

/// One frame of a moving scene: the boxes of the groups it replaces (every other group keeps
/// its boxes from the frame before). The first frame replaces every group.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameUpdate {
    /// The frame's time, in ms.
    pub t_ms: f64,
    /// The groups whose boxes this frame replaces.
    pub replace: Vec<u32>,
    /// Their new boxes, each of a group in `replace`.
    pub obbs: Vec<Obb>,
}

/// A gripper: its boxes at rest (as in the still scene), its group, its tip (the mean of its
/// jaw boxes' centers, x and y) and its sliding heading.
struct Gripper {
    boxes: Vec<Obb>,
    group: u32,
    tip: [f64; 2],
    heading: [f64; 2],
}

pub struct SurgicalMotion {
    surface: Surface,
    n_tissue: usize,
    grippers: Vec<Gripper>,
}

impl SurgicalMotion {
    /// The motion of `surgical(n, seed)`.
    pub fn new(n: usize, seed: u64) -> Result<SurgicalMotion, GenerateError> {
        let p = parts(n, seed)?;
        let headings = [[0.8, 0.6], [-0.6, 0.8]];
        let grippers = p
            .grippers
            .into_iter()
            .zip(headings)
            .map(|((boxes, jaw_from), heading)| {
                let jaws = &boxes[jaw_from..];
                let mean = |k: usize| {
                    jaws.iter().map(|b| b.center[k]).sum::<f64>() / jaws.len().max(1) as f64
                };
                Gripper {
                    group: boxes.first().map_or(0, |b| b.group),
                    tip: [mean(0), mean(1)],
                    heading,
                    boxes,
                }
            })
            .collect();
        Ok(SurgicalMotion {
            surface: p.surface,
            n_tissue: p.tissue.len(),
            grippers,
        })
    }

    /// The groups of the scene: the tissue (0) and the grippers.
    pub fn groups(&self) -> Vec<u32> {
        std::iter::once(0)
            .chain(self.grippers.iter().map(|g| g.group))
            .collect()
    }

    /// The tissue surface as it is on frame `k`: as at its last update.
    fn surface_at(&self, k: usize) -> Surface {
        let t = (k / TISSUE_EVERY * TISSUE_EVERY) as f64 / HAPTIC_HZ;
        Surface {
            phase: [
                self.surface.phase[0] + 0.4 * t,
                self.surface.phase[1] - 0.3 * t,
            ],
            rise: 1.5 * (2.0 * PI * 0.25 * t).sin(),
        }
    }

    /// The grippers as rigid bodies: each one's boxes in its own frame (where the still scene
    /// has them), in group order.
    pub fn bodies(&self) -> Vec<Vec<Obb>> {
        self.grippers.iter().map(|g| g.boxes.clone()).collect()
    }

    /// Frame `k`'s new tissue surface, on frames 0, 40, 80, ...
    pub fn tissue(&self, k: usize) -> Option<Vec<Obb>> {
        k.is_multiple_of(TISSUE_EVERY).then(|| {
            tissue(&self.surface_at(k), self.n_tissue)
                .iter()
                .map(|q| quad_box(q, TISSUE_HALF_THICKNESS, 0))
                .collect()
        })
    }

    /// Frame `k`'s time, in ms.
    pub fn frame_time_ms(&self, k: usize) -> f64 {
        k as f64 * 1e3 / HAPTIC_HZ
    }

    /// The grippers' poses on frame `k`, in group order: translations.
    pub fn poses(&self, k: usize) -> Vec<Pose> {
        let surface = self.surface_at(k);
        let s = (k % CYCLE) as f64 / CYCLE as f64;
        let lift = if s < 0.2 {
            LIFT * (1.0 - s / 0.2)
        } else if s > 0.8 {
            LIFT * (s - 0.8) / 0.2
        } else {
            0.0
        };
        let slide = if (0.2..=0.8).contains(&s) {
            SLIDE * (PI * (s - 0.2) / 0.6).sin()
        } else {
            0.0
        };
        self.grippers
            .iter()
            .map(|g| {
                let (dx, dy) = (slide * g.heading[0], slide * g.heading[1]);
                // The tip keeps its depth under the surface wherever the surface has moved to.
                let dz = lift + surface.height(g.tip[0] + dx, g.tip[1] + dy)
                    - self.surface.height(g.tip[0], g.tip[1]);
                Pose::translation([dx, dy, dz])
            })
            .collect()
    }

    /// Frame `k`: on frames 0, 40, 80, ... the tissue's boxes, then the grippers' boxes placed
    /// by their poses.
    pub fn frame(&self, k: usize) -> FrameUpdate {
        let mut replace = Vec::with_capacity(1 + self.grippers.len());
        let mut obbs = Vec::new();
        if let Some(t) = self.tissue(k) {
            replace.push(0);
            obbs.extend(t);
        }
        for (g, pose) in self.grippers.iter().zip(self.poses(k)) {
            replace.push(g.group);
            obbs.extend(g.boxes.iter().map(|b| pose.apply(b)));
        }
        FrameUpdate {
            t_ms: self.frame_time_ms(k),
            replace,
            obbs,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::surgical;

    #[test]
    fn the_still_scene_with_the_grippers_up_then_down_along_and_out() {
        let m = SurgicalMotion::new(1750, 5).unwrap();
        let still = surgical(1750, 5).unwrap().obbs;
        let f0 = m.frame(0);
        assert_eq!(f0.replace, vec![0, 1, 2]);
        assert_eq!(f0.obbs.len(), still.len());
        assert_eq!(f0.obbs[..1000], still[..1000], "the tissue at rest");
        for (a, b) in f0.obbs.iter().zip(&still).skip(1000) {
            assert!((a.center[2] - b.center[2] - LIFT).abs() < 1e-9);
        }
        // Frame 1 moves only the grippers; frame 40 brings a new tissue.
        assert_eq!(m.frame(1).replace, vec![1, 2]);
        let f40 = m.frame(40);
        assert_eq!(f40.replace, vec![0, 1, 2]);
        assert_ne!(f40.obbs[..1000], still[..1000]);
        // Frames 0 and 1000 bring every group: up out of the tissue, then in it.
        let touching = |k: usize| {
            let f = m.frame(k);
            assert_eq!(f.replace, vec![0, 1, 2]);
            let mut prepared = crate::Prepared::default();
            let frame = prepared.update(&f.obbs);
            crate::detect(crate::EngineKind::Grid, &frame, &crate::GroupMask::Cross)
                .0
                .len()
        };
        assert_eq!(touching(0), 0);
        assert!(touching(1000) > 0);
        assert_eq!(m.frame(1000).t_ms, 1000.0);
    }
}
