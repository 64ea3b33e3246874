//! `obbcd replay`: a moving scene frame by frame, as a control loop runs it, with each frame's
//! latency from its boxes to its pairs. Frames that replace the tissue (group 0) are tissue
//! updates, reported apart from the haptic frames.

use crate::builtin::DEFAULT_SEED;
use crate::capi::CapiRun;
use crate::frames::{FrameReader, FrameWriter};
use crate::neighbour::{Chased, Neighbour};
use anyhow::{bail, Context, Result};
use clap::Args;
use obb_model::engines::{Resident, RigidResident};
use obb_model::generate::{FrameUpdate, SurgicalMotion, SURGICAL_DEFAULT_N};
use obb_model::{EngineKind, GroupMask, Obb, Pair, Prepared};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The built-in run's length: one gripper cycle (2 s at 1 kHz).
const DEFAULT_FRAMES: usize = 2000;

#[derive(Args)]
pub struct ReplayArgs {
    /// Recorded frames: `.jsonl` (JSON lines) or the binary format (any other name). Default:
    /// the built-in moving surgical scene.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Frames to run (default: 2000 of the built-in scene, every frame of a file).
    #[arg(long)]
    frames: Option<usize>,
    /// Built-in scene: number of boxes.
    #[arg(long)]
    n: Option<usize>,
    /// Built-in scene: seed.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
    /// brute, sap, improved-sap, sweep or grid.
    #[arg(long, default_value = "grid")]
    engine: EngineKind,
    /// Which group pairs (`all`, `cross`, or a list like `0-1,0-2`).
    #[arg(long, default_value = "cross")]
    groups: GroupMask,
    /// Keep the tissue (group 0) resident: prepared and entered in its own grid on a tissue
    /// update only; a haptic frame prepares and probes with the other groups' boxes (grid only).
    #[arg(long)]
    resident: bool,
    /// Run the frames through the C ABI (the obbcd-capi library) as a C caller would: the
    /// tissue resident, each frame's groups set, then a detection (grid only). The time starts
    /// with the boxes already in the ABI's records.
    #[arg(long, conflicts_with = "resident")]
    capi: bool,
    /// The built-in motion's grippers as rigid bodies: their boxes given once in their own
    /// frame, a haptic frame brings only a pose per gripper; the tissue resident (grid only).
    /// Only the grippers' box clusters near the tissue or the other gripper are placed. With
    /// --capi, through the C ABI (`obbcd_set_pose`).
    #[arg(long, conflicts_with_all = ["resident", "input"])]
    rigid: bool,
    /// Write the frames run to this file (`.jsonl` or binary).
    #[arg(long)]
    record: Option<PathBuf>,
    /// Write every frame's latency and pairs (CSV).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Plot the latency over the frames (SVG).
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Beside the frames, a thread of its own reads random lines of a buffer of this many MB, as
    /// a tenant of the CPU that keeps its own lines in the shared L3 does (`bench
    /// --neighbour-mb`); the summary then gives its size and pace (`neighbour_mb=`,
    /// `neighbour_ns=`). It needs a core beside the worker threads.
    #[arg(long)]
    neighbour_mb: Option<usize>,
}

/// One frame's outcome.
struct Run {
    t_ms: f64,
    tissue: bool,
    latency_ms: f64,
    pairs: usize,
}

/// The scene's boxes as the frames leave them: by group, ascending, each group's in the order
/// its last frame gave them (so a box's index is stable while no group changes its count).
#[derive(Default)]
struct Boxes {
    all: Vec<Obb>,
    /// Each group's range in `all`, by group.
    ranges: BTreeMap<u32, Range<usize>>,
}

impl Boxes {
    /// Applies a frame: its groups' boxes replace theirs, moved straight into place when every
    /// replaced group keeps its count (the haptic frames), else the scene is laid out again.
    fn apply(&mut self, f: FrameUpdate) -> Result<()> {
        let slot = |g: u32| {
            f.replace
                .iter()
                .position(|&r| r == g)
                .with_context(|| format!("a box of group {g}, which the frame does not replace"))
        };
        let mut counts = vec![0; f.replace.len()];
        for b in &f.obbs {
            counts[slot(b.group)?] += 1;
        }
        let kept = f
            .replace
            .iter()
            .zip(&counts)
            .all(|(g, &n)| self.ranges.get(g).map(|r| r.len()) == Some(n));
        if kept {
            let mut at: Vec<usize> = f.replace.iter().map(|g| self.ranges[g].start).collect();
            for b in f.obbs {
                let k = slot(b.group)?;
                self.all[at[k]] = b;
                at[k] += 1;
            }
            return Ok(());
        }
        let mut by_group: BTreeMap<u32, Vec<Obb>> = BTreeMap::new();
        for (g, r) in &self.ranges {
            if !f.replace.contains(g) {
                by_group.insert(*g, self.all[r.clone()].to_vec());
            }
        }
        for &g in &f.replace {
            by_group.insert(g, Vec::new());
        }
        for b in f.obbs {
            by_group.entry(b.group).or_default().push(b);
        }
        self.all.clear();
        self.ranges.clear();
        for (g, boxes) in by_group {
            self.ranges
                .insert(g, self.all.len()..self.all.len() + boxes.len());
            self.all.extend(boxes);
        }
        Ok(())
    }
}

/// The frames: the file's, or the built-in motion's, one at a time.
enum Source {
    File(FrameReader),
    Builtin(SurgicalMotion, usize),
}

impl Source {
    fn next(&mut self) -> Result<Option<FrameUpdate>> {
        match self {
            Source::File(r) => r.next_frame(),
            Source::Builtin(m, k) => {
                let f = m.frame(*k);
                *k += 1;
                Ok(Some(f))
            }
        }
    }
}

pub fn run(a: ReplayArgs) -> Result<()> {
    if a.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    let (mut source, limit) = match &a.input {
        Some(path) => {
            if a.n.is_some() {
                bail!("--n is for the built-in scene, not with --input");
            }
            (Source::File(FrameReader::open(path)?), a.frames)
        }
        None => {
            let motion = SurgicalMotion::new(a.n.unwrap_or(SURGICAL_DEFAULT_N), a.seed)
                .context("cannot generate the built-in moving scene")?;
            (
                Source::Builtin(motion, 0),
                Some(a.frames.unwrap_or(DEFAULT_FRAMES)),
            )
        }
    };
    let mut record = a.record.as_deref().map(FrameWriter::create).transpose()?;
    if (a.resident || a.capi || a.rigid) && a.engine != EngineKind::Grid {
        bail!(
            "--resident, --capi and --rigid keep the tissue in a grid: they take --engine grid only"
        );
    }
    let mut resident = a.resident.then(Resident::default);
    let mut capi = if a.capi {
        Some(CapiRun::new(&a.groups, rayon::current_num_threads())?)
    } else {
        None
    };
    // With --rigid, --capi's engine runs the rigid frames.
    let mut rigid = match (&source, a.rigid) {
        (Source::Builtin(m, _), true) => Some(match capi.take() {
            None => {
                let mut r = RigidResident::default();
                r.set_bodies(&m.bodies());
                Rigid::Native(Box::new(r))
            }
            Some(mut c) => {
                let mut groups = Vec::new();
                for body in m.bodies() {
                    let g = body.first().map_or(0, |b| b.group);
                    c.stage_group(g, body.iter());
                    c.set(g)?;
                    groups.push(g);
                }
                Rigid::Capi(c, groups)
            }
        }),
        _ => None,
    };
    let mut engine = a.engine.build();
    let mut prepared = Prepared::default();
    let mut boxes = Boxes::default();
    let mut pairs: Vec<Pair> = Vec::new();
    let mut runs = Vec::new();
    let neighbour = a.neighbour_mb.map(Neighbour::beside_workers).transpose()?;
    // As `detect`: the loop runs on a pool worker, so parallel phases do not wake a thread from
    // outside the pool.
    rayon::scope(|_| -> Result<()> {
        while limit.is_none_or(|l| runs.len() < l) {
            if let (Some(r), Source::Builtin(m, k)) = (rigid.as_mut(), &mut source) {
                runs.push(rigid_frame(
                    r,
                    m,
                    *k,
                    &a.groups,
                    &mut pairs,
                    record.as_mut(),
                )?);
                *k += 1;
                continue;
            }
            let Some(frame) = source.next()? else { break };
            if let Some(w) = record.as_mut() {
                w.write(&frame)?;
            }
            let (t_ms, tissue) = (frame.t_ms, frame.replace.contains(&0));
            if let Some(c) = capi.as_mut() {
                c.stage(&frame);
            }
            let start = Instant::now();
            let found = if let Some(c) = capi.as_mut() {
                c.detect(&frame.replace)?
            } else {
                boxes.apply(frame)?;
                if let Some(r) = resident.as_mut() {
                    // Group 0 comes first: its boxes are 0..s, the moving ones after them.
                    let s = boxes.ranges.get(&0).map_or(0, |r| r.end);
                    if tissue {
                        r.update_static(&boxes.all[..s], &a.groups);
                    }
                    r.detect(&boxes.all[s..], &mut pairs);
                } else {
                    let f = prepared.update(&boxes.all);
                    engine.detect(&f, &a.groups, &mut pairs);
                }
                pairs.len()
            };
            let latency_ms = start.elapsed().as_secs_f64() * 1e3;
            runs.push(Run {
                t_ms,
                tissue,
                latency_ms,
                pairs: found,
            });
        }
        Ok(())
    })?;
    let chased = neighbour.map(Neighbour::finish).transpose()?;
    if let Some(w) = record {
        w.finish()?;
    }
    let obbs = match (&capi, &rigid) {
        (Some(c), _) | (_, Some(Rigid::Capi(c, _))) => c.len(),
        (_, Some(Rigid::Native(r))) => r.boxes(),
        _ => boxes.all.len(),
    };
    println!("{}", summary(&runs, &a, obbs, chased.as_ref()));
    if let Some(path) = &a.csv {
        std::fs::write(path, csv(&runs))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    if let Some(path) = &a.svg {
        plot(&runs, path)?;
    }
    Ok(())
}

/// Where `--rigid` runs: the engine itself, or the C ABI with the bodies' groups.
enum Rigid {
    Native(Box<RigidResident>),
    Capi(CapiRun, Vec<u32>),
}

/// Frame `k` of the built-in motion with rigid grippers: the tissue on its update frames, then
/// the grippers' poses; the time runs from the poses (and the tissue) to the pairs.
fn rigid_frame(
    rigid: &mut Rigid,
    motion: &SurgicalMotion,
    k: usize,
    mask: &GroupMask,
    pairs: &mut Vec<Pair>,
    record: Option<&mut FrameWriter>,
) -> Result<Run> {
    if let Some(w) = record {
        w.write(&motion.frame(k))?;
    }
    let tissue = motion.tissue(k);
    let poses = motion.poses(k);
    let updated = tissue.is_some();
    // (Staged before the clock starts: a C caller has the boxes in the ABI's records.)
    if let (Rigid::Capi(c, _), Some(t)) = (&mut *rigid, &tissue) {
        c.stage_group(0, t.iter());
    }
    let start = Instant::now();
    let found = match rigid {
        Rigid::Native(r) => {
            if let Some(t) = tissue {
                r.update_static(&t, mask);
            }
            r.detect(&poses, pairs);
            pairs.len()
        }
        Rigid::Capi(c, groups) => c.detect_posed(updated, groups, &poses)?,
    };
    Ok(Run {
        t_ms: motion.frame_time_ms(k),
        tissue: updated,
        latency_ms: start.elapsed().as_secs_f64() * 1e3,
        pairs: found,
    })
}

/// `frame,t_ms,tissue_update,latency_ms,pairs`, a row per frame.
fn csv(runs: &[Run]) -> String {
    let mut csv = String::from("frame,t_ms,tissue_update,latency_ms,pairs\n");
    for (k, r) in runs.iter().enumerate() {
        let _ = writeln!(
            csv,
            "{k},{},{},{:.6},{}",
            r.t_ms, r.tissue, r.latency_ms, r.pairs
        );
    }
    csv
}

/// The `p`-th percentile (nearest rank) of `v`, 0 for no values.
fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => 0.0,
        n => v[((p * n as f64).ceil() as usize).clamp(1, n) - 1],
    }
}

fn summary(runs: &[Run], a: &ReplayArgs, obbs: usize, neighbour: Option<&Chased>) -> String {
    let mut haptic: Vec<f64> = runs
        .iter()
        .filter(|r| !r.tissue)
        .map(|r| r.latency_ms)
        .collect();
    let mut tissue: Vec<f64> = runs
        .iter()
        .filter(|r| r.tissue)
        .map(|r| r.latency_ms)
        .collect();
    let pairs_max = runs.iter().map(|r| r.pairs).max().unwrap_or(0);
    let pairs_mean = runs.iter().map(|r| r.pairs).sum::<usize>() as f64 / runs.len().max(1) as f64;
    format!(
        "frames={} haptic_frames={} tissue_updates={} p50_ms={:.4} p99_ms={:.4} max_ms={:.4} \
         tissue_p99_ms={:.4} tissue_max_ms={:.4} pairs_mean={pairs_mean:.1} pairs_max={pairs_max} \
         engine={}{}{}{} groups={} obbs={obbs} threads={}{}",
        runs.len(),
        haptic.len(),
        tissue.len(),
        percentile(&mut haptic, 0.5),
        percentile(&mut haptic, 0.99),
        percentile(&mut haptic, 1.0),
        percentile(&mut tissue, 0.99),
        percentile(&mut tissue, 1.0),
        a.engine,
        if a.resident || a.capi || a.rigid {
            " resident=0"
        } else {
            ""
        },
        if a.capi { " capi=1" } else { "" },
        if a.rigid { " rigid=1" } else { "" },
        a.groups,
        rayon::current_num_threads(),
        neighbour.map_or(String::new(), |c| format!(
            " neighbour_mb={} neighbour_ns={:.1}",
            c.mb,
            c.ns_per_load()
        ))
    )
}

/// Latency over the frames' times: haptic frames as a line, tissue updates as points.
fn plot(runs: &[Run], path: &Path) -> Result<()> {
    let t_end = runs.last().map_or(1.0, |r| r.t_ms).max(1.0);
    let worst = runs.iter().map(|r| r.latency_ms).fold(0.01, f64::max);
    let root = SVGBackend::new(path, (1000, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("obbcd replay: latency per frame", ("sans-serif", 18))
        .margin(20)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_end, 0.0..worst * 1.1)?;
    chart
        .configure_mesh()
        .x_desc("frame time (ms)")
        .y_desc("latency (ms)")
        .draw()?;
    let haptic = runs.iter().filter(|r| !r.tissue);
    chart
        .draw_series(LineSeries::new(
            haptic.map(|r| (r.t_ms, r.latency_ms)),
            BLUE.stroke_width(1),
        ))?
        .label("haptic frames")
        .legend(|(x, y)| PathElement::new(vec![(x - 10, y), (x + 10, y)], BLUE));
    chart
        .draw_series(
            runs.iter()
                .filter(|r| r.tissue)
                .map(|r| Circle::new((r.t_ms, r.latency_ms), 3, RED.filled())),
        )?
        .label("tissue updates")
        .legend(|(x, y)| Circle::new((x, y), 3, RED.filled()));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::percentile;

    #[test]
    fn percentiles_are_nearest_rank() {
        let mut v: Vec<f64> = (1..=200).rev().map(f64::from).collect();
        assert_eq!(percentile(&mut v, 0.5), 100.0);
        assert_eq!(percentile(&mut v, 0.99), 198.0);
        assert_eq!(percentile(&mut v, 1.0), 200.0);
        assert_eq!(percentile(&mut [7.0], 0.99), 7.0);
        assert_eq!(percentile(&mut [], 0.5), 0.0);
    }
}
