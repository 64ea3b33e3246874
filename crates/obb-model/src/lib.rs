//! obb-model: the golden model of the obbcd collision-detection core.
//!
//! Scenes of oriented bounding boxes (OBBs), their validation and generators, the f64
//! separating-axis test with a derived conservative margin, colliding pairs' contacts (normal and
//! penetration depth), and the CPU detection engines
//! (brute force, the paper's conventional and improved sweep and prune, a single-axis sweep and a
//! uniform grid). Everything later (fixed-point model, hardware, co-simulation) is checked against
//! what this crate computes.

pub mod aabb;
pub mod contact;
pub mod engines;
pub mod fixed;
pub mod generate;
pub mod groups;
pub mod mesh;
pub mod pose;
pub mod prepared;
pub mod radix;
pub mod sat;
pub mod scene;
pub mod simd;
pub mod stats;

pub use engines::{detect, Counters, Engine, EngineKind, Pair};
pub use groups::GroupMask;
pub use prepared::{Frame, Prepared};
pub use scene::{Obb, Scene, SceneError};
