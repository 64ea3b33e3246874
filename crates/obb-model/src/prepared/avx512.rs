//! [`super::prepare`] on eight boxes at a time, written with AVX-512 intrinsics.
//!
//! Scalar, the preparation is half of a cross-group frame: every box's AABB and slack take about
//! a hundred dependent operations. Here eight consecutive boxes are read whole and transposed in
//! registers (`crate::avx512::boxes`), so that each vector holds one value of the eight, and
//! every product, sum, comparison and maximum is the one `Aabb::of`, `Slack::of` (with
//! `Obb::ortho_error`) and `Aabb::union` write, in the same order and without fused
//! multiply-add: each lane rounds exactly as the scalar code does, which the tests check on
//! random and extreme boxes.

use crate::aabb::{Aabb, EXTENT_FLOOR, U};
use crate::avx512::{abs, add, boxes, dot, field3, higher, lower, mul, sub, AXES, CENTER, HALF};
use crate::sat::Slack;
use crate::scene::Obb;
use std::arch::x86_64::*;

/// Boxes prepared side by side: the f64 lanes of a 512-bit vector.
const WIDTH: usize = 8;

/// Whether [`prepare`] can run here: the CPU has AVX-512F.
pub(super) fn usable() -> bool {
    is_x86_feature_detected!("avx512f")
}

/// `outward` of `aabb.rs` on eight lanes: `d + dir·(|d|·2u) + 0`.
#[inline]
#[target_feature(enable = "avx512f")]
fn outward(d: __m512d, dir: f64) -> __m512d {
    let step = mul(_mm512_set1_pd(dir), mul(abs(d), _mm512_set1_pd(2.0 * U)));
    add(add(d, step), _mm512_setzero_pd())
}

/// [`super::prepare`], eight boxes per step; the last `len % 8` boxes go to the scalar form.
/// Only for a CPU that [`usable`] accepts.
#[target_feature(enable = "avx512f")]
pub(super) fn prepare(
    obbs: &[Obb],
    aabbs: &mut [Aabb],
    slack: &mut [Slack],
    groups: &mut [u32],
) -> Aabb {
    let n = obbs
        .len()
        .min(aabbs.len())
        .min(slack.len())
        .min(groups.len());
    let whole = n - n % WIDTH;
    let mut low = [_mm512_set1_pd(Aabb::EMPTY.min[0]); 3];
    let mut high = [_mm512_set1_pd(Aabb::EMPTY.max[0]); 3];
    for first in (0..whole).step_by(WIDTH) {
        // SAFETY: the eight boxes from `first` are below `whole`, inside `obbs`.
        let b = unsafe { boxes(obbs, std::array::from_fn(|l| first + l)) };
        let axes = [0, 3, 6].map(|row| field3(&b, AXES + row));
        let (center, half) = (field3(&b, CENTER), field3(&b, HALF));
        // Aabb::of: each world axis's half-extent, enlarged, and the end points stepped out.
        let mut ends = [_mm512_setzero_pd(); 6];
        for x in 0..3 {
            let e = add(
                add(mul(half[0], abs(axes[0][x])), mul(half[1], abs(axes[1][x]))),
                mul(half[2], abs(axes[2][x])),
            );
            let e = add(
                mul(e, _mm512_set1_pd(1.0 + 8.0 * U)),
                _mm512_set1_pd(EXTENT_FLOOR),
            );
            ends[x] = outward(sub(center[x], e), -1.0);
            ends[3 + x] = outward(add(center[x], e), 1.0);
            low[x] = lower(low[x], ends[x]);
            high[x] = higher(high[x], ends[3 + x]);
        }
        // Slack::of: the Gram matrix's worst entry, in Obb::ortho_error's order. Its
        // `worst.max(v)` is `higher(worst, v)` here: `worst` starts at 0 and is never NaN, and
        // both keep `worst` when `v` is NaN.
        let mut worst = _mm512_setzero_pd();
        for i in 0..3 {
            for k in i..3 {
                let target = _mm512_set1_pd(if i == k { 1.0 } else { 0.0 });
                worst = higher(worst, abs(sub(dot(&axes[i], &axes[k]), target)));
            }
        }
        let eta = add(worst, _mm512_set1_pd(8.0 * U));
        let hsum = add(add(half[0], half[1]), half[2]);
        let kappa = mul(mul(_mm512_set1_pd(2.01), eta), hsum);
        let (ends, [hsum, kappa]) = (lanes(ends), lanes([hsum, kappa]));
        let (aabbs, slack) = (
            &mut aabbs[first..first + WIDTH],
            &mut slack[first..first + WIDTH],
        );
        let boxes = obbs[first..first + WIDTH]
            .iter()
            .zip(&mut groups[first..first + WIDTH]);
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
    let bounds = super::prepare_scalar(
        &obbs[whole..n],
        &mut aabbs[whole..n],
        &mut slack[whole..n],
        &mut groups[whole..n],
    );
    let ends = lanes([low[0], low[1], low[2], high[0], high[1], high[2]]);
    (0..WIDTH).fold(bounds, |b, l| b.union(&lane_aabb(&ends, l)))
}

/// The lanes of each vector of `v`.
#[inline]
#[target_feature(enable = "avx512f")]
fn lanes<const N: usize>(v: [__m512d; N]) -> [[f64; WIDTH]; N] {
    let mut lanes = [[0.0; WIDTH]; N];
    for (v, lane) in v.iter().zip(lanes.iter_mut()) {
        // SAFETY: `lane` is eight f64.
        unsafe { _mm512_storeu_pd(lane.as_mut_ptr(), *v) };
    }
    lanes
}

/// The AABB in lane `l` of `ends`: the lanes of min x, y, z, then max x, y, z.
#[inline(always)]
fn lane_aabb(ends: &[[f64; WIDTH]; 6], l: usize) -> Aabb {
    Aabb {
        min: [ends[0][l], ends[1][l], ends[2][l]],
        max: [ends[3][l], ends[4][l], ends[5][l]],
    }
}
