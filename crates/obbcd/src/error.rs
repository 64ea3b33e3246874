//! `obbcd error`: what each data width costs. For each width, the model's false positives and
//! false negatives (which must be 0) against the f64 reference, the worst AABB inflation, and
//! the modelled cycles per frame: the paper's Figure 9 with the error added.

use crate::detect::load_config;
use anyhow::{bail, Context, Result};
use clap::Args;
use obb_model::fixed::accuracy::{
    at_width, differences, false_positive_rate, reference_pairs, worst_inflation_um, MAX_WIDTH,
    MIN_WIDTH,
};
use obb_model::fixed::grid::MAX_WINDOW;
use obb_model::fixed::ModelFrame;
use obb_model::Scene;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Args)]
pub struct ErrorArgs {
    /// Scene JSON file.
    #[arg(long)]
    scene: PathBuf,
    /// Base hardware configuration (TOML); each width replaces its center and key widths and
    /// fits the LSB to the scene. Default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Widths to try: `a..b` (inclusive) or a list `12,16,20`; each from 8 to 23.
    #[arg(long, default_value = "12..23")]
    widths: String,
    /// Also write the table as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
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

pub fn run(a: ErrorArgs) -> Result<()> {
    let scene = Scene::load(&a.scene)?;
    let base = load_config(a.config.as_deref())?;
    let widths = parse_widths(&a.widths)?;
    let reference = reference_pairs(&scene, &base.groups);
    let mut csv = String::from(
        "width,lsb_um,pairs,false_positives,fp_rate,false_negatives,inflation_um,cycles\n",
    );
    println!(
        "groups={} broad_phase={} reference_pairs={}",
        base.groups,
        base.broad_phase,
        reference.len()
    );
    println!("width  lsb_um   pairs  false_pos  fp_rate  false_neg  inflation_um  cycles");
    let mut missed_any = false;
    for w in widths {
        let cfg = at_width(&base, w).fitted(&scene);
        let frame = ModelFrame::new(&scene, &cfg)
            .with_context(|| format!("width {w}: the scene does not fit"))?;
        let run = frame.run();
        if run.work.incomplete {
            // The grid's slow path refused a window: the pairs are not the frame's.
            println!(
                "{w:>5}  {:>6.3}  incomplete: a box spans more than {} grid cells on an axis",
                cfg.lsb_mm * 1e3,
                MAX_WINDOW - 1
            );
            continue;
        }
        let (fp, missed) = differences(&run.pairs, &reference);
        missed_any |= !missed.is_empty();
        let rate = false_positive_rate(fp.len(), run.pairs.len());
        let inflation = worst_inflation_um(&frame, &scene);
        let lsb_um = cfg.lsb_mm * 1e3;
        println!(
            "{w:>5}  {lsb_um:>6.3}  {:>6}  {:>9}  {rate:>7.4}  {:>9}  {inflation:>12.2}  {}",
            run.pairs.len(),
            fp.len(),
            missed.len(),
            run.cycles.total
        );
        writeln!(
            csv,
            "{w},{lsb_um},{},{},{rate},{},{inflation},{}",
            run.pairs.len(),
            fp.len(),
            missed.len(),
            run.cycles.total
        )?;
    }
    if let Some(path) = &a.csv {
        std::fs::write(path, csv).with_context(|| format!("cannot write {}", path.display()))?;
    }
    if missed_any {
        bail!("a width missed pairs the f64 reference reports: this is a bug");
    }
    Ok(())
}
