//! [`super::prepare`] on several boxes at a time, written once over the vector instruction set
//! ([`Isa`]): eight boxes with AVX-512, four with AVX2.
//!
//! Scalar, the preparation is half of a cross-group frame: every box's AABB and slack take about
//! a hundred dependent operations. Here consecutive boxes are read whole and transposed in
//! registers ([`Isa::boxes`]), so that each vector holds one value of each box, and every
//! product, sum, comparison and maximum is the one `Aabb::of`, `Slack::of` (with
//! `Obb::ortho_error`) and `Aabb::union` write, in the same order and without fused
//! multiply-add: each lane rounds exactly as the scalar code does, which the tests check on
//! random and extreme boxes.

use super::Spread;
use crate::aabb::{Aabb, EXTENT_FLOOR, U};
use crate::sat::Slack;
use crate::scene::Obb;
use crate::simd::{
    axes, compile_for_each_isa, dot, field3, higher, lower, Isa, Lanes, CENTER, HALF,
};

compile_for_each_isa!(prepare(
    obbs: &[Obb],
    aabbs: &mut [Aabb],
    slack: &mut [Slack],
    groups: &mut [u32],
) -> Spread);

/// `outward` of `aabb.rs` on each lane: `d + dir·(|d|·2u) + 0`.
#[inline(always)]
fn outward<I: Isa<W>, const W: usize>(isa: I, d: I::F, dir: f64) -> I::F {
    let step = isa.splat(dir) * (d.abs() * isa.splat(2.0 * U));
    d + step + isa.splat(0.0)
}

/// [`super::prepare`], `W` boxes per step; the last `len % W` boxes go to the scalar form.
#[inline(always)]
fn prepare<I: Isa<W>, const W: usize>(
    isa: I,
    obbs: &[Obb],
    aabbs: &mut [Aabb],
    slack: &mut [Slack],
    groups: &mut [u32],
) -> Spread {
    let n = obbs
        .len()
        .min(aabbs.len())
        .min(slack.len())
        .min(groups.len());
    let whole = n - n % W;
    let mut low = [isa.splat(Aabb::EMPTY.min[0]); 3];
    let mut high = [isa.splat(Aabb::EMPTY.max[0]); 3];
    let mut widest = isa.splat(0.0);
    let mut skew = isa.splat(0.0);
    for first in (0..whole).step_by(W) {
        // Plain loops here, no `map` or `from_fn`: their closures are compiled outside the
        // function that enables the instruction set, so vector work in them would be a call
        // each.
        let mut at = [first; W];
        for (l, at) in at.iter_mut().enumerate() {
            *at += l;
        }
        // SAFETY: the `W` boxes from `first` are below `whole`, inside `obbs`.
        let b = unsafe { isa.boxes(obbs, at) };
        let axes = axes(&b);
        let (center, half) = (field3(&b, CENTER), field3(&b, HALF));
        // Aabb::of: each world axis's half-extent, enlarged, and the end points stepped out.
        let mut ends = [isa.splat(0.0); 6];
        for x in 0..3 {
            let e = half[0] * axes[0][x].abs()
                + half[1] * axes[1][x].abs()
                + half[2] * axes[2][x].abs();
            let e = e * isa.splat(1.0 + 8.0 * U) + isa.splat(EXTENT_FLOOR);
            ends[x] = outward(isa, center[x] - e, -1.0);
            ends[3 + x] = outward(isa, center[x] + e, 1.0);
            low[x] = lower(low[x], ends[x]);
            high[x] = higher(high[x], ends[3 + x]);
            widest = higher(widest, ends[3 + x] - ends[x]);
        }
        // Slack::of: the Gram matrix's worst entry, in Obb::ortho_error's order. Its
        // `worst.max(v)` is `higher(worst, v)` here: `worst` starts at 0 and is never NaN, and
        // both keep `worst` when `v` is NaN.
        let mut worst = isa.splat(0.0);
        for i in 0..3 {
            for k in i..3 {
                let target = isa.splat(if i == k { 1.0 } else { 0.0 });
                worst = higher(worst, (dot(&axes[i], &axes[k]) - target).abs());
            }
        }
        let eta = worst + isa.splat(8.0 * U);
        let hsum = half[0] + half[1] + half[2];
        let box_skew = isa.splat(2.01) * eta;
        skew = higher(skew, box_skew);
        let kappa = box_skew * hsum;
        let ends = lanes(isa, ends);
        let [hsum, kappa] = lanes(isa, [hsum, kappa]);
        let (aabbs, slack) = (&mut aabbs[first..first + W], &mut slack[first..first + W]);
        let boxes = obbs[first..first + W]
            .iter()
            .zip(&mut groups[first..first + W]);
        for (l, ((aabb, slack), (obb, group))) in aabbs.iter_mut().zip(slack).zip(boxes).enumerate()
        {
            *aabb = lane_aabb(&ends, l);
            *slack = Slack {
                hsum: hsum[l],
                kappa: kappa[l],
            };
            *group = obb.group;
        }
    }
    let tail = super::prepare_scalar(
        &obbs[whole..n],
        &mut aabbs[whole..n],
        &mut slack[whole..n],
        &mut groups[whole..n],
    );
    let ends = lanes(isa, [low[0], low[1], low[2], high[0], high[1], high[2]]);
    let [widest, skew] = lanes(isa, [widest, skew]);
    (0..W).fold(tail, |s, l| {
        let lane = Spread {
            bounds: lane_aabb(&ends, l),
            widest: widest[l],
            skew: skew[l],
        };
        s.join(lane)
    })
}

/// The lanes of each vector of `v`.
#[inline(always)]
fn lanes<I: Isa<W>, const W: usize, const N: usize>(isa: I, v: [I::F; N]) -> [[f64; W]; N] {
    let mut lanes = [[0.0; W]; N];
    for (v, lane) in v.iter().zip(lanes.iter_mut()) {
        *lane = isa.lanes(*v);
    }
    lanes
}

/// The AABB in lane `l` of `ends`: the lanes of min x, y, z, then max x, y, z.
#[inline(always)]
fn lane_aabb<const W: usize>(ends: &[[f64; W]; 6], l: usize) -> Aabb {
    Aabb {
        min: [ends[0][l], ends[1][l], ends[2][l]],
        max: [ends[3][l], ends[4][l], ends[5][l]],
    }
}
