//! `gen-rtl`: writes the core's Verilog and its manifest for a hardware configuration.

use anyhow::{bail, Result};
use clap::Parser;
use obb_model::fixed::HwConfig;
use obb_rtl::flow::aims::AimArgs;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "gen-rtl",
    about = "Write the obbcd core's Verilog, manifest, ISE constraints and xtclsh project script"
)]
struct Args {
    /// Hardware configuration (TOML); default: the built-in one, or with `--scene` the plan
    /// for the scenes (as `obbcd plan`).
    #[arg(long)]
    config: Option<PathBuf>,
    #[command(flatten)]
    aims: AimArgs,
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
    // A closed output pipe (`gen-rtl | head -1`) ends the program as it ends `cat`, by SIGPIPE,
    // where Rust's runtime ignores the signal and `println!` then panics on the failed write.
    // SAFETY: restoring a signal's default action, before any other thread runs.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
    let a = Args::parse();
    let cfg = match (&a.config, a.aims.scenes.is_empty()) {
        (Some(_), false) => {
            bail!("--config and --scene: give a configuration or scenes to plan one")
        }
        (Some(p), true) => HwConfig::load(p)?,
        (None, true) => HwConfig::default(),
        (None, false) => {
            let plan = a.aims.plan()?;
            println!("planned: {}", plan.summary());
            plan.cfg
        }
    };
    for name in obb_rtl::flow::generate::write(&cfg, &a.out)? {
        println!("wrote {}", a.out.join(name).display());
    }
    obb_rtl::flow::generate::write_handoff(&cfg, &a.out, &a.ucf, &a.tcl)?;
    println!("wrote {}", a.ucf.display());
    println!("wrote {}", a.tcl.display());
    Ok(())
}
