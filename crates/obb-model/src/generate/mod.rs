//! Scene generators, deterministic from a seed (ChaCha8, whose stream is fixed across platforms).

mod motion;
mod slabs;
mod surgical;
mod uniform;

pub use motion::{FrameUpdate, SurgicalMotion, HAPTIC_HZ, TISSUE_EVERY};
pub use slabs::slabs;
pub use surgical::{surgical, surgical_meshes, SurfaceMesh, SURGICAL_DEFAULT_N};
pub use uniform::{uniform, UNIFORM_DEFAULT_DENSITY};

use crate::scene::Obb;
use nalgebra::{Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use thiserror::Error;

#[derive(Debug, Error, PartialEq)]
pub enum GenerateError {
    #[error("--n must be at least 1, got {0}")]
    TooFew(usize),
    #[error("--n {0} is above the limit of {1} boxes")]
    TooMany(usize, usize),
    #[error("--density must be a number in (0, 100], got {0}")]
    Density(f64),
}

/// Largest scene a generator makes (16 Mi boxes: several GB of JSON already).
pub const MAX_GENERATED: usize = 1 << 24;

fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn check_n(n: usize) -> Result<(), GenerateError> {
    if n == 0 {
        Err(GenerateError::TooFew(n))
    } else if n > MAX_GENERATED {
        Err(GenerateError::TooMany(n, MAX_GENERATED))
    } else {
        Ok(())
    }
}

/// An OBB from a center, a rotation whose columns are the box axes, and half-lengths.
pub(crate) fn obb(center: Vector3<f64>, rot: &Matrix3<f64>, half: [f64; 3], group: u32) -> Obb {
    let col = |k: usize| [rot[(0, k)], rot[(1, k)], rot[(2, k)]];
    Obb {
        center: [center.x, center.y, center.z],
        axes: [col(0), col(1), col(2)],
        half,
        group,
    }
}
