//! The tool flow around the hardware: Verilog generation and the ISE hand-off, the simulators
//! (Verilator, Icarus) with their test benches and build cache, and the yosys synthesis
//! estimate. Nothing here is part of the core.

pub mod aims;
pub mod cache;
pub mod cosim;
pub mod emit;
pub mod generate;
pub mod handoff;
pub mod synth;
pub mod verilator;
pub mod waves;
