//! `obbcd cosim`: one frame of a scene through the emitted Verilog of the core in a real
//! simulator, compared with the bit-exact model: the pair stream in order, the counters and the
//! clock count. Any difference fails the command with the first one.

use crate::detect::{load_config, write_pairs};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use obb_model::fixed::grid::MAX_WINDOW;
use obb_model::Scene;
use obb_rtl::cosim::{self, compare, prepare, Expected, Level, RunOptions, Taken};
use obb_rtl::verilator::Simulator;
use obb_rtl::{cache, generate, synth};
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(Clone, Copy, ValueEnum)]
pub enum SimulatorArg {
    Verilator,
    Icarus,
}

#[derive(Args)]
pub struct CosimArgs {
    /// Scene JSON file.
    #[arg(long)]
    scene: PathBuf,
    /// Hardware configuration (TOML); default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    #[arg(long, value_enum, default_value = "verilator")]
    simulator: SimulatorArg,
    /// Simulate yosys' netlist of the core (Virtex-6 primitives) instead of the RTL: a check
    /// of the DSP48E1, LUT and carry mapping. The memories are mapped to distributed RAM, as
    /// yosys' simulation models of the block RAMs have no behaviour; slow to synthesize
    /// (cached) and to simulate.
    #[arg(long)]
    gate_level: bool,
    /// The receiver takes a pair one clock in N (back-pressure on the pair stream).
    #[arg(long, default_value_t = 1)]
    ready_every: u32,
    /// Pairs JSON file to write (as `obbcd detect` writes it).
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Waveform file (VCD) of the whole frame.
    #[arg(long)]
    vcd: Option<PathBuf>,
    /// Cache of simulator builds and netlists (default: $OBBCD_CACHE, else ~/.cache/obbcd).
    #[arg(long)]
    cache: Option<PathBuf>,
}

fn spinner(msg: String) -> ProgressBar {
    let bar = ProgressBar::new_spinner().with_message(msg);
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

pub fn run(a: CosimArgs) -> Result<()> {
    if a.ready_every == 0 {
        bail!("--ready-every must be at least 1");
    }
    let scene = Scene::load(&a.scene)?;
    let cfg = load_config(a.config.as_deref())?;
    let (model, boxes) =
        prepare(&scene, &cfg).context("the scene does not fit the hardware configuration")?;
    let run = model.as_ref().map(|m| m.run());
    let cache = a.cache.clone().unwrap_or_else(cache::default_dir);
    let sim = match a.simulator {
        SimulatorArg::Verilator => Simulator::Verilator,
        SimulatorArg::Icarus => Simulator::Icarus,
    };
    let mut design = generate::core(&cfg)?;
    let level = if a.gate_level {
        let bar = spinner("synthesizing the core with yosys (cached after the first time)".into());
        let (dir, _) = synth::netlist(
            &design,
            "obb_core",
            synth::Mapping::Simulation,
            &cache.join("synth"),
        )?;
        bar.finish_and_clear();
        design = std::fs::read_to_string(dir.join("syn.v"))?;
        Level::Gates
    } else {
        Level::Rtl
    };
    let bar = spinner(format!("building the {sim:?} simulation"));
    let bench = cosim::build(&design, level, sim, a.vcd.is_some(), &cache.join("cosim"))?;
    bar.finish_and_clear();
    eprintln!(
        "{sim:?} build: {}",
        if bench.cached { "cached" } else { "new" }
    );

    let work = cache.join(format!("run-{}", std::process::id()));
    std::fs::create_dir_all(&work).with_context(|| format!("cannot create {}", work.display()))?;
    let stim = work.join("stim.hex");
    std::fs::write(&stim, cosim::stimulus(&boxes, &cfg))?;
    // The model's clocks, or for a frame over capacity a bound: the bar's length.
    let expect = cosim::frame_clocks(&scene, &cfg, run.as_ref())?;
    let bar = ProgressBar::new(expect).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} clocks ({eta})")
            .expect("a valid template"),
    );
    bar.set_message("simulating");
    let opts = RunOptions {
        ready_every: a.ready_every,
        // A core that never says `done` is a failure, not a hang: twice the clocks the frame
        // can take with every pair waiting `ready_every` clocks.
        timeout: 2 * (expect + run.as_ref().map_or(0, |r| r.reported()) * u64::from(a.ready_every))
            + 10_000,
        progress_every: (expect / 200).max(1000),
        vcd: a.vcd.clone(),
    };
    let start = Instant::now();
    let result = bench.run(&stim, boxes.len(), &opts, |clock| bar.set_position(clock));
    bar.finish_and_clear();
    let _ = std::fs::remove_dir_all(&work);
    let got = result?;
    let secs = start.elapsed().as_secs_f64();

    let mut pairs = got.stream.clone();
    pairs.sort_unstable();
    pairs.dedup();
    let want = Expected::of(run.as_ref());
    let verdict = compare(&got, &want, Taken::of(a.ready_every, cfg.lanes));
    println!(
        "simulator={} level={} obbs={} pairs={} reported={} candidates={} sat={} cycles={} \
         model_cycles={} frame_ms={:.3} clock_ns={} sim_s={secs:.2} clocks_per_s={:.0}",
        format!("{sim:?}").to_lowercase(),
        if a.gate_level { "gates" } else { "rtl" },
        boxes.len(),
        pairs.len(),
        got.pairs,
        got.candidates,
        got.sat_tests,
        got.cycles,
        run.as_ref().map_or(0, |r| r.cycles.total),
        got.cycles as f64 * cfg.clock_ns * 1e-6,
        cfg.clock_ns,
        got.clocks as f64 / secs,
    );
    if let Err(e) = verdict {
        bail!("the core and the model differ: {e}");
    }
    if run.is_none() {
        bail!(
            "the scene's {} boxes exceed the configured capacity of {}: the core flagged \
             capacity_exceeded and reported no pair, as it must; no pairs file was written",
            boxes.len(),
            cfg.capacity
        );
    }
    if let Expected::Incomplete(_) = want {
        bail!(
            "a box spans more than {} grid cells of {} mm on an axis, a window the grid's slow \
             path does not read: the core flagged capacity_exceeded, and the {} pair(s) it sent \
             are the model's; no pairs file was written (a larger `grid_cell_mm` takes the box)",
            MAX_WINDOW - 1,
            cfg.grid_cell_mm,
            got.stream.len()
        );
    }
    if let Some(path) = &a.output {
        write_pairs(path, &pairs)?;
    }
    Ok(())
}
