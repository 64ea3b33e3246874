//! obb-model's integration tests, one binary (one build, and the tests of every file share the
//! test threads); `tests/steady_state.rs` is a binary of its own, for it counts every
//! allocation of its process. Each module is one file of this directory, named after what it
//! checks; `cargo test -p obb-model --test model -- stiff::` runs one of them.

mod common;

mod contact;
mod engines;
mod fixed;
mod grid;
mod plan;
mod radix;
mod resident;
mod resident_grid;
mod rigid;
mod sat;
mod scene;
mod stiff;
mod underflow;
