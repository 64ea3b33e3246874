//! The conservative fixed-point model of the core: its configuration, the host's quantization,
//! and bit-exact models of the hardware stages. It never misses a collision that the f64
//! reference finds on the original boxes, for every supported configuration
//! (docs/numerics.md, tests/fixed.rs, tests/stiff.rs).

pub mod config;
pub mod frame;
pub mod margins;
pub mod quantize;
pub mod sat;

pub use config::{BroadPhase, ConfigError, HwConfig};
pub use frame::ModelFrame;
pub use margins::Margins;
pub use quantize::{keys, project, quantize, Projected, QObb, QuantizeError};
