//! obb-rtl's integration tests, one binary (one build of rust-hdl's generics, and the tests of
//! every file share the test threads). Each module is one file of this directory, named after
//! what it checks; `cargo test -p obb-rtl --test rtl -- grid::` runs one of them.

mod common;
mod mutation;

mod core_stages;
#[path = "core.rs"]
mod cores;
mod cosim;
mod generate;
mod grid;
mod handoff;
mod leaves;
mod mutants;
mod projection;
mod radix;
mod sat;
mod sat_back;
mod sat_front;
mod sat_leaves;
mod synth;
mod walkers;
