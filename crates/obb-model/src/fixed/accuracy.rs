//! What a configuration costs in accuracy, against the f64 reference on the original boxes:
//! the reference pairs, the model's false positives and false negatives (which must be none),
//! the worst AABB inflation, and the configuration at a data width. Shared by `obbcd error`,
//! `obbcd detect --engine model` and the planner (`plan`).

use super::grid::MAX_KEY_BITS;
use super::{BroadPhase, HwConfig, ModelFrame};
use crate::aabb::Aabb;
use crate::engines::{detect, EngineKind, Pair};
use crate::groups::GroupMask;
use crate::prepared::Prepared;
use crate::scene::Scene;

/// Narrowest supported data width (centers and sort keys).
pub const MIN_WIDTH: u32 = 8;
/// Widest supported data width: the SAT's T·a operand must fit a DSP48E1 port
/// (docs/numerics.md).
pub const MAX_WIDTH: u32 = 23;

/// The f64 reference pairs (the CPU grid) under `mask`.
pub fn reference_pairs(scene: &Scene, mask: &GroupMask) -> Vec<Pair> {
    let mut prepared = Prepared::default();
    detect(EngineKind::Grid, &prepared.update(&scene.obbs), mask).0
}

/// Pairs of `model` not in `reference` (false positives) and pairs of `reference` not in
/// `model` (false negatives); both sorted ascending.
pub fn differences(model: &[Pair], reference: &[Pair]) -> (Vec<Pair>, Vec<Pair>) {
    let only = |a: &[Pair], b: &[Pair]| -> Vec<Pair> {
        a.iter()
            .filter(|p| b.binary_search(p).is_err())
            .copied()
            .collect()
    };
    (only(model, reference), only(reference, model))
}

/// The share of `reported` pairs that are false positives (0 when none is reported).
pub fn false_positive_rate(false_positives: usize, reported: usize) -> f64 {
    false_positives as f64 / reported.max(1) as f64
}

/// `base` at data width `w`: centers and sort keys of `w` bits (half-lengths and radix digits
/// no wider; the grid's keys at most `MAX_KEY_BITS`, what its block holds), its LSB not yet
/// fitted to a scene.
pub fn at_width(base: &HwConfig, w: u32) -> HwConfig {
    let keys = match base.broad_phase {
        BroadPhase::Grid => w.min(MAX_KEY_BITS),
        _ => w,
    };
    HwConfig {
        center_bits: w,
        key_bits: keys,
        half_bits: base.half_bits.min(w - 1),
        radix_digit_bits: base.radix_digit_bits.min(w),
        ..base.clone()
    }
}

/// Worst distance in µm by which a box's key interval reaches beyond its f64 AABB.
pub fn worst_inflation_um(frame: &ModelFrame, scene: &Scene) -> f64 {
    let cfg = &frame.cfg;
    let (q, s) = (cfg.lsb_mm, cfg.key_shift());
    let offset = 1i64 << (cfg.center_bits - 1);
    let mm = |k: u64| ((k << s) as i64 - offset) as f64 * q;
    let mut worst: f64 = 0.0;
    for (o, (lo, hi)) in scene.obbs.iter().zip(&frame.keys) {
        let b = Aabb::of(o);
        for x in 0..3 {
            worst = worst.max(b.min[x] - mm(lo[x])).max(mm(hi[x]) - b.max[x]);
        }
    }
    worst * 1e3
}
