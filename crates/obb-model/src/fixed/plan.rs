//! A hardware configuration planned from scenes and the user's aims (`obbcd plan`,
//! `gen-rtl --scene`, `detect --engine model` without a configuration). Every key is decided by
//! a figure measured on the scenes with the model, and the plan says which:
//!
//! - the group mask is the user's (all pairs by default, as the CPU engines);
//! - the data width is the narrowest whose false-positive rate is at most the aim on every
//!   scene (no width has a false negative: docs/numerics.md proves it, and the plan checks it);
//! - the LSB is the finest at which every box fits half the center range (the other half is
//!   room for motion);
//! - the capacity is the next power of two at or above 1.25 times the largest scene;
//! - the broad phase is the one with the fewest clocks on the slowest scene by the cycle model:
//!   the grid (its cell from the largest box, and twice and four times that), the sweep, or
//!   every pair (`brute`, the paper's inequality (2): run only where its pairs alone do not
//!   already take more clocks than the best); the paper's improved-sap is kept as a mode to
//!   measure against, never planned;
//! - with the grid, the fewest walker lanes that reach the aimed frame rate at the aimed period,
//!   with as many buckets as the default list heads' memory holds;
//! - the SAT compares at its full width (no low bits dropped).

use super::accuracy::{
    at_width, differences, false_positive_rate, reference_pairs, MAX_WIDTH, MIN_WIDTH,
};
use super::config::{BroadPhase, ConfigError, HwConfig, GROUP_BITS, MAX_LANES};
use super::grid::MAX_KEY_BITS;
use super::quantize::QuantizeError;
use super::ModelFrame;
use crate::engines::Pair;
use crate::groups::GroupMask;
use crate::scene::Scene;
use thiserror::Error;

/// What the user wants of the core.
#[derive(Clone, Debug)]
pub struct Aims {
    /// The group pairs to report.
    pub groups: GroupMask,
    /// The largest share of reported pairs that may be false positives, on every scene.
    pub fp_rate: f64,
    /// Frames per second to reach on every scene at `period_ns`, if any (the grid's lanes).
    pub rate_hz: Option<f64>,
    /// The clock period the frame rate assumes, in ns (the UCF's constraint).
    pub period_ns: f64,
}

impl Default for Aims {
    fn default() -> Self {
        Aims {
            groups: GroupMask::All,
            fp_rate: 0.01,
            rate_hz: None,
            period_ns: HwConfig::default().clock_ns,
        }
    }
}

/// A configuration key and the figure that decided it.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    pub key: &'static str,
    pub why: String,
}

/// The planned core on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFigures {
    pub boxes: usize,
    pub clocks: u64,
    pub pairs: usize,
    pub false_positives: usize,
}

/// A planned configuration, why each key is what it is, and the figures on each scene.
#[derive(Clone, Debug)]
pub struct Plan {
    pub cfg: HwConfig,
    pub choices: Vec<Choice>,
    pub scenes: Vec<SceneFigures>,
    /// The aims the planned core does not meet, each with the figure that falls short.
    pub unmet: Vec<String>,
}

/// Why no configuration can be planned.
#[derive(Debug, Error)]
pub enum PlanError {
    #[error("no scene to plan for")]
    NoScene,
    #[error("the false-positive rate aim {0} is not a share between 0 and 1")]
    FpRate(f64),
    #[error("the frame rate aim {0} Hz is not a positive number")]
    Rate(f64),
    #[error("the clock period {0} ns is outside 1..=100 ns")]
    Period(f64),
    #[error("scene {scene}: {boxes} boxes, beyond the core's {max}")]
    TooManyBoxes {
        scene: usize,
        boxes: usize,
        max: u32,
    },
    #[error("scene {scene}: {cause}")]
    Quantize { scene: usize, cause: QuantizeError },
    #[error(
        "scene {scene} at {width} bits: the model misses {missed} pair(s) of the f64 reference, \
         first {first:?}: this is a bug"
    )]
    Missed {
        scene: usize,
        width: u32,
        missed: usize,
        first: Pair,
    },
    #[error("the planned configuration is invalid: {0}")]
    Config(ConfigError),
}

/// The most boxes the core's indices hold.
const MAX_CAPACITY: u32 = 1 << 20;
/// Brute force is run only while its pairs, at one a clock, do not exceed this many: beyond,
/// the pairs alone take more clocks than the grid or the sweep on any scene measured.
const BRUTE_MAX_PAIRS: u64 = 20_000_000;

/// Plans a configuration for `scenes` (each a frame the core must take) and `aims`.
pub fn plan(scenes: &[Scene], aims: &Aims) -> Result<Plan, PlanError> {
    check_aims(scenes, aims)?;
    let mut choices = Vec::new();
    let mut why = |key: &'static str, why: String| choices.push(Choice { key, why });
    let most = scenes.iter().map(|s| s.obbs.len()).max().unwrap_or(0);
    let capacity = ((most as u64 * 5).div_ceil(4).max(1)).next_power_of_two();
    if capacity > u64::from(MAX_CAPACITY) {
        let (scene, s) = scenes
            .iter()
            .enumerate()
            .max_by_key(|(_, s)| s.obbs.len())
            .expect("scenes are not empty");
        return Err(PlanError::TooManyBoxes {
            scene,
            boxes: s.obbs.len(),
            max: MAX_CAPACITY * 4 / 5,
        });
    }
    why(
        "capacity",
        format!(
            "the largest scene has {most} boxes; the next power of two at or above 1.25 times that"
        ),
    );
    let top_group = scenes
        .iter()
        .flat_map(|s| &s.obbs)
        .map(|o| o.group)
        .max()
        .unwrap_or(0);
    let base = HwConfig {
        capacity: capacity as u32,
        groups: aims.groups.clone(),
        grid_groups: (top_group + 1).min(1 << GROUP_BITS),
        clock_ns: aims.period_ns,
        ..HwConfig::default()
    };
    why("groups", format!("the pairs asked for: {}", aims.groups));
    why(
        "resident_groups",
        "none: every frame loads every box (name the groups the core keeps between frames, \
         such as the tissue, for haptic frames)"
            .into(),
    );
    why(
        "grid_groups",
        format!("the scenes' groups run from 0 to {top_group}"),
    );
    why(
        "clock_ns",
        format!("the clock period aimed at: {} ns", aims.period_ns),
    );
    let references: Vec<Vec<Pair>> = scenes
        .iter()
        .map(|s| reference_pairs(s, &aims.groups))
        .collect();

    // The narrowest width whose false-positive rate meets the aim on every scene.
    // The scenes are quantized once a width: the cell changes no key.
    let mut chosen = None;
    for w in MIN_WIDTH..=MAX_WIDTH {
        let at = widths(&base, w, scenes);
        let quantized = frames(&at, scenes)?;
        let cfg = with_fitted_cell(&at, &quantized);
        let worst = worst_fp_rate(&frames_with(&quantized, &cfg), &references, w)?;
        let meets = worst.rate <= aims.fp_rate;
        chosen = Some((w, cfg, worst));
        if meets {
            break;
        }
    }
    let (w, cfg, worst) = chosen.expect("the widths are not empty");
    let rate = worst.rate;
    let met = if rate <= aims.fp_rate {
        format!(
            "the narrowest whose false-positive rate is at most {}",
            aims.fp_rate
        )
    } else {
        format!(
            "the widest: no width meets the false-positive aim {}",
            aims.fp_rate
        )
    };
    why(
        "center_bits",
        format!(
            "{w} bits, {met}: the worst scene's is {rate:.4} (scene {}: {} of {} pairs); no \
             width misses a pair",
            worst.scene, worst.false_positives, worst.pairs
        ),
    );
    why(
        "key_bits",
        format!("the data width, {w} bits (at most {MAX_KEY_BITS} with the grid)"),
    );
    why(
        "lsb_mm",
        format!(
            "the finest power of two at which every box's AABB fits half the ±{} mm center range \
             (the other half is room for motion) and every half-length fits {} bits",
            cfg.lsb_mm * f64::from(1u32 << (cfg.center_bits - 1)),
            cfg.half_bits
        ),
    );
    why(
        "half_bits",
        format!(
            "{} bits, one less than the data width at most",
            cfg.half_bits
        ),
    );
    let cfg = HwConfig {
        sat_bits: cfg.sat_full_bits().clamp(16, 48),
        ..cfg
    };
    why(
        "sat_bits",
        format!(
            "the SAT's full width for {w}-bit centers and {}-bit rotations: nothing dropped",
            cfg.rot_bits
        ),
    );

    // The broad phase: the fewest clocks on the slowest scene.
    let frames = frames(&cfg, scenes)?;
    let mut options: Vec<(u64, HwConfig, String)> = Vec::new();
    for scale in [1, 2, 4] {
        let grid = HwConfig {
            grid_cell_mm: cfg.grid_cell_mm * f64::from(scale),
            ..cfg.clone()
        };
        let clocks = slowest(&frames, &grid);
        let note = format!("grid with {} mm cells: {clocks} clocks", grid.grid_cell_mm);
        options.push((clocks, grid, note));
    }
    let sweep = HwConfig {
        broad_phase: BroadPhase::Sweep,
        ..cfg.clone()
    };
    let clocks = slowest(&frames, &sweep);
    options.push((clocks, sweep, format!("sweep: {clocks} clocks")));
    let best = options.iter().map(|o| o.0).min().expect("options");
    let brute_pairs = scenes
        .iter()
        .map(|s| (s.obbs.len() as u64).saturating_sub(1) * s.obbs.len() as u64 / 2)
        .max()
        .unwrap_or(0);
    if brute_pairs <= BRUTE_MAX_PAIRS.min(best) {
        let brute = HwConfig {
            broad_phase: BroadPhase::Brute,
            ..cfg.clone()
        };
        let clocks = slowest(&frames, &brute);
        options.push((clocks, brute, format!("brute: {clocks} clocks")));
    } else {
        options.push((
            u64::MAX,
            cfg.clone(),
            format!("brute: {brute_pairs} pairs, at one a clock (not run)"),
        ));
    }
    let pick = options
        .iter()
        .enumerate()
        .min_by_key(|(_, o)| o.0)
        .map(|(k, _)| k)
        .expect("options");
    let notes: Vec<String> = options.iter().map(|o| o.2.clone()).collect();
    let (clocks, mut cfg, _) = options.swap_remove(pick);
    why(
        "broad_phase",
        format!(
            "the fewest clocks on the slowest scene by the cycle model ({})",
            notes.join("; ")
        ),
    );
    if matches!(cfg.broad_phase, BroadPhase::Grid | BroadPhase::Brute) {
        why(
            "radix_digit_bits",
            format!("not used by the {} (no sort)", cfg.broad_phase),
        );
    }
    if cfg.broad_phase == BroadPhase::Grid {
        why(
            "grid_cell_mm",
            format!(
                "the fewest clocks among cells of the largest box's extent, twice and four \
                 times that ({})",
                notes[..3].join("; ")
            ),
        );
    } else {
        for key in [
            "grid_cell_mm",
            "lanes",
            "grid_hash_bits",
            "grid_group_lists",
        ] {
            why(key, format!("not used by the {}", cfg.broad_phase));
        }
    }

    // Lanes: the fewest that reach the aimed rate.
    let frame_rate = |clocks: u64| 1e9 / (clocks as f64 * aims.period_ns);
    let mut clocks = clocks;
    if cfg.broad_phase == BroadPhase::Grid {
        let mut tried = Vec::new();
        let mut lanes = 1;
        cfg.grid_hash_bits = hash_bits(&cfg, 1);
        // One list for every group, when the mask pairs them all: more buckets in the same
        // memory, fewer lists to enumerate, against more lists of mixed cells; the faster is
        // kept. (One group has one list a bucket either way.)
        let one_list = cfg.grid_groups > 1
            && HwConfig {
                grid_group_lists: false,
                ..cfg.clone()
            }
            .validate()
            .is_ok();
        loop {
            let layouts: &[bool] = if one_list { &[true, false] } else { &[true] };
            for &group_lists in layouts {
                let lane_cfg = HwConfig {
                    lanes,
                    grid_group_lists: group_lists,
                    ..cfg.clone()
                };
                let lane_cfg = HwConfig {
                    grid_hash_bits: hash_bits(&lane_cfg, lanes),
                    ..lane_cfg
                };
                let c = slowest(&frames, &lane_cfg);
                let first = tried.is_empty();
                let lists = if group_lists { "" } else { " one list" };
                tried.push(format!("{lanes}{lists}: {c} clocks"));
                if first || c < clocks {
                    (clocks, cfg) = (c, lane_cfg);
                }
            }
            let reached = aims.rate_hz.is_none_or(|f| frame_rate(clocks) >= f);
            if reached || lanes == MAX_LANES {
                break;
            }
            lanes *= 2;
        }
        let aim = match aims.rate_hz {
            None => "no frame rate asked for".to_string(),
            Some(f) if frame_rate(clocks) >= f => {
                format!("the fewest that reach {f} Hz at {} ns", aims.period_ns)
            }
            Some(f) => format!(
                "the fastest: none reaches {f} Hz at {} ns ({:.0} Hz)",
                aims.period_ns,
                frame_rate(clocks)
            ),
        };
        why("lanes", format!("{aim} (lanes: {})", tried.join(", ")));
        why(
            "grid_group_lists",
            match (one_list, cfg.grid_group_lists) {
                (false, _) if cfg.grid_groups == 1 => "one group: one list a bucket".to_string(),
                (false, _) => "a list per group: the mask does not pair every group".to_string(),
                (true, true) => {
                    format!("a list per group: the fewer clocks ({})", tried.join(", "))
                }
                (true, false) => format!(
                    "one list for every group (the mask pairs them all): the fewer clocks ({})",
                    tried.join(", ")
                ),
            },
        );
        why(
            "grid_hash_bits",
            format!(
                "as many buckets as the default list heads' memory holds for {} list(s) a \
                 bucket on {} lane(s)",
                cfg.list_groups(),
                cfg.lanes
            ),
        );
    }
    cfg.validate().map_err(PlanError::Config)?;

    // The figures of the planned core.
    let frames = frames_with(&frames, &cfg);
    let mut figures = Vec::with_capacity(scenes.len());
    for (k, f) in frames.iter().enumerate() {
        let run = f.run();
        let (fp, missed) = differences(&run.pairs, &references[k]);
        if let Some(&first) = missed.first() {
            return Err(PlanError::Missed {
                scene: k,
                width: w,
                missed: missed.len(),
                first,
            });
        }
        figures.push(SceneFigures {
            boxes: f.obbs.len(),
            clocks: run.cycles.total,
            pairs: run.pairs.len(),
            false_positives: fp.len(),
        });
    }
    let mut unmet = Vec::new();
    if rate > aims.fp_rate {
        unmet.push(format!(
            "false-positive rate {rate:.4} on scene {}, above the {} asked (the widest width)",
            worst.scene, aims.fp_rate
        ));
    }
    let slowest = figures.iter().map(|f| f.clocks).max().unwrap_or(0);
    if let Some(f) = aims.rate_hz.filter(|&f| frame_rate(slowest) < f) {
        unmet.push(format!(
            "{:.0} frames per second at {} ns ({slowest} clocks on the slowest scene), below \
             the {f} Hz asked",
            frame_rate(slowest),
            aims.period_ns
        ));
    }
    Ok(Plan {
        cfg,
        choices,
        scenes: figures,
        unmet,
    })
}

fn check_aims(scenes: &[Scene], aims: &Aims) -> Result<(), PlanError> {
    if scenes.is_empty() {
        return Err(PlanError::NoScene);
    }
    if !(0.0..=1.0).contains(&aims.fp_rate) {
        return Err(PlanError::FpRate(aims.fp_rate));
    }
    if let Some(f) = aims.rate_hz.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(PlanError::Rate(f));
    }
    if !(aims.period_ns.is_finite() && (1.0..=100.0).contains(&aims.period_ns)) {
        return Err(PlanError::Period(aims.period_ns));
    }
    Ok(())
}

/// `base` at data width `w` (keys no wider than the grid takes), its LSB fitted to `scenes`.
fn widths(base: &HwConfig, w: u32, scenes: &[Scene]) -> HwConfig {
    at_width(base, w).fitted_all(scenes)
}

/// `cfg` with grid cells as large as the largest key extent of a box of `frames` (quantized in
/// `cfg`'s formats), so that no box takes the slow path.
fn with_fitted_cell(cfg: &HwConfig, frames: &[ModelFrame]) -> HwConfig {
    let extent = frames
        .iter()
        .flat_map(|f| &f.keys)
        .flat_map(|(lo, hi)| (0..3).map(move |x| hi[x] - lo[x]))
        .max()
        .unwrap_or(0);
    let bits = (64 - extent.max(1).saturating_sub(1).leading_zeros()).min(cfg.key_bits);
    let key_unit = cfg.lsb_mm * f64::from(1u32 << cfg.key_shift());
    HwConfig {
        grid_cell_mm: key_unit * f64::from(1u32 << bits),
        ..cfg.clone()
    }
}

/// The scenes in `cfg`'s formats.
fn frames(cfg: &HwConfig, scenes: &[Scene]) -> Result<Vec<ModelFrame>, PlanError> {
    scenes
        .iter()
        .enumerate()
        .map(|(scene, s)| {
            ModelFrame::new(s, cfg).map_err(|cause| PlanError::Quantize { scene, cause })
        })
        .collect()
}

/// `frames` under `cfg`, whose formats are theirs (only the broad phase's keys differ).
fn frames_with(frames: &[ModelFrame], cfg: &HwConfig) -> Vec<ModelFrame> {
    frames
        .iter()
        .map(|f| ModelFrame {
            cfg: cfg.clone(),
            ..f.clone()
        })
        .collect()
}

/// The most clocks a frame of `frames` takes under `cfg`.
fn slowest(frames: &[ModelFrame], cfg: &HwConfig) -> u64 {
    frames_with(frames, cfg)
        .iter()
        .map(|f| f.run().cycles.total)
        .max()
        .unwrap_or(0)
}

/// A scene's false positives under a configuration.
#[derive(Clone, Copy, Debug, Default)]
struct FalsePositives {
    rate: f64,
    scene: usize,
    false_positives: usize,
    pairs: usize,
}

/// The frame of `frames` (the scenes under one configuration) with the worst false-positive
/// rate; a missed pair is an error.
fn worst_fp_rate(
    frames: &[ModelFrame],
    references: &[Vec<Pair>],
    width: u32,
) -> Result<FalsePositives, PlanError> {
    let mut worst = FalsePositives::default();
    for (k, f) in frames.iter().enumerate() {
        let run = f.detect(BroadPhase::Grid, &f.cfg.groups);
        let (fp, missed) = differences(&run.pairs, &references[k]);
        if let Some(&first) = missed.first() {
            return Err(PlanError::Missed {
                scene: k,
                width,
                missed: missed.len(),
                first,
            });
        }
        let rate = false_positive_rate(fp.len(), run.pairs.len());
        if k == 0 || rate > worst.rate {
            worst = FalsePositives {
                rate,
                scene: k,
                false_positives: fp.len(),
                pairs: run.pairs.len(),
            };
        }
    }
    Ok(worst)
}

/// Bucket bits for `lanes` lanes: the most whose list heads (27 banks, `list_groups` lists per
/// lane and bucket) are no more than the default core's (3 groups, one lane, 2^10 buckets).
fn hash_bits(cfg: &HwConfig, lanes: u32) -> u32 {
    let default = HwConfig::default();
    let budget = u64::from(default.grid_groups) << default.grid_hash_bits;
    let per_bucket = u64::from(cfg.list_groups()) * u64::from(lanes);
    (budget / per_bucket)
        .ilog2()
        .clamp(1, super::grid::MAX_HASH_BITS)
}

impl Plan {
    /// One line: the broad phase, lanes, data width, LSB, capacity, mask, and the slowest
    /// scene's clocks.
    pub fn summary(&self) -> String {
        let c = &self.cfg;
        format!(
            "broad_phase={} lanes={} width={} lsb_mm={} capacity={} groups={} clocks={}",
            c.broad_phase,
            c.lanes,
            c.center_bits,
            c.lsb_mm,
            c.capacity,
            c.groups,
            self.scenes.iter().map(|f| f.clocks).max().unwrap_or(0)
        )
    }

    /// The configuration as TOML, each key after a comment naming the figure that decided it.
    pub fn to_toml(&self) -> String {
        let mut out = String::from(
            "# Planned by obbcd plan: each key's comment names the figure that decided it.\n",
        );
        for aim in &self.unmet {
            out.push_str(&format!("# Aim not met: {aim}.\n"));
        }
        for line in self.cfg.to_toml().lines() {
            let key = line.split(" = ").next().unwrap_or("");
            match self.choices.iter().find(|c| c.key == key) {
                Some(c) => out.push_str(&format!("# {}\n", c.why)),
                None if !key.is_empty() => out.push_str("# the default (not planned)\n"),
                None => {}
            }
            out.push_str(line);
            out.push('\n');
        }
        out
    }
}
