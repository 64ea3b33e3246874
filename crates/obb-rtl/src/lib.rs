//! obb-rtl: the obbcd collision-detection core described in rust-hdl, checked cycle by cycle
//! against the bit-exact model in `obb-model` (`obb_model::fixed`), and its Verilog generator.

pub mod aims;
pub mod bin_table;
pub mod box_queue;
pub mod cache;
pub mod core;
pub mod cosim;
pub mod dist_ram;
pub mod emit;
pub mod generate;
pub mod grid;
pub mod grid_cells;
pub mod handoff;
pub mod leaf;
pub mod pair_fifo;
pub mod projection;
pub mod radix;
pub mod resize;
pub mod sat;
pub mod sat_back;
pub mod sat_front;
pub mod sat_round;
pub mod sweep;
pub mod synth;
pub mod table_ram;
pub mod verilator;
pub mod walker;
pub mod waves;
