//! Rigid poses: an instrument's boxes kept in its own frame and placed in the world by a rotation
//! and a translation, `x_world = R x_local + t`.

use crate::scene::Obb;
use serde::{Deserialize, Serialize};

/// A rigid pose: `rotation` (rows) then `translation`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
}

impl Default for Pose {
    fn default() -> Pose {
        Pose::IDENTITY
    }
}

impl Pose {
    pub const IDENTITY: Pose = Pose {
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        translation: [0.0; 3],
    };

    /// A pure translation.
    pub fn translation(t: [f64; 3]) -> Pose {
        Pose {
            translation: t,
            ..Pose::IDENTITY
        }
    }

    /// `R v`, each entry summed in the order x, y, z (the order `apply` and the rigid engine's
    /// error bound assume).
    #[inline(always)]
    pub fn rotate(&self, v: &[f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        std::array::from_fn(|x| r[x][0] * v[0] + r[x][1] * v[1] + r[x][2] * v[2])
    }

    /// The box in the world: center `R c + t`, axes `R a_k`, the same half-lengths and group.
    #[inline]
    pub fn apply(&self, b: &Obb) -> Obb {
        let c = self.rotate(&b.center);
        Obb {
            center: std::array::from_fn(|x| c[x] + self.translation[x]),
            axes: b.axes.map(|a| self.rotate(&a)),
            half: b.half,
            group: b.group,
        }
    }
}
