//! Host-side quantization of a scene to the core's integer formats, and the projection stage
//! (AABB end points and sort keys) that the hardware computes from them.

use super::config::HwConfig;
use super::margins::Margins;
use super::rounding::ceil_shift;
use crate::aabb::U;
use crate::scene::{Obb, Scene, SceneError};
use thiserror::Error;

/// One OBB in the core's formats: lengths in LSBs, rotation entries in Q1.f.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QObb {
    /// Rounded to nearest.
    pub center: [i64; 3],
    /// Rounded up.
    pub half: [i64; 3],
    /// `axes[k][x]`, rounded to nearest, in units of 2^-f.
    pub axes: [[i64; 3]; 3],
    /// The box's group, as in the scene.
    pub group: u32,
}

/// What the projection stage makes of one box: its AABB in LSBs, containing the original box,
/// and its SAT margin (docs/numerics.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Projected {
    pub min: [i64; 3],
    pub max: [i64; 3],
    /// `ceil(β · Σh)` in SAT units (LSB · 2^-f).
    pub margin: i64,
}

/// Why a scene cannot enter the core.
#[derive(Debug, Error)]
pub enum QuantizeError {
    #[error("the scene has {count} obbs, more than the configured capacity of {capacity}")]
    Capacity { count: usize, capacity: u32 },
    #[error("obb {index}: {what} {value} mm is beyond the configured limit of {limit} mm")]
    Range {
        index: usize,
        what: String,
        value: f64,
        limit: f64,
    },
    #[error(
        "obb {index}: group {group} is beyond the configuration's {groups} groups (8 in the \
         core; with the grid, `grid_groups`)"
    )]
    Group {
        index: usize,
        group: u32,
        groups: u32,
    },
    #[error(
        "obb {index}: its axes deviate from orthonormality by {error:e}, more than the configured ortho_tol {tol:e}"
    )]
    Ortho { index: usize, error: f64, tol: f64 },
    #[error(
        "obb {index}: group {group} is resident (`resident_groups`), and an update frame loads \
         the resident groups' boxes first: it follows obb {after} of a streamed group"
    )]
    ResidentOrder {
        index: usize,
        group: u32,
        after: usize,
    },
    #[error(
        "obb {index}: group {group} is resident (`resident_groups`): a haptic frame streams \
         only the other groups' boxes (the resident ones come with an update frame)"
    )]
    ResidentStreamed { index: usize, group: u32 },
    /// A box that fails the scene's own validation (NaN, negative half-length, ...).
    #[error(transparent)]
    Invalid(#[from] SceneError),
    /// The configuration itself is not supported.
    #[error(transparent)]
    Config(#[from] super::config::ConfigError),
}

/// Largest |coordinate| in LSBs: centers and AABB end points lie in `-limit..=limit`. The top
/// key step is kept free, so that a max end point rounded up to its key still fits `key_bits`.
fn coord_limit(cfg: &HwConfig) -> i64 {
    (1i64 << (cfg.center_bits - 1)) - (1i64 << cfg.key_shift())
}

/// Quantizes every box of `scene`; rejects (never wraps or saturates) a box that does not fit.
pub fn quantize(scene: &Scene, cfg: &HwConfig) -> Result<Vec<QObb>, QuantizeError> {
    cfg.validate()?;
    if scene.obbs.len() > cfg.capacity as usize {
        return Err(QuantizeError::Capacity {
            count: scene.obbs.len(),
            capacity: cfg.capacity,
        });
    }
    scene
        .obbs
        .iter()
        .enumerate()
        .map(|(i, o)| quantize_obb(i, o, cfg))
        .collect()
}

/// Quantizes one box (`index` names it in errors) and checks that its AABB fits the range.
pub fn quantize_obb(index: usize, o: &Obb, cfg: &HwConfig) -> Result<QObb, QuantizeError> {
    // Scenes read from files are validated already; one built in code may not be.
    o.validate(index)?;
    let groups = cfg.groups_allowed();
    if o.group >= groups {
        return Err(QuantizeError::Group {
            index,
            group: o.group,
            groups,
        });
    }
    let q = cfg.lsb_mm;
    let limit = coord_limit(cfg);
    // q and 2^f are powers of two: dividing and scaling are exact, only the rounding is not.
    let scale = f64::from(1u32 << cfg.frac_bits());
    // The Gram matrix in f64 has error < 4u per entry; the margins cover ortho_tol.
    let ortho = o.ortho_error() + 8.0 * U;
    if ortho > cfg.ortho_tol {
        return Err(QuantizeError::Ortho {
            index,
            error: ortho,
            tol: cfg.ortho_tol,
        });
    }
    // A quantized value within ±limit, or the error naming the field.
    let fit = |what: String, value: f64, lsbs: f64, limit: i64| {
        if lsbs.abs() > limit as f64 {
            Err(QuantizeError::Range {
                index,
                what,
                value,
                limit: limit as f64 * q,
            })
        } else {
            Ok(lsbs as i64)
        }
    };
    let half_limit = (1i64 << cfg.half_bits) - 1;
    let mut half = [0; 3];
    for (k, h) in half.iter_mut().enumerate() {
        *h = fit(
            format!("half[{k}]"),
            o.half[k],
            (o.half[k] / q).ceil(),
            half_limit,
        )?;
    }
    let mut center = [0; 3];
    for (x, c) in center.iter_mut().enumerate() {
        *c = fit(
            format!("center[{x}]"),
            o.center[x],
            (o.center[x] / q).round(),
            limit,
        )?;
    }
    let axes = o.axes.map(|a| a.map(|v| (v * scale).round() as i64));
    let qobb = QObb {
        center,
        half,
        axes,
        group: o.group,
    };
    let p = project_extent(&qobb, cfg);
    for x in 0..3 {
        let reach = center[x].abs() + p[x];
        let what = format!("the AABB on axis {x} reaches |x| =");
        fit(what, reach as f64 * q, reach as f64, limit)?;
    }
    Ok(qobb)
}

/// The AABB half-extent per axis in LSBs, covering the original box's extent plus the half LSB
/// of center rounding: `E = ceil((Σ_k h_k (2|r_kx| + 1) + 2^f) / 2^(f+1))`.
fn project_extent(b: &QObb, cfg: &HwConfig) -> [i64; 3] {
    let f = cfg.frac_bits();
    std::array::from_fn(|x| {
        let sum: i64 = (0..3)
            .map(|k| b.half[k] * (2 * b.axes[k][x].abs() + 1))
            .sum();
        ceil_shift(sum + (1 << f), f + 1)
    })
}

/// The projection stage: AABB end points (min down, max up) and the SAT margin.
pub fn project(b: &QObb, cfg: &HwConfig, margins: &Margins) -> Projected {
    let e = project_extent(b, cfg);
    Projected {
        min: std::array::from_fn(|x| b.center[x] - e[x]),
        max: std::array::from_fn(|x| b.center[x] + e[x]),
        margin: margins.per_box(b.half),
    }
}

/// Sort keys of an AABB: end points offset to unsigned and cut to `key_bits`, min rounded down
/// and max rounded up, so key intervals contain the end-point intervals.
pub fn keys(p: &Projected, cfg: &HwConfig) -> ([u64; 3], [u64; 3]) {
    let offset = 1i64 << (cfg.center_bits - 1);
    let s = cfg.key_shift();
    (
        p.min.map(|v| ((v + offset) >> s) as u64),
        p.max.map(|v| ceil_shift(v + offset, s) as u64),
    )
}
