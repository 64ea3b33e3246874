//! The conservative fixed-point model of the core: its configuration, the host's quantization,
//! and bit-exact models of the hardware stages. It never misses a collision that the f64
//! reference finds on the original boxes, for every supported configuration
//! (docs/numerics.md, tests/fixed.rs, tests/stiff.rs).

pub mod accuracy;
pub mod broad;
pub mod config;
pub mod cycles;
pub mod frame;
pub mod grid;
pub mod grid_clocks;
pub mod margins;
pub mod plan;
pub mod quantize;
pub mod rounding;
pub mod run;
pub mod sat;
pub mod stream;
pub mod work;

pub use config::{BroadPhase, ConfigError, HwConfig};
pub use cycles::{frame_cycles, FrameCycles};
pub use frame::ModelFrame;
pub use margins::Margins;
pub use quantize::{keys, project, quantize, Projected, QObb, QuantizeError};
pub use run::ModelRun;
