//! `obbcd error`: error against run time, the paper's Figure 9 with the error added. For each
//! data width and each broad phase: the model's false positives and false negatives (which must
//! be 0) against the f64 reference, the worst AABB inflation, the clocks per frame, the
//! estimated period of that core (from a cached synthesis, else the configuration's
//! `clock_ns`, and the table says which), the frame time and rate, and whether the point is on
//! the Pareto front of frame time and false-positive rate.

use crate::detect::load_config;
use crate::error_plot;
use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use obb_model::fixed::accuracy::{
    at_width, differences, false_positive_rate, reference_pairs, worst_inflation_um, MAX_WIDTH,
    MIN_WIDTH,
};
use obb_model::fixed::grid::MAX_WINDOW;
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame};
use obb_model::Scene;
use obb_rtl::flow::{cache, generate, synth};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ErrorArgs {
    /// Scene JSON file.
    #[arg(long)]
    scene: PathBuf,
    /// Base hardware configuration (TOML); each row replaces its widths and broad phase and
    /// fits the LSB to the scene. Default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Widths to try: `a..b` (inclusive) or a list `12,16,20`; each from 8 to 23.
    #[arg(long, default_value = "12..23")]
    widths: String,
    /// Broad phases to try, a list such as `grid,sweep` (default: all four).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "grid,sweep,improved-sap,brute"
    )]
    broad_phases: Vec<BroadPhase>,
    /// Synthesize the cores that have no cached synthesis for their period (yosys: minutes for
    /// a sweep core, about half an hour for a grid core). Without it those rows take
    /// `clock_ns`.
    #[arg(long)]
    synth: bool,
    /// Cache of netlists and their periods (default: $OBBCD_CACHE, else ~/.cache/obbcd), as
    /// `obbcd synth`'s.
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Also write the table as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Also plot the false-positive rate against the frame time, Pareto front marked (SVG).
    #[arg(long)]
    svg: Option<PathBuf>,
}

/// Parses `a..b` (inclusive) or `a,b,c`.
fn parse_widths(s: &str) -> Result<Vec<u32>> {
    let widths: Vec<u32> = if let Some((a, b)) = s.split_once("..") {
        let a: u32 = a
            .trim()
            .parse()
            .with_context(|| format!("width `{a}` in `{s}`"))?;
        let b: u32 = b
            .trim()
            .parse()
            .with_context(|| format!("width `{b}` in `{s}`"))?;
        if a > b {
            bail!("widths `{s}`: {a} is above {b}");
        }
        (a..=b).collect()
    } else {
        s.split(',')
            .map(|w| {
                w.trim()
                    .parse()
                    .with_context(|| format!("width `{w}` in `{s}`"))
            })
            .collect::<Result<_>>()?
    };
    if let Some(w) = widths
        .iter()
        .find(|w| !(MIN_WIDTH..=MAX_WIDTH).contains(*w))
    {
        bail!(
            "width {w} is not supported: widths run from {MIN_WIDTH} to {MAX_WIDTH} (above 23 bits \
             the SAT's T·a operand no longer fits one DSP48E1 port)"
        );
    }
    Ok(widths)
}

/// Where a row's period comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeriodFrom {
    /// The synthesis estimate of exactly this core (`obbcd synth`'s delay model).
    Synthesis,
    /// No synthesis of this core: the configuration's `clock_ns`.
    ClockNs,
}

impl std::fmt::Display for PeriodFrom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PeriodFrom::Synthesis => "synthesis",
            PeriodFrom::ClockNs => "clock_ns",
        })
    }
}

/// One configuration's accuracy and run time on the scene.
#[derive(Clone, Debug)]
pub struct Row {
    pub width: u32,
    pub broad_phase: BroadPhase,
    pub lsb_um: f64,
    pub pairs: usize,
    pub false_positives: usize,
    pub false_negatives: usize,
    pub inflation_um: f64,
    pub clocks: u64,
    pub period_ns: f64,
    pub period_from: PeriodFrom,
    pub pareto: bool,
}

impl Row {
    pub fn fp_rate(&self) -> f64 {
        false_positive_rate(self.false_positives, self.pairs)
    }

    pub fn frame_ms(&self) -> f64 {
        self.clocks as f64 * self.period_ns * 1e-6
    }

    pub fn rate_hz(&self) -> f64 {
        1e3 / self.frame_ms()
    }
}

/// Marks the rows no other row beats on both frame time and false-positive rate (a tie on one
/// and better on the other beats).
fn mark_pareto(rows: &mut [Row]) {
    for k in 0..rows.len() {
        let (t, e) = (rows[k].frame_ms(), rows[k].fp_rate());
        rows[k].pareto = !rows.iter().any(|o| {
            let (ot, oe) = (o.frame_ms(), o.fp_rate());
            ot <= t && oe <= e && (ot < t || oe < e)
        });
    }
}

/// The period of `cfg`'s core: its cached synthesis estimate (made with `synthesize`), else
/// `clock_ns`. `known` says whether any synthesis is cached at all: without one no core is
/// generated to look it up.
fn period(
    cfg: &HwConfig,
    cache: &Path,
    synthesize: bool,
    known: bool,
) -> Result<(f64, PeriodFrom)> {
    if synthesize || known {
        let verilog = generate::core(cfg)?;
        if let Some(ns) = synth::period_ns(&verilog, "obb_core", cache, synthesize)? {
            return Ok((ns, PeriodFrom::Synthesis));
        }
    }
    Ok((cfg.clock_ns, PeriodFrom::ClockNs))
}

pub fn run(a: ErrorArgs) -> Result<()> {
    let scene = Scene::load(&a.scene)?;
    let base = load_config(a.config.as_deref())?;
    let widths = parse_widths(&a.widths)?;
    let mut phases: Vec<BroadPhase> = Vec::new();
    for p in &a.broad_phases {
        if !phases.contains(p) {
            phases.push(*p);
        }
    }
    let reference = reference_pairs(&scene, &base.groups);
    let cache = a
        .cache
        .clone()
        .unwrap_or_else(cache::default_dir)
        .join("synth");
    let known = synth::has_netlists(&cache);
    println!(
        "groups={} reference_pairs={} obbs={}",
        base.groups,
        reference.len(),
        scene.obbs.len()
    );
    let bar = ProgressBar::new((widths.len() * phases.len()) as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("a valid template"),
    );
    let mut rows = Vec::new();
    let mut incomplete = Vec::new();
    for &w in &widths {
        for &broad_phase in &phases {
            bar.set_message(format!("{w} bits, {broad_phase}"));
            let lanes = if broad_phase == BroadPhase::Grid {
                base.lanes
            } else {
                1
            };
            let phase = HwConfig {
                broad_phase,
                lanes,
                ..base.clone()
            };
            let cfg = at_width(&phase, w).fitted(&scene);
            let frame = ModelFrame::new(&scene, &cfg)
                .with_context(|| format!("width {w}: the scene does not fit"))?;
            let run = frame.run();
            bar.inc(1);
            if run.work.incomplete {
                // The grid's slow path refused a window: the pairs are not the frame's.
                incomplete.push(w);
                continue;
            }
            let (fp, missed) = differences(&run.pairs, &reference);
            let (period_ns, period_from) = period(&cfg, &cache, a.synth, known)
                .with_context(|| format!("the period of the {broad_phase} core at {w} bits"))?;
            rows.push(Row {
                width: w,
                broad_phase,
                lsb_um: cfg.lsb_mm * 1e3,
                pairs: run.pairs.len(),
                false_positives: fp.len(),
                false_negatives: missed.len(),
                inflation_um: worst_inflation_um(&frame, &scene),
                clocks: run.cycles.total,
                period_ns,
                period_from,
                pareto: false,
            });
        }
    }
    bar.finish_and_clear();
    mark_pareto(&mut rows);
    print!("{}", table(&rows));
    for w in &incomplete {
        println!(
            "{w:>5}  grid         incomplete: a box spans more than {} cells of {} mm on an axis",
            MAX_WINDOW - 1,
            base.grid_cell_mm
        );
    }
    if let Some(path) = &a.csv {
        std::fs::write(path, csv(&rows))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    if let Some(path) = &a.svg {
        let title = format!(
            "{} ({} OBBs, {}): false positives against frame time",
            a.scene.file_name().unwrap_or_default().to_string_lossy(),
            scene.obbs.len(),
            base.groups
        );
        error_plot::svg(&rows, &title, path)?;
    }
    if rows.iter().any(|r| r.false_negatives > 0) {
        bail!("a configuration missed pairs the f64 reference reports: this is a bug");
    }
    Ok(())
}

/// A cell of the table: the CSV writes numbers in full, the printed table rounds them.
enum Cell {
    Int(u64),
    Real(f64, usize),
    Text(String),
}

type Column = (&'static str, usize, fn(&Row) -> Cell);

/// The columns: name, printed width, value.
const COLUMNS: [Column; 14] = [
    ("width", 5, |r| Cell::Int(r.width.into())),
    ("broad_phase", 12, |r| Cell::Text(r.broad_phase.to_string())),
    ("lsb_um", 8, |r| Cell::Real(r.lsb_um, 3)),
    ("pairs", 8, |r| Cell::Int(r.pairs as u64)),
    ("false_positives", 15, |r| {
        Cell::Int(r.false_positives as u64)
    }),
    ("fp_rate", 7, |r| Cell::Real(r.fp_rate(), 4)),
    ("false_negatives", 15, |r| {
        Cell::Int(r.false_negatives as u64)
    }),
    ("inflation_um", 12, |r| Cell::Real(r.inflation_um, 2)),
    ("clocks", 11, |r| Cell::Int(r.clocks)),
    ("period_ns", 9, |r| Cell::Real(r.period_ns, 3)),
    ("period_from", 11, |r| Cell::Text(r.period_from.to_string())),
    ("frame_ms", 10, |r| Cell::Real(r.frame_ms(), 4)),
    ("rate_hz", 10, |r| Cell::Real(r.rate_hz(), 1)),
    ("pareto", 6, |r| Cell::Text(r.pareto.to_string())),
];

/// The table as printed: one row per width and broad phase, numbers rounded, aligned.
fn table(rows: &[Row]) -> String {
    let names: Vec<String> = COLUMNS
        .iter()
        .map(|(name, width, _)| format!("{name:>w$}", w = (*width).max(name.len())))
        .collect();
    let mut out = names.join("  ") + "\n";
    for r in rows {
        let cells: Vec<String> = COLUMNS
            .iter()
            .map(|(name, width, value)| {
                let w = (*width).max(name.len());
                match value(r) {
                    Cell::Int(v) => format!("{v:>w$}"),
                    Cell::Real(v, digits) => format!("{v:>w$.digits$}"),
                    Cell::Text(t) => format!("{t:>w$}"),
                }
            })
            .collect();
        out += &(cells.join("  ") + "\n");
    }
    out
}

/// The CSV of `rows`, with a header: numbers in full.
fn csv(rows: &[Row]) -> String {
    let names: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    let mut out = names.join(",") + "\n";
    for r in rows {
        let cells: Vec<String> = COLUMNS
            .iter()
            .map(|(_, _, value)| match value(r) {
                Cell::Int(v) => v.to_string(),
                Cell::Real(v, _) => v.to_string(),
                Cell::Text(t) => t,
            })
            .collect();
        out += &(cells.join(",") + "\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of `clocks` whose false-positive rate is `tenths` / 10.
    fn row(clocks: u64, tenths: usize) -> Row {
        Row {
            width: 16,
            broad_phase: BroadPhase::Grid,
            lsb_um: 1.0,
            pairs: 10,
            false_positives: tenths,
            false_negatives: 0,
            inflation_um: 0.0,
            clocks,
            period_ns: 4.0,
            period_from: PeriodFrom::ClockNs,
            pareto: false,
        }
    }

    #[test]
    fn the_pareto_front_keeps_what_nothing_beats() {
        // (clocks, tenths of a rate): the fastest, the most accurate, one between them on the front, one
        // beaten on both, one tied on time and worse on error, and a duplicate of a front point.
        let mut rows = vec![
            row(100, 5),
            row(1000, 0),
            row(300, 1),
            row(400, 2),
            row(100, 6),
            row(300, 1),
        ];
        mark_pareto(&mut rows);
        let front: Vec<bool> = rows.iter().map(|r| r.pareto).collect();
        assert_eq!(front, [true, true, true, false, false, true]);
    }
}
