//! `obbcd cosim`: one frame of a scene (and, with resident groups, haptic frames after it)
//! through the emitted Verilog of the core in a real simulator, compared with the bit-exact
//! model: the pair stream in order, the counters and the clock count. Any difference fails the
//! command with the first one.

use crate::builtin::scene_or_builtin;
use crate::detect::{load_config, write_pairs};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use obb_model::fixed::grid::MAX_WINDOW;
use obb_model::fixed::stream::{interleave, STREAM_WAYS};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::Scene;
use obb_rtl::flow::cosim::{self, compare, prepare, Expected, Level, RunOptions, Taken};
use obb_rtl::flow::verilator::Simulator;
use obb_rtl::flow::waves::Waves;
use obb_rtl::flow::{cache, generate, synth};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, ValueEnum)]
pub enum SimulatorArg {
    Verilator,
    Icarus,
}

#[derive(Args)]
pub struct CosimArgs {
    /// Scene JSON file; default: the built-in surgical scene (`obbcd scene surgical`).
    #[arg(long)]
    scene: Option<PathBuf>,
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
    /// With `resident_groups` in the configuration: after the scene's (update) frame, this many
    /// haptic frames, each streaming the scene's boxes of the other groups again while the core
    /// keeps the resident ones; each is compared with the model and gets its own line.
    #[arg(long, default_value_t = 0)]
    haptic_frames: usize,
    /// Haptic frames stream the boxes interleaved in this many ways (box 0, W, 2W, ..., then
    /// box 1, 1 + W, ...), which spreads the runs of boxes that meet many others over the
    /// frame; 1 streams them in the scene's order.
    #[arg(long, default_value_t = STREAM_WAYS)]
    interleave: usize,
    /// Pairs JSON file to write (as `obbcd detect` writes it), of the first frame.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Record waves to this file, VCD (`.vcd`) or FST (`.fst`, many times smaller; GTKWave
    /// reads both), in a second run of the stimulus on a traced build after the compared one.
    #[arg(long)]
    waves: Option<PathBuf>,
    /// The first clock recorded, counted over the whole run (all its frames).
    #[arg(long, default_value_t = 0, requires = "waves")]
    waves_from: u64,
    /// The recording run ends at this clock (default: the run's end).
    #[arg(long, requires = "waves")]
    waves_to: Option<u64>,
    /// Levels of hierarchy recorded: 1 the test bench's signals, 2 also `obb_core`'s ports and
    /// its own signals, ...; 0 all.
    #[arg(long, default_value_t = 0, requires = "waves")]
    waves_depth: u32,
    /// Cache of simulator builds and netlists (default: $OBBCD_CACHE, else ~/.cache/obbcd).
    #[arg(long)]
    cache: Option<PathBuf>,
}

fn spinner(msg: String) -> ProgressBar {
    let bar = ProgressBar::new_spinner().with_message(msg);
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// Runs the scene's frame (and its haptic frames) through the core's Verilog and compares
/// each frame with the model.
pub fn run(a: CosimArgs) -> Result<()> {
    if a.ready_every == 0 {
        bail!("--ready-every must be at least 1");
    }
    if a.interleave == 0 {
        bail!("--interleave must be at least 1 (1: the scene's order)");
    }
    let waves = a
        .waves
        .as_deref()
        .map(|p| Waves::new(p, a.waves_from, a.waves_to, a.waves_depth))
        .transpose()?;
    let scene = scene_or_builtin(a.scene.as_deref())?;
    let cfg = load_config(a.config.as_deref())?;
    let (model, boxes) =
        prepare(&scene, &cfg).context("the scene does not fit the hardware configuration")?;
    let run = model.as_ref().map(|m| m.run());
    let haptic = haptic_frames(&scene, &cfg, model.as_ref(), a.haptic_frames, a.interleave)?;
    let haptic_runs: Vec<_> = haptic.iter().map(|m| m.run()).collect();
    let cache = a.cache.clone().unwrap_or_else(cache::default_dir);
    let sim = match a.simulator {
        SimulatorArg::Verilator => Simulator::Verilator,
        SimulatorArg::Icarus => Simulator::Icarus,
    };
    let core = Core::build(&cfg, sim, a.gate_level, &cache)?;

    let mut frames = vec![(true, boxes.as_slice())];
    frames.extend(haptic.iter().map(|m| (false, m.streamed())));
    // The model's clocks, or for a frame over capacity a bound: the bar's length.
    let expect = cosim::frame_clocks(&scene, &cfg, run.as_ref())?
        + haptic_runs.iter().map(|r| r.cycles.total).sum::<u64>();
    let reported = run.as_ref().map_or(0, |r| r.reported())
        + haptic_runs.iter().map(|r| r.reported()).sum::<u64>();
    let opts = RunOptions {
        ready_every: a.ready_every,
        // A core that never says `done` is a failure, not a hang: twice the clocks the frame
        // can take with every pair waiting `ready_every` clocks.
        timeout: 2 * (expect + reported * u64::from(a.ready_every)) + 10_000,
        progress_every: (expect / 200).max(1000),
        ..RunOptions::default()
    };
    let start = Instant::now();
    let mut got = core.simulate(&frames, &cfg, &opts, expect, waves.as_ref())?;
    let secs = start.elapsed().as_secs_f64();
    let later = got.split_off(1);
    let got = got.remove(0);
    let line = |frame: &str, got: &cosim::SimFrame, obbs: usize, pairs: usize, model: u64| {
        format!(
            "frame={frame} simulator={} level={} obbs={obbs} pairs={pairs} reported={} \
             visits={} sat_tests={} cycles={} model_cycles={model} frame_ms={:.3} clock_ns={}",
            format!("{sim:?}").to_lowercase(),
            if a.gate_level { "gates" } else { "rtl" },
            got.pairs,
            got.visits,
            got.sat_tests,
            got.cycles,
            got.cycles as f64 * cfg.clock_ns * 1e-6,
            cfg.clock_ns,
        )
    };

    let pairs = distinct(&got.stream);
    let mut kept = None;
    let want = Expected::for_frame(run.as_ref(), &mut kept, &scene, &cfg)?;
    let verdict = compare(&got, &want, Taken::of(a.ready_every, cfg.lanes));
    let total_clocks: u64 = got.clocks + later.iter().map(|f| f.clocks).sum::<u64>();
    println!(
        "{} sim_s={secs:.2} clocks_per_s={:.0}",
        line(
            if cfg.resident_groups.is_empty() {
                "whole"
            } else {
                "update"
            },
            &got,
            boxes.len(),
            pairs.len(),
            run.as_ref().map_or(0, |r| r.cycles.total)
        ),
        total_clocks as f64 / secs,
    );
    if let Err(e) = verdict {
        bail!("the core and the model differ: {e}");
    }
    first_frame_complete(&boxes, &cfg, run.is_some(), &want, got.stream.len())?;
    for (k, ((m, r), sim_frame)) in haptic.iter().zip(&haptic_runs).zip(&later).enumerate() {
        let pairs = distinct(&sim_frame.stream);
        println!(
            "{}",
            line(
                "haptic",
                sim_frame,
                m.streamed().len(),
                pairs.len(),
                r.cycles.total
            )
        );
        if let Err(e) = compare(
            sim_frame,
            &Expected::of(r),
            Taken::of(a.ready_every, cfg.lanes),
        ) {
            bail!("haptic frame {}: the core and the model differ: {e}", k + 1);
        }
    }
    if let Some(path) = &a.output {
        write_pairs(path, &pairs, None)?;
    }
    Ok(())
}

/// The pairs of a stream, sorted, each once.
fn distinct(stream: &[[u32; 2]]) -> Vec<[u32; 2]> {
    let mut pairs = stream.to_vec();
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// A first frame that agrees with the model but is not the scene's whole answer (over
/// capacity, or a grid window too wide) still fails the command, saying why.
fn first_frame_complete(
    boxes: &[obb_model::fixed::QObb],
    cfg: &HwConfig,
    fits: bool,
    want: &Expected,
    sent: usize,
) -> Result<()> {
    if !fits {
        bail!(
            "the scene's {} boxes exceed the configured capacity of {}: the core flagged \
             capacity_exceeded and sent {sent} pair(s), as it must (the grid sends true pairs \
             of the boxes it kept until the box over capacity, the other broad phases none); \
             no pairs file was written",
            boxes.len(),
            cfg.capacity
        );
    }
    if let Expected::Incomplete(_) = want {
        bail!(
            "a box spans more than {} grid cells of {} mm on an axis, a window the grid's slow \
             path does not read: the core flagged capacity_exceeded, and the {sent} pair(s) it \
             sent are the model's; no pairs file was written (a larger `grid_cell_mm` takes the \
             box)",
            MAX_WINDOW - 1,
            cfg.grid_cell_mm,
        );
    }
    Ok(())
}

/// The core's Verilog (RTL, or yosys' netlist of it) built for a simulator.
struct Core {
    design: String,
    level: Level,
    sim: Simulator,
    cache: PathBuf,
    bench: cosim::Bench,
}

impl Core {
    /// Generates the core for `cfg`, synthesizes it for `gate_level`, and builds the
    /// simulation (each step cached under `cache`).
    fn build(cfg: &HwConfig, sim: Simulator, gate_level: bool, cache: &Path) -> Result<Core> {
        let mut design = generate::core(cfg)?;
        let level = if gate_level {
            let bar =
                spinner("synthesizing the core with yosys (cached after the first time)".into());
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
        let bench = cosim::build(&design, level, sim, None, &cache.join("cosim"))?;
        bar.finish_and_clear();
        eprintln!(
            "{sim:?} build: {}",
            if bench.cached { "cached" } else { "new" }
        );
        Ok(Core {
            design,
            level,
            sim,
            cache: cache.to_path_buf(),
            bench,
        })
    }

    /// Runs the frames back to back (with a bar over the `expect` clocks) and returns what
    /// each frame gave; then, whatever the verdict, records the waves if asked (a difference
    /// is when they are wanted).
    fn simulate(
        &self,
        frames: &[(bool, &[obb_model::fixed::QObb])],
        cfg: &HwConfig,
        opts: &RunOptions,
        expect: u64,
        waves: Option<&Waves>,
    ) -> Result<Vec<cosim::SimFrame>> {
        std::fs::create_dir_all(&self.cache)
            .with_context(|| format!("cannot create {}", self.cache.display()))?;
        // (Removed when dropped, on every way out.)
        let work = tempfile::Builder::new()
            .prefix("run-")
            .tempdir_in(&self.cache)
            .with_context(|| format!("cannot create a directory in {}", self.cache.display()))?;
        let stim = work.path().join("stim.hex");
        std::fs::write(&stim, cosim::stimulus(frames, cfg))?;
        let bar = ProgressBar::new(expect).with_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} clocks ({eta})")
                .expect("a valid template"),
        );
        bar.set_message("simulating");
        // (The bar follows the frames' clocks one after another.)
        let mut done = 0;
        let mut last = 0;
        let result = self.bench.run(&stim, frames.len(), opts, |clock| {
            if clock < last {
                done += last;
            }
            last = clock;
            bar.set_position(done + clock)
        });
        bar.finish_and_clear();
        let recorded = match waves {
            Some(w) if result.is_ok() => self.record_waves(&stim, frames.len(), opts, w),
            _ => Ok(()),
        };
        let got = result?;
        recorded?;
        Ok(got)
    }

    /// The same stimulus again on a traced build, into `waves`.
    fn record_waves(
        &self,
        stim: &Path,
        frames: usize,
        opts: &RunOptions,
        waves: &Waves,
    ) -> Result<()> {
        let sim = self.sim;
        let bar = spinner(format!("building the traced {sim:?} simulation"));
        let traced = cosim::build(
            &self.design,
            self.level,
            sim,
            Some(waves.trace()),
            &self.cache.join("cosim"),
        )?;
        bar.set_message(format!("recording {}", waves.path.display()));
        traced.record(stim, frames, opts, waves, |_| {})?;
        bar.finish_and_clear();
        eprintln!("waves: {}", waves.path.display());
        Ok(())
    }
}

/// The model's `count` haptic frames after the scene's frame `update`: each streams the
/// scene's boxes of the groups that are not resident, interleaved in `ways` ways.
fn haptic_frames(
    scene: &Scene,
    cfg: &HwConfig,
    update: Option<&ModelFrame>,
    count: usize,
    ways: usize,
) -> Result<Vec<ModelFrame>> {
    if count == 0 {
        return Ok(Vec::new());
    }
    if cfg.resident_groups.is_empty() {
        bail!(
            "--haptic-frames needs resident groups: the configuration's `resident_groups` is empty"
        );
    }
    let Some(update) = update else {
        bail!("--haptic-frames: the scene's frame is over capacity, so no group is resident");
    };
    let streamed = Scene {
        obbs: scene
            .obbs
            .iter()
            .filter(|o| !cfg.is_resident(o.group))
            .cloned()
            .collect(),
    };
    let streamed = interleave(&streamed, ways);
    let first = update
        .haptic(&streamed)
        .context("the haptic frame does not fit the hardware configuration")?;
    Ok(vec![first; count])
}
