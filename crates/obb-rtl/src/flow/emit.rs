//! Verilog emission with a chosen top-module name (rust-hdl's `generate_verilog` always names
//! it `top`).

use anyhow::{anyhow, Result};
use rust_hdl::prelude::*;

/// The Verilog of `block`, its top module named `name`, after rust-hdl's connection checks.
pub fn verilog<B: Block>(block: &mut B, name: &str) -> Result<String> {
    block.connect_all();
    check_all(block).map_err(|e| anyhow!("{name}: rust-hdl check failed: {e:?}"))?;
    let mut defines = ModuleDefines::default();
    block.accept(name, &mut defines);
    Ok(defines.defines())
}
