//! `gen-rtl`: writes the core's Verilog and its manifest for a hardware configuration.

use anyhow::Result;
use clap::Parser;
use obb_model::fixed::HwConfig;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "gen-rtl",
    about = "Write the obbcd core's Verilog and manifest"
)]
struct Args {
    /// Hardware configuration (TOML); default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "rtl-out")]
    out: PathBuf,
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
    Ok(())
}
