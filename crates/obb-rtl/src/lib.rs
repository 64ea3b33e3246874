//! obb-rtl: the obbcd collision-detection core described in rust-hdl, checked cycle by cycle
//! against the bit-exact model in `obb-model` (`obb_model::fixed`), and the tool flow around it
//! (`flow`: Verilog generation, simulators, synthesis estimate, ISE hand-off).
//!
//! The hardware, in the order a box goes through the core:

// Building blocks: arithmetic leaves (each product one DSP48E1), memories, delay lines, a width
// adapter.
pub mod dist_ram;
pub mod leaf;
pub mod pipe;
pub mod resize;
pub mod table_ram;

// The load (which box is taken, at which index) and the projection: a box's AABB keys and SAT
// margin.
pub mod box_load;
pub mod projection;

// The broad phases: the radix sort (sweep, improved-sap), the walkers, and the grid.
pub mod bin_table;
pub mod box_queue;
pub mod grid;
pub mod grid_cells;
pub mod radix;
pub mod sweep;
pub mod walker;

// The key check of a visit (the grid checks its own), and a SAT test's geometry fetch.
pub mod geometry_fetch;
pub mod key_check;

// The narrow phase: the 15-axis SAT, front and back, and the pair stream's FIFO.
pub mod pair_fifo;
pub mod sat;
pub mod sat_back;
pub mod sat_front;
pub mod sat_round;

// The whole core.
pub mod core;

pub mod flow;
