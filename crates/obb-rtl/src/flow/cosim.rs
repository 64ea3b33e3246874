//! Co-simulation of the emitted core on whole scenes: the hand-written test bench
//! `sim/tb_obb_core.v` streams a scene's quantized boxes into `obb_core`, takes the pair stream
//! (optionally throttled) and the status counters, and writes them to a file; this module
//! builds it in Verilator or Icarus (once per design: builds are cached), runs it, reads the
//! result and compares it with the bit-exact model. `obbcd cosim` is its command line.

use crate::flow::cache;
use crate::flow::verilator::{binary_flags, hex_word, output, Runs, Simulator, Warnings};
use crate::flow::waves::{Trace, WaveFormat, Waves};
use anyhow::{bail, Context, Result};
use obb_model::fixed::{quantize, BroadPhase, HwConfig, ModelFrame, ModelRun, QObb, QuantizeError};
use obb_model::{Pair, Scene};
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The test bench, compiled into the binary so that `obbcd` runs anywhere.
pub const TESTBENCH: &str = include_str!("../../../../sim/tb_obb_core.v");

/// The model's frame for `scene` and the boxes to stream. A scene over capacity has no model
/// frame; its boxes are quantized anyway, for the core must see them to flag the frame.
pub fn prepare(
    scene: &Scene,
    cfg: &HwConfig,
) -> Result<(Option<ModelFrame>, Vec<QObb>), QuantizeError> {
    match ModelFrame::new(scene, cfg) {
        Ok(m) => {
            let boxes = m.obbs.clone();
            Ok((Some(m), boxes))
        }
        Err(QuantizeError::Capacity { .. }) => {
            let roomy = HwConfig {
                capacity: 1 << 20,
                ..cfg.clone()
            };
            Ok((None, quantize(scene, &roomy)?))
        }
        Err(e) => Err(e),
    }
}

/// The clocks a frame of `scene` takes: the model's, or for a frame over capacity a bound: the
/// core runs its broad phase on the boxes it took (the first `capacity`; no pair leaves, so
/// back-pressure does not slow it), which the model's frame of those boxes counts, and passes
/// over one box a clock after.
pub fn frame_clocks(scene: &Scene, cfg: &HwConfig, run: Option<&ModelRun>) -> Result<u64> {
    Ok(match run {
        Some(r) => r.cycles.total,
        None => taken_run(scene, cfg)?.cycles.total + scene.obbs.len() as u64,
    })
}

/// The model's frame of the boxes a frame over capacity keeps: its first `capacity`.
pub fn kept_frame(scene: &Scene, cfg: &HwConfig) -> Result<ModelFrame> {
    let took = (cfg.capacity as usize).min(scene.obbs.len());
    let first = Scene {
        obbs: scene.obbs[..took].to_vec(),
    };
    Ok(ModelFrame::new(&first, cfg)?)
}

/// The model's run of `kept_frame`.
pub fn taken_run(scene: &Scene, cfg: &HwConfig) -> Result<ModelRun> {
    Ok(kept_frame(scene, cfg)?.run())
}

/// The values of the box input ports for one box, in the test bench's word order (lowest bits
/// first): `obb_center[0..3]` (offset binary), `obb_half[0..3]`, `obb_axes[0..9]` (two's
/// complement, row-major), `obb_group`.
pub fn box_ports(b: &QObb, cfg: &HwConfig) -> [(u64, usize); 16] {
    use crate::projection::{CENTER, HALF, ROT};
    let offset = 1i64 << (cfg.center_bits - 1);
    let mut w = [(0, 0); 16];
    for x in 0..3 {
        w[x] = ((b.center[x] + offset) as u64, CENTER);
        w[3 + x] = (b.half[x] as u64, HALF);
    }
    for k in 0..9 {
        w[6 + k] = (b.axes[k / 3][k % 3] as u64 & ((1 << ROT) - 1), ROT);
    }
    w[15] = (
        u64::from(b.group),
        obb_model::fixed::config::GROUP_BITS as usize,
    );
    w
}

/// One box as the test bench reads it: the ports packed into one hex word.
pub fn box_word(b: &QObb, cfg: &HwConfig) -> String {
    hex_word(&box_ports(b, cfg))
}

/// One frame for the test bench: whether it is an update frame (`frame_update`; a frame of
/// a configuration without resident groups is one), and its boxes.
pub type BenchFrame<'a> = (bool, &'a [QObb]);

/// The stimulus file: per frame a line `UPDATE N`, then its N boxes, one per line.
pub fn stimulus(frames: &[BenchFrame], cfg: &HwConfig) -> String {
    let mut text = String::new();
    for &(update, obbs) in frames {
        text += &format!("{} {}\n", u8::from(update), obbs.len());
        text.extend(obbs.iter().map(|b| box_word(b, cfg) + "\n"));
    }
    text
}

/// Which Verilog of the core is simulated: the emitted RTL, or the yosys netlist of it
/// (Xilinx primitives, simulated with yosys' `cells_sim.v`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    Rtl,
    Gates,
}

/// A built test bench, in the cache.
#[derive(Debug)]
pub struct Bench {
    dir: PathBuf,
    sim: Simulator,
    /// Whether the build was found in the cache.
    pub cached: bool,
}

/// yosys' simulation models of the Xilinx primitives, for gate-level runs: in the `share`
/// directory beside the `yosys` found on `PATH` (Debian's `yosys-config` is in a separate
/// package).
pub fn cells_sim() -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let bin = std::env::split_paths(&path)
        .map(|d| d.join("yosys"))
        .find(|p| p.is_file())
        .context("yosys is not on PATH (scripts/test.sh installs it)")?;
    let share = bin
        .parent()
        .and_then(Path::parent)
        .map(|p| p.join("share/yosys/xilinx/cells_sim.v"))
        .context("no directory above yosys")?;
    if !share.is_file() {
        bail!("{} is missing: yosys is incomplete", share.display());
    }
    Ok(share)
}

/// Builds the test bench around `design` (the core's Verilog, or its netlist) in `sim`, with
/// waves if `trace` is given; reuses a build of the same sources, simulator version and options
/// from `cache`.
pub fn build(
    design: &str,
    level: Level,
    sim: Simulator,
    trace: Option<Trace>,
    cache: &Path,
) -> Result<Bench> {
    let version = match sim {
        Simulator::Verilator => output(Command::new("verilator").arg("--version"), "verilator")?,
        Simulator::Icarus => output(Command::new("iverilog").arg("-V"), "iverilog")?,
    };
    let cells = match level {
        Level::Rtl => String::new(),
        Level::Gates => std::fs::read_to_string(cells_sim()?)?,
    };
    let flags = compile_flags(sim, level, trace);
    let options = format!("{level:?} {}", flags.join(" "));
    let parts = [TESTBENCH, design, &cells, &version, &options].map(str::as_bytes);
    let name = format!(
        "{sim:?}-{level:?}{}-{}",
        if trace.is_some() { "-trace" } else { "" },
        cache::key(&parts)
    )
    .to_lowercase();
    let (dir, cached) = cache::entry(cache, &name, |work| {
        std::fs::write(work.join("tb.v"), TESTBENCH)?;
        std::fs::write(work.join("core.v"), design)?;
        let mut sources = vec!["tb.v", "core.v"];
        if level == Level::Gates {
            std::fs::write(work.join("cells_sim.v"), &cells)?;
            sources.push("cells_sim.v");
        }
        compile(work, sim, &flags, &sources)
    })?;
    Ok(Bench { dir, sim, cached })
}

/// The simulator's flags for a build, all of them part of the build's cache key (a changed flag
/// must not reuse a stale build).
fn compile_flags(sim: Simulator, level: Level, trace: Option<Trace>) -> Vec<String> {
    let mut flags = Vec::new();
    match sim {
        Simulator::Verilator => {
            // A netlist runs only small scenes, and its C++ is large (38 MB for a small sweep
            // core): compiled at `-O0`. The RTL runs whole scenes.
            match level {
                Level::Rtl => flags.extend(binary_flags(Runs::Long, Warnings::Printed)),
                Level::Gates => {
                    flags.extend(binary_flags(Runs::Short, Warnings::Printed));
                    flags.extend(["-Wno-lint", "-Wno-style"].map(String::from));
                }
            }
            if let Some(t) = trace {
                flags.push(match t.format {
                    WaveFormat::Vcd => "--trace".into(),
                    WaveFormat::Fst => "--trace-fst".into(),
                });
                if t.depth > 0 {
                    flags.extend(["--trace-depth".into(), t.depth.to_string()]);
                }
            }
        }
        Simulator::Icarus => flags.extend(["-g2012", "-s", "tb", "-o", "tb.vvp"].map(String::from)),
    }
    flags
}

fn compile(work: &Path, sim: Simulator, flags: &[String], sources: &[&str]) -> Result<()> {
    match sim {
        Simulator::Verilator => {
            // `flags` begins with `binary_flags`.
            let mut cmd = Command::new("verilator");
            cmd.current_dir(work).args(flags).args(sources);
            output(&mut cmd, "verilator (build)")?;
        }
        Simulator::Icarus => {
            output(
                Command::new("iverilog")
                    .current_dir(work)
                    .args(flags)
                    .args(sources),
                "iverilog (build)",
            )?;
        }
    }
    Ok(())
}

/// How the test bench runs a frame.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// `pair_ready` is high one clock in this many (1: always).
    pub ready_every: u32,
    /// Clocks without `done` after which the run fails.
    pub timeout: u64,
    /// Clocks between progress reports (0: none).
    pub progress_every: u64,
    /// Abort each frame once at this clock of it, if it has not finished, and send it again
    /// (0: never).
    pub abort_at: u64,
}

impl Default for RunOptions {
    fn default() -> RunOptions {
        RunOptions {
            ready_every: 1,
            timeout: 1 << 40,
            progress_every: 0,
            abort_at: 0,
        }
    }
}

/// What the simulated core gave for one frame (of a run of several back to back).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SimFrame {
    /// The pairs taken from the stream, in order.
    pub stream: Vec<Pair>,
    /// Clocks from `frame_start` until `done` was seen.
    pub clocks: u64,
    /// The `cycles` output at `done`.
    pub cycles: u64,
    /// The `visits` output at `done`.
    pub visits: u64,
    /// The `sat_tests` output at `done`.
    pub sat_tests: u64,
    /// The `pairs` output at `done`.
    pub pairs: u64,
    /// The `capacity_exceeded` output at `done`.
    pub capacity_exceeded: bool,
    /// The `pair_overflow` output at `done`.
    pub pair_overflow: bool,
    /// Aborted once (`RunOptions::abort_at`): the pairs taken before the abort. `stream` and
    /// the rest are the frame's as sent again.
    pub before_abort: Option<Vec<Pair>>,
}

impl Bench {
    /// Runs the `frames` frames of the stimulus file `stim` (`stimulus`) back to back; calls
    /// `progress` with the frame's clock count as the simulation reports it.
    pub fn run(
        &self,
        stim: &Path,
        frames: usize,
        opts: &RunOptions,
        progress: impl FnMut(u64),
    ) -> Result<Vec<SimFrame>> {
        let (out, errors) = self.simulate(stim, frames, opts, &[], progress)?;
        let text = std::fs::read_to_string(&out)
            .with_context(|| format!("the simulation wrote no {}:\n{errors}", out.display()))?;
        let got = parse_result(&text).with_context(|| format!("in {}", out.display()))?;
        if got.len() != frames {
            bail!(
                "{}: {} of the {frames} frames finished",
                out.display(),
                got.len()
            );
        }
        Ok(got)
    }

    /// Runs the stimulus again on a traced build (`build` with `waves.trace()`), recording
    /// `waves`; the run ends at the window's end, so its result is not compared.
    pub fn record(
        &self,
        stim: &Path,
        frames: usize,
        opts: &RunOptions,
        waves: &Waves,
        progress: impl FnMut(u64),
    ) -> Result<()> {
        let mut args = waves.plusargs()?;
        if self.sim == Simulator::Icarus && waves.format == WaveFormat::Fst {
            // vvp's own flag (before the plusargs) selects FST for `$dumpfile`.
            args.insert(0, "-fst".into());
        }
        let _ = std::fs::remove_file(&waves.path);
        self.simulate(stim, frames, opts, &args, progress)?;
        if !waves.path.is_file() {
            bail!(
                "the simulation wrote no {} (is the window past the run's end?)",
                waves.path.display()
            );
        }
        Ok(())
    }

    /// Runs the test bench on `stim` with `extra` arguments; calls `progress` with the clocks
    /// the simulation reports; fails with what it said if it fails. Returns the result file it
    /// was told to write (beside `stim`) and what it said.
    fn simulate(
        &self,
        stim: &Path,
        frames: usize,
        opts: &RunOptions,
        extra: &[String],
        mut progress: impl FnMut(u64),
    ) -> Result<(PathBuf, String)> {
        let stim = std::path::absolute(stim)?;
        let out = stim.with_extension("out");
        let mut cmd = match self.sim {
            Simulator::Verilator => Command::new(self.dir.join("obj/Vtb")),
            Simulator::Icarus => {
                let mut c = Command::new("vvp");
                c.arg("-n").arg(self.dir.join("tb.vvp"));
                c
            }
        };
        let _ = std::fs::remove_file(&out);
        let mut child = cmd
            .args(extra)
            .arg(format!("+stim={}", stim.display()))
            .arg(format!("+out={}", out.display()))
            .arg(format!("+frames={frames}"))
            .arg(format!("+ready={}", opts.ready_every))
            .arg(format!("+timeout={}", opts.timeout))
            .arg(format!("+progress={}", opts.progress_every))
            .arg(format!("+abort={}", opts.abort_at))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("cannot start the {:?} simulation", self.sim))?;
        let mut stderr = child.stderr.take().expect("piped");
        let errors = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = stderr.read_to_string(&mut s);
            s
        });
        let mut said = Vec::new();
        for line in BufReader::new(child.stdout.take().expect("piped")).lines() {
            let line = line?;
            match line.strip_prefix("progress ").map(str::parse) {
                Some(Ok(clock)) => progress(clock),
                _ => said.push(line),
            }
        }
        let status = child.wait()?;
        let errors = errors.join().unwrap_or_default();
        if !status.success() {
            bail!(
                "the {:?} simulation failed ({status}):\n{}\n{errors}",
                self.sim,
                said.join("\n")
            );
        }
        Ok((out, said.join("\n") + "\n" + &errors))
    }
}

/// Reads the test bench's result file: the frames that finished.
fn parse_result(text: &str) -> Result<Vec<SimFrame>> {
    let mut frames = Vec::new();
    let mut stream = Vec::new();
    let mut before_abort = None;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let tag = words.next();
        let nums: Vec<u64> = words
            .map(|w| w.parse().with_context(|| format!("bad line `{line}`")))
            .collect::<Result<_>>()?;
        match (tag, nums.as_slice()) {
            (Some("pair"), &[a, b]) => stream.push([a as u32, b as u32]),
            (Some("abort"), &[]) if before_abort.is_none() => {
                before_abort = Some(std::mem::take(&mut stream))
            }
            (Some("done"), &[clocks, cycles, visits, sat_tests, pairs, over, lost]) => {
                frames.push(SimFrame {
                    stream: std::mem::take(&mut stream),
                    clocks,
                    cycles,
                    visits,
                    sat_tests,
                    pairs,
                    capacity_exceeded: over == 1,
                    pair_overflow: lost == 1,
                    before_abort: before_abort.take(),
                })
            }
            _ => bail!("bad line `{line}`"),
        }
    }
    Ok(frames)
}

/// The model's verdict on a frame whose boxes all fit, or the capacity error for one that does
/// not.
pub enum Expected<'a> {
    Frame(&'a ModelRun),
    /// Over capacity, but for the grid: the flag, and no pair (the other broad phases start
    /// once every box is in).
    OverCapacity,
    /// The frame is incomplete, and the core flags it; the pairs it sent before are some of
    /// this run's. The grid met a large box whose window spans more than `grid::MAX_WINDOW`
    /// cells on an axis, which its slow path does not read; or the grid's frame is over
    /// capacity, and the run is of the boxes it kept (`taken_run`): it walks them as they
    /// arrive, and sends their pairs until the box over capacity.
    Incomplete(&'a ModelRun),
}

impl<'a> Expected<'a> {
    /// What the core must give for the model's run of a frame whose boxes fit.
    pub fn of(run: &'a ModelRun) -> Expected<'a> {
        match run.work.incomplete {
            true => Expected::Incomplete(run),
            false => Expected::Frame(run),
        }
    }

    /// What the core for `cfg` must give for a frame of `scene` whose model run is `run`
    /// (`None`: over capacity). The grid's frame over capacity is judged against the run of
    /// the boxes it kept (`taken_run`), which `kept` holds.
    pub fn for_frame(
        run: Option<&'a ModelRun>,
        kept: &'a mut Option<ModelRun>,
        scene: &Scene,
        cfg: &HwConfig,
    ) -> Result<Expected<'a>> {
        Ok(match run {
            Some(run) => Expected::of(run),
            None if cfg.broad_phase == BroadPhase::Grid => {
                Expected::Incomplete(kept.insert(taken_run(scene, cfg)?))
            }
            None => Expected::OverCapacity,
        })
    }
}

/// How the pair stream was taken, and so what of the model's run it must show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Taken {
    /// On every clock: the model's pairs in the model's order, in the model's cycles.
    Freely,
    /// Throttled, one walker lane: the model's order, in more cycles (the stream stalls the
    /// broad phase).
    Throttled,
    /// Throttled, several grid walker lanes: the model's pairs with their repeats, in more
    /// cycles, but their order may differ: the lowest lane with a SAT test issues it, and a
    /// stall changes which lanes hold one when the issue resumes.
    ThrottledLanes,
}

impl Taken {
    /// The pair stream taken one clock in `ready_every`, with `lanes` walker lanes.
    pub fn of(ready_every: u32, lanes: u32) -> Taken {
        match ready_every > 1 {
            false => Taken::Freely,
            true => Taken::throttled(lanes),
        }
    }

    /// The pair stream taken on some clocks only (any pattern), with `lanes` walker lanes.
    pub fn throttled(lanes: u32) -> Taken {
        match lanes > 1 {
            false => Taken::Throttled,
            true => Taken::ThrottledLanes,
        }
    }
}

/// Compares a simulated frame with the model: the pair stream (in order unless `taken` says
/// otherwise), the counters, and (with the pair stream never throttled) the cycle count; `done`
/// within three clocks of it. Over capacity: the flag, and no pair. Incomplete (and the grid
/// over capacity): the flag, and only the model's pairs. A frame showing `pair_overflow` fails;
/// an aborted one's pairs before the abort must be the model's. Returns the first difference.
pub fn compare(got: &SimFrame, want: &Expected, taken: Taken) -> Result<(), String> {
    let throttled = taken != Taken::Freely;
    if got.pair_overflow {
        return Err("pair_overflow is high: a pair or a SAT test was lost to a full queue".into());
    }
    // An aborted frame offers only its own true pairs before the abort; the frame sent again
    // is judged whole below.
    if let Some(before) = &got.before_abort {
        let known = match want {
            Expected::Frame(run) | Expected::Incomplete(run) => &run.pairs[..],
            Expected::OverCapacity => &[],
        };
        // (`ModelRun::pairs` is sorted.)
        if let Some(p) = before.iter().find(|p| known.binary_search(p).is_err()) {
            return Err(format!(
                "before the abort the core sent {p:?}, which the model does not report"
            ));
        }
    }
    let run = match want {
        Expected::Incomplete(run) => {
            if !got.capacity_exceeded {
                return Err(
                    "the frame is incomplete (over capacity, or a large box's window \
                            too wide for the grid), but capacity_exceeded is low"
                        .into(),
                );
            }
            if let Some(p) = got.stream.iter().find(|p| !run.pairs.contains(p)) {
                return Err(format!(
                    "the core sent {p:?}, which the model does not report"
                ));
            }
            return match got.pairs == got.stream.len() as u64 {
                true => Ok(()),
                false => Err(format!(
                    "the core sent {} pairs and counted {}",
                    got.stream.len(),
                    got.pairs
                )),
            };
        }
        Expected::OverCapacity => {
            if !got.capacity_exceeded {
                return Err("over capacity, but capacity_exceeded is low".into());
            }
            if let Some(p) = got.stream.first() {
                return Err(format!(
                    "over capacity, but the core sent {} pair(s), first {p:?}",
                    got.stream.len()
                ));
            }
            let counters = [got.visits, got.sat_tests, got.pairs];
            return match counters {
                [0, 0, 0] => Ok(()),
                c => Err(format!(
                    "over capacity, but the counters (visits, sat_tests, pairs) are {c:?}"
                )),
            };
        }
        Expected::Frame(run) => run,
    };
    if got.capacity_exceeded {
        return Err("capacity_exceeded is high, but the boxes fit".into());
    }
    let (mut core, mut model) = (got.stream.clone(), run.stream.clone());
    let what = match taken {
        Taken::ThrottledLanes => {
            core.sort_unstable();
            model.sort_unstable();
            "sorted stream"
        }
        Taken::Freely | Taken::Throttled => "stream",
    };
    if let Some(k) = (0..core.len().max(model.len())).find(|&k| core.get(k) != model.get(k)) {
        return Err(format!(
            "pair {k} of the {what}: core {:?}, model {:?} ({} and {} pairs in all)",
            core.get(k),
            model.get(k),
            core.len(),
            model.len()
        ));
    }
    let c = run.counters();
    let counters = [
        ("visits", got.visits, c.visits),
        ("sat_tests", got.sat_tests, c.sat_tests),
        ("pairs", got.pairs, run.reported()),
    ];
    for (name, core, model) in counters {
        if core != model {
            return Err(format!("counter {name}: core {core}, model {model}"));
        }
    }
    let total = run.cycles.total;
    if throttled {
        // A throttled stream stalls the broad phase: never fewer clocks than the model.
        if got.cycles < total {
            return Err(format!(
                "cycles: core {}, model at least {total}",
                got.cycles
            ));
        }
    } else if got.cycles != total {
        return Err(format!(
            "cycles: core {}, model {total} ({:?})",
            got.cycles, run.cycles
        ));
    }
    // `done` waits for the last pair to leave: with the stream throttled, that may be long
    // after the last verdict.
    // (After an abort, the clocks count from the abort: the old frame runs out first.)
    let late = got.clocks.saturating_sub(got.cycles);
    let patient = throttled || got.before_abort.is_some();
    if got.clocks < got.cycles || (!patient && late > 3) {
        return Err(format!(
            "done came {} clocks after frame_start, for {} cycles",
            got.clocks, got.cycles
        ));
    }
    Ok(())
}
