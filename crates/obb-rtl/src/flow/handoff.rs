//! The ISE hand-off: a UCF with the clock constraint, and an xtclsh script that creates the
//! XC6VHX565T project, adds the core's Verilog and the UCF, and runs synthesis, implementation
//! and the bitstream (docs/hardware.md, README "Handing the core to Xilinx ISE"). Neither can
//! run here; `tests/handoff.rs` checks what can be checked.

use obb_model::fixed::HwConfig;

/// The device and package of the target board.
pub const DEVICE: &str = "xc6vhx565t";
pub const PACKAGE: &str = "ff1923";

/// The UCF: one clock, `clock_ns` from the configuration.
pub fn ucf(cfg: &HwConfig, header: &str) -> String {
    format!(
        "{}\
NET \"clock\" TNM_NET = \"clock\";\n\
TIMESPEC \"TS_clock\" = PERIOD \"clock\" {:.3} ns HIGH 50%;\n",
        header.replace("//", "#"),
        cfg.clock_ns
    )
}

/// The xtclsh script. `verilog` and `constraints` are the paths of `obb_core.v` and of the UCF
/// relative to the script's own directory, so the script runs from any build directory.
pub fn build_tcl(cfg: &HwConfig, header: &str, verilog: &str, constraints: &str) -> String {
    format!(
        "{}\
# Run in an empty build directory: xtclsh <path to this script>\n\
set here [file dirname [file normalize [info script]]]\n\
project new obb_core.xise\n\
project set family \"Virtex6\"\n\
project set device \"{DEVICE}\"\n\
project set package \"{PACKAGE}\"\n\
project set speed \"-{}\"\n\
project set top_level_module_type \"HDL\"\n\
project set synthesis_tool \"XST (VHDL/Verilog)\"\n\
project set \"Preferred Language\" \"Verilog\"\n\
xfile add [file join $here {verilog}]\n\
xfile add [file join $here {constraints}]\n\
project set top obb_core\n\
process run \"Synthesize - XST\"\n\
process run \"Implement Design\"\n\
process run \"Generate Programming File\"\n\
project close\n",
        header.replace("//", "#"),
        cfg.speed_grade
    )
}
