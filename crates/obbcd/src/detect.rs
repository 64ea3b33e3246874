//! `obbcd detect`: the colliding pairs of a scene, by a CPU engine or by the fixed-point model of
//! the core, and with `--contacts` each pair's normal and penetration depth.

use crate::builtin::scene_or_builtin;
use crate::timing::median_ms;
use anyhow::{bail, Context, Result};
use clap::Args;
use obb_model::contact::{contact, Contact};
use obb_model::fixed::accuracy::{differences, reference_pairs};
use obb_model::fixed::grid::MAX_WINDOW;
use obb_model::fixed::plan::{plan, Aims};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::{EngineKind, GroupMask, Pair, Prepared, Scene};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;

/// An engine on the command line: a CPU engine, or `model`, the bit-exact fixed-point model of
/// the core.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EngineArg {
    Cpu(EngineKind),
    Model,
}

impl FromStr for EngineArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "model" {
            return Ok(EngineArg::Model);
        }
        s.parse()
            .map(EngineArg::Cpu)
            .map_err(|e: String| format!("{e}, or model"))
    }
}

impl fmt::Display for EngineArg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EngineArg::Cpu(k) => write!(f, "{k}"),
            EngineArg::Model => write!(f, "model"),
        }
    }
}

#[derive(Args)]
pub struct DetectArgs {
    /// Scene JSON file; default: the built-in surgical scene (`obbcd scene surgical`).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// brute, sap, improved-sap, sweep, grid, or model (the fixed-point core).
    #[arg(long, default_value = "grid")]
    engine: EngineArg,
    /// Which group pairs: `all`, `cross` (different groups only) or a list like `0-1,0-2,1-2`.
    /// Default: `all`, or with `--engine model --config` the configuration's `groups`.
    #[arg(long)]
    groups: Option<GroupMask>,
    /// Hardware configuration (TOML) for `--engine model`; default: one planned for the scene
    /// (`obbcd plan`, with `--groups` and the default aims).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Run the detection N times and report the median time.
    #[arg(long, default_value_t = 1)]
    repeat: usize,
    /// Pairs JSON file to write.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Add to the pairs file each pair's contact: the unit normal of the axis of least overlap
    /// (from the first box to the second) and the penetration depth along it.
    #[arg(long, requires = "output")]
    contacts: bool,
}

/// The pairs file: `{"pairs":[[i,j], ...]}`, i < j, sorted ascending; with contacts,
/// `"contacts":[{"normal":[x,y,z],"depth":d}, ...]`, one per pair in the pairs' order.
#[derive(Serialize)]
struct PairsFile<'a> {
    pairs: &'a [Pair],
    #[serde(skip_serializing_if = "Option::is_none")]
    contacts: Option<&'a [Contact]>,
}

/// Writes a pairs file.
pub fn write_pairs(path: &Path, pairs: &[Pair], contacts: Option<&[Contact]>) -> Result<()> {
    let json = serde_json::to_string(&PairsFile { pairs, contacts })?;
    std::fs::write(path, json).with_context(|| format!("cannot write {}", path.display()))
}

/// The configuration for the model: the file, or the defaults.
pub fn load_config(path: Option<&Path>) -> Result<HwConfig> {
    Ok(match path {
        Some(p) => HwConfig::load(p)?,
        None => HwConfig::default(),
    })
}

pub fn run(a: DetectArgs) -> Result<()> {
    if a.config.is_some() && a.engine != EngineArg::Model {
        bail!("--config applies to --engine model only");
    }
    let scene = scene_or_builtin(a.scene.as_deref())?;
    let pairs = match a.engine {
        EngineArg::Cpu(kind) => run_cpu(&a, &scene, kind)?,
        EngineArg::Model => run_model(&a, &scene)?,
    };
    println!("{}", by_group_pair(&scene, &pairs));
    let contacts = a.contacts.then(|| contacts_of(&scene, &pairs));
    if let Some(path) = &a.output {
        write_pairs(path, &pairs, contacts.as_deref())?;
    }
    if a.scene.is_none() {
        eprintln!(
            "next: `obbcd detect --engine model` runs the frame through the bit-exact model of \
             the hardware core; `obbcd cosim` through its Verilog in Verilator (the core's \
             default mask, cross-group)"
        );
    }
    Ok(())
}

/// Each pair's contact, on the worker threads, timed apart from the detection; prints
/// `contacts=N max_depth=D contacts_ms=T`.
fn contacts_of(scene: &Scene, pairs: &[Pair]) -> Vec<Contact> {
    let start = Instant::now();
    let contacts: Vec<Contact> = pairs
        .par_iter()
        .map(|&[i, j]| contact(&scene.obbs[i as usize], &scene.obbs[j as usize]))
        .collect();
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let deepest = contacts.iter().map(|c| c.depth).fold(0.0, f64::max);
    println!(
        "contacts={} max_depth={deepest:.6} contacts_ms={ms:.3}",
        contacts.len()
    );
    contacts
}

/// The pairs counted by the groups of their boxes: `pairs_by_groups 0-0=.. 0-1=..`, every
/// group pair that has a pair, in order.
fn by_group_pair(scene: &Scene, pairs: &[Pair]) -> String {
    let mut counts = BTreeMap::<(u32, u32), usize>::new();
    for &[i, j] in pairs {
        let (g, h) = (scene.obbs[i as usize].group, scene.obbs[j as usize].group);
        *counts.entry((g.min(h), g.max(h))).or_default() += 1;
    }
    let mut line = String::from("pairs_by_groups");
    for ((g, h), n) in counts {
        line += &format!(" {g}-{h}={n}");
    }
    line
}

fn run_cpu(a: &DetectArgs, scene: &Scene, kind: EngineKind) -> Result<Vec<Pair>> {
    let mask = a.groups.clone().unwrap_or_default();
    let mut engine = kind.build();
    let mut boxes = Prepared::default();
    let mut pairs = Vec::new();
    // Timed: the per-frame work (AABBs, SAT slack, broad and narrow phase), scene already loaded.
    // The loop runs on a pool worker, as a real-time loop should: a call from outside the pool
    // pays a thread wake-up per parallel phase (README, "Measured figures").
    let (ms, counters) = rayon::scope(|_| {
        median_ms(a.repeat, || {
            let frame = boxes.update(&scene.obbs);
            engine.detect(&frame, &mask, &mut pairs)
        })
    });
    println!(
        "engine={kind} obbs={} groups={mask} visits={} sat_tests={} pairs={} time_ms={ms:.3} threads={}",
        scene.obbs.len(),
        counters.visits,
        counters.sat_tests,
        counters.pairs,
        rayon::current_num_threads()
    );
    Ok(pairs)
}

/// The model's configuration: the file (its mask replaced by `--groups`), or a plan for the
/// scene, which every scene the CPU engines take fits.
fn model_config(a: &DetectArgs, scene: &Scene) -> Result<HwConfig> {
    let Some(path) = &a.config else {
        let aims = Aims {
            groups: a.groups.clone().unwrap_or_default(),
            ..Aims::default()
        };
        let plan = plan(std::slice::from_ref(scene), &aims)
            .context("cannot plan a configuration for the scene")?;
        eprintln!(
            "planned for the scene (obbcd plan writes it; --config takes a file): {}",
            plan.summary()
        );
        for aim in &plan.unmet {
            eprintln!("warning: aim not met: {aim}");
        }
        return Ok(plan.cfg);
    };
    let mut cfg = HwConfig::load(path)?;
    if let Some(mask) = &a.groups {
        cfg.groups = mask.clone();
    }
    Ok(cfg)
}

fn run_model(a: &DetectArgs, scene: &Scene) -> Result<Vec<Pair>> {
    let cfg = model_config(a, scene)?;
    let frame = ModelFrame::new(scene, &cfg)
        .context("the scene does not fit the hardware configuration")?;
    let (ms, run) = median_ms(a.repeat, || frame.run());
    if run.work.incomplete {
        bail!(
            "a box spans more than {} grid cells of {} mm on an axis, a window the grid's slow \
             path does not read: the frame is incomplete (the core flags capacity_exceeded); a \
             larger `grid_cell_mm` takes the box",
            MAX_WINDOW - 1,
            cfg.grid_cell_mm
        );
    }
    let reference = reference_pairs(scene, &cfg.groups);
    let (fp, missed) = differences(&run.pairs, &reference);
    let c = run.counters();
    println!(
        "engine=model obbs={} groups={} broad_phase={} visits={} sat_tests={} pairs={} \
         false_positives={} false_negatives={} cycles={} time_ms={ms:.3}",
        scene.obbs.len(),
        cfg.groups,
        cfg.broad_phase,
        c.visits,
        c.sat_tests,
        c.pairs,
        fp.len(),
        missed.len(),
        run.cycles.total,
    );
    if let Some(p) = missed.first() {
        bail!(
            "the model missed {} pair(s) the f64 reference reports, first {p:?}: this is a bug",
            missed.len()
        );
    }
    Ok(run.pairs)
}
