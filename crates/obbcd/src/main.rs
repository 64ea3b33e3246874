//! `obbcd`: scenes, CPU collision detection, the fixed-point model, statistics and benchmarks.

mod bench;
mod builtin;
mod capi;
mod cosim;
mod detect;
mod error;
mod error_plot;
mod frames;
mod mesh_io;
mod neighbour;
mod parry;
mod plan;
mod replay;
mod scene;
mod stats;
mod synth;
mod timing;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "obbcd",
    version,
    about = "OBB collision detection: golden model, CPU engines, and the hardware core's co-simulation and synthesis estimate"
)]
struct Cli {
    /// Worker threads (default: one per core).
    #[arg(long, global = true)]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate a scene, or make one from OBJ and STL meshes, and write it as JSON.
    Scene(scene::SceneArgs),
    /// Find every colliding pair of a scene.
    Detect(detect::DetectArgs),
    /// Run a moving scene frame by frame as a control loop does (the built-in surgical motion
    /// at 1 kHz, or recorded frames): latency percentiles of the haptic frames, tissue updates
    /// apart.
    Replay(replay::ReplayArgs),
    /// Per-axis overlap counts, each broad phase's visits and SAT tests, and collisions, by
    /// group pair.
    Stats(stats::StatsArgs),
    /// Time every engine and parry3d on the surgical scene and on uniform scenes.
    Bench(bench::BenchArgs),
    /// Error against run time: for each data width and broad phase, the fixed-point model's
    /// false positives and negatives against the f64 reference, the worst AABB inflation, the
    /// clocks, the period and the frame time, and the Pareto front (CSV, SVG plot).
    Error(error::ErrorArgs),
    /// Plan a hardware configuration from scenes and aims: each key with the figure that
    /// decided it (TOML).
    Plan(plan::PlanArgs),
    /// Run one frame of a scene through the emitted Verilog in Verilator or Icarus and compare
    /// the pairs, counters and cycles with the bit-exact model.
    Cosim(cosim::CosimArgs),
    /// Synthesize the core with yosys for the XC6VHX565T: resources, logic depth, estimated
    /// period, beside the paper's tables (a Markdown report).
    Synth(synth::SynthArgs),
}

fn main() -> ExitCode {
    quiet_on_closed_pipe();
    // The matches are kept beside the parsed arguments: `scene mesh` pairs each mesh with the
    // options after it, an order the derived structs do not keep.
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some(t) = cli.threads {
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
        {
            eprintln!("error: cannot start {t} threads: {e}");
            return ExitCode::FAILURE;
        }
    }
    let result = match cli.command {
        Command::Scene(a) => match matches.subcommand() {
            Some((_, m)) => scene::run(a, m),
            None => unreachable!("clap requires a subcommand"),
        },
        Command::Detect(a) => detect::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Stats(a) => stats::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Error(a) => error::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Cosim(a) => cosim::run(a),
        Command::Synth(a) => synth::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// A closed output pipe (`obbcd detect | head -1`) ends the program as it ends `cat`, by
/// SIGPIPE, where Rust's runtime ignores the signal and `println!` then panics on the failed
/// write.
fn quiet_on_closed_pipe() {
    // SAFETY: restoring a signal's default action, before any other thread runs.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
}
