//! `uniform`: N randomly rotated boxes scattered in a cube.

use super::{check_n, obb, rng, GenerateError};
use crate::scene::Scene;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use rand::Rng;
use rand_distr::StandardNormal;

/// Default total box volume over cube volume.
pub const UNIFORM_DEFAULT_DENSITY: f64 = 0.1;

/// `n` boxes with half-lengths uniform in [0.5, 1.5] mm and uniformly random rotations, centers
/// uniform in a cube sized so that the boxes' total volume is `density` times the cube's.
pub fn uniform(n: usize, seed: u64, density: f64) -> Result<Scene, GenerateError> {
    check_n(n)?;
    if !(density > 0.0 && density <= 100.0) {
        return Err(GenerateError::Density(density));
    }
    let mut r = rng(seed);
    // Mean box volume: 8 · E[h]^3 = 8 mm³ for independent h uniform in [0.5, 1.5].
    let side = (n as f64 * 8.0 / density).cbrt();
    let obbs = (0..n)
        .map(|_| {
            let center = Vector3::new(
                r.random::<f64>() * side,
                r.random::<f64>() * side,
                r.random::<f64>() * side,
            );
            let half = [
                r.random_range(0.5..=1.5),
                r.random_range(0.5..=1.5),
                r.random_range(0.5..=1.5),
            ];
            // A normalised 4-D Gaussian is a uniformly random rotation.
            let q = Quaternion::new(
                r.sample(StandardNormal),
                r.sample(StandardNormal),
                r.sample(StandardNormal),
                r.sample(StandardNormal),
            );
            let rot = UnitQuaternion::from_quaternion(q).to_rotation_matrix();
            obb(center, rot.matrix(), half, 0)
        })
        .collect();
    Ok(Scene { obbs })
}
