//! `gen-rtl`: writes the core's Verilog and its manifest for a hardware configuration.

use anyhow::Result;
use clap::Parser;
use obb_model::fixed::HwConfig;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "gen-rtl",
    about = "Write the obbcd core's Verilog, manifest, ISE constraints and xtclsh project script"
)]
struct Args {
    /// Hardware configuration (TOML); default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output directory of the Verilog and the manifest.
    #[arg(long, default_value = "rtl-out")]
    out: PathBuf,
    /// The ISE constraints (clock period from `clock_ns`).
    #[arg(long, default_value = "constraints/obb_core.ucf")]
    ucf: PathBuf,
    /// The xtclsh project script (speed grade from `speed_grade`).
    #[arg(long, default_value = "scripts/ise/build.tcl")]
    tcl: PathBuf,
}

fn main() -> Result<()> {
    let a = Args::parse();
    let cfg = match &a.config {
        Some(p) => HwConfig::load(p)?,
        None => HwConfig::default(),
    };
    for name in obb_rtl::generate::write(&cfg, &a.out)? {
        println!("wrote {}", a.out.join(name).display());
    }
    obb_rtl::generate::write_handoff(&cfg, &a.out, &a.ucf, &a.tcl)?;
    println!("wrote {}", a.ucf.display());
    println!("wrote {}", a.tcl.display());
    Ok(())
}
