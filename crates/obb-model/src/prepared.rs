//! Per-frame preparation shared by every engine: each box's AABB and SAT slack, and its group.

use crate::aabb::Aabb;
use crate::engines::threads;
use crate::sat::{boxes_collide, Slack};
use crate::scene::Obb;
use crate::simd::Vectors;
use rayon::prelude::*;

/// Boxes below this count are prepared on one thread: below it, waking the pool costs more.
const PARALLEL_MIN: usize = 4096;
/// Boxes per parallel task.
const CHUNK: usize = 1024;

/// The per-box buffers of one frame, reused from frame to frame. The boxes themselves are not
/// copied: the SAT reads them from the scene, which keeps the per-frame writes small (they, not
/// the arithmetic, bound this pass).
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    aabbs: Vec<Aabb>,
    slack: Vec<Slack>,
    groups: Vec<u32>,
}

/// One frame's boxes, ready for the broad and narrow phases.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    pub obbs: &'a [Obb],
    pub aabbs: &'a [Aabb],
    pub slack: &'a [Slack],
    pub groups: &'a [u32],
    /// The union of the AABBs (`Aabb::EMPTY` for no boxes).
    pub bounds: Aabb,
    /// The largest extent of any AABB on any axis (0 for no boxes).
    pub widest: f64,
    /// The largest skew of any box ([`Slack::with_skew`]; 0 for no boxes): every box's `kappa`
    /// is at most `fl(skew · hsum)`. The SAT's first pass bounds the boxes' slack by it, where
    /// reading each box's would cost two gathers a step.
    pub skew: f64,
}

/// What the preparation learns of the boxes together, in the same pass as their AABBs: the
/// grid sizes its cells from both.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Spread {
    bounds: Aabb,
    widest: f64,
    skew: f64,
}

/// The larger of the two, `x` kept when `y` is NaN: a NaN extent never becomes the widest
/// (validated boxes have none), and a NaN skew comes only from NaN or infinite axes, whose
/// `t_k` already fail the SAT's first pass. (`simd::higher` is this on vector lanes.)
#[inline(always)]
fn higher(x: f64, y: f64) -> f64 {
    if y > x {
        y
    } else {
        x
    }
}

impl Spread {
    const NONE: Spread = Spread {
        bounds: Aabb::EMPTY,
        widest: 0.0,
        skew: 0.0,
    };

    /// With `aabb`, and a box of skew `skew`, too.
    #[inline(always)]
    fn with(self, aabb: &Aabb, skew: f64) -> Spread {
        let mut widest = self.widest;
        for x in 0..3 {
            widest = higher(widest, aabb.max[x] - aabb.min[x]);
        }
        Spread {
            bounds: self.bounds.union(aabb),
            widest,
            skew: higher(self.skew, skew),
        }
    }

    /// Both spreads together.
    fn join(self, other: Spread) -> Spread {
        Spread {
            bounds: self.bounds.union(&other.bounds),
            widest: higher(self.widest, other.widest),
            skew: higher(self.skew, other.skew),
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod vector;

/// Prepares one run of boxes and returns their AABBs' spread, on the best vector instructions
/// this CPU has ([`prepare_with`]).
fn prepare(obbs: &[Obb], aabbs: &mut [Aabb], slack: &mut [Slack], groups: &mut [u32]) -> Spread {
    prepare_with(Vectors::detected(), obbs, aabbs, slack, groups)
}

/// [`prepare`] on the instruction set `vectors` (one this CPU has): eight boxes at a time with
/// AVX-512, four with AVX2 (`vector`), else [`prepare_scalar`]. Every lane rounds as the scalar
/// code does, so the result is the same in every form.
fn prepare_with(
    vectors: Vectors,
    obbs: &[Obb],
    aabbs: &mut [Aabb],
    slack: &mut [Slack],
    groups: &mut [u32],
) -> Spread {
    #[cfg(target_arch = "x86_64")]
    if let Some(spread) = vector::on(vectors, obbs, aabbs, slack, groups) {
        return spread;
    }
    prepare_scalar(obbs, aabbs, slack, groups)
}

/// [`prepare`], one box at a time: one read of each box serves every per-box quantity.
fn prepare_scalar(
    obbs: &[Obb],
    aabbs: &mut [Aabb],
    slack: &mut [Slack],
    groups: &mut [u32],
) -> Spread {
    let mut spread = Spread::NONE;
    for (((obb, aabb), slack), group) in obbs.iter().zip(aabbs).zip(slack).zip(groups) {
        *aabb = Aabb::of(obb);
        let skew;
        (*slack, skew) = Slack::with_skew(obb);
        *group = obb.group;
        spread = spread.with(aabb, skew);
    }
    spread
}

impl Prepared {
    /// Recomputes everything from `obbs`, keeping the allocations.
    pub fn update<'a>(&'a mut self, obbs: &'a [Obb]) -> Frame<'a> {
        let n = obbs.len();
        self.aabbs.resize(n, Aabb::default());
        self.slack.resize(n, Slack::default());
        self.groups.resize(n, 0);
        let spread = if n < PARALLEL_MIN || threads() == 1 {
            prepare(obbs, &mut self.aabbs, &mut self.slack, &mut self.groups)
        } else {
            obbs.par_chunks(CHUNK)
                .zip(self.aabbs.par_chunks_mut(CHUNK))
                .zip(self.slack.par_chunks_mut(CHUNK))
                .zip(self.groups.par_chunks_mut(CHUNK))
                .map(|(((o, a), s), g)| prepare(o, a, s, g))
                .reduce(|| Spread::NONE, Spread::join)
        };
        Frame {
            obbs,
            aabbs: &self.aabbs,
            slack: &self.slack,
            groups: &self.groups,
            bounds: spread.bounds,
            widest: spread.widest,
            skew: spread.skew,
        }
    }
}

impl Frame<'_> {
    pub fn len(&self) -> usize {
        self.obbs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.obbs.is_empty()
    }

    /// The 15-axis SAT on boxes `i` and `j`, without the AABB check.
    #[inline]
    pub fn sat(&self, i: usize, j: usize) -> bool {
        boxes_collide(&self.obbs[i], &self.slack[i], &self.obbs[j], &self.slack[j])
    }

    /// The narrow phase every engine uses: closed AABB overlap, then the 15-axis SAT. Every
    /// engine reports exactly the pairs for which this is true (and the mask allows).
    #[inline]
    pub fn collide(&self, i: usize, j: usize) -> bool {
        self.aabbs[i].overlaps(&self.aabbs[j]) && self.sat(i, j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Boxes of every kind the preparation meets: rotated and skewed axes, flat and empty boxes,
    /// subnormal, huge and zero values, negative zeros, centres at the coordinate limit.
    fn boxes(n: usize) -> Vec<Obb> {
        let mut rng = ChaCha8Rng::seed_from_u64(19);
        let extremes = [0.0, -0.0, 1e-310, -1e-310, 1e-30, 1.0, 1e6, -1e6, 0.1, 3.0];
        (0..n)
            .map(|k| {
                let mut pick = |scale: f64| {
                    if rng.random_bool(0.2) {
                        extremes[rng.random_range(0..extremes.len())]
                    } else {
                        rng.random_range(-1.0..1.0) * scale
                    }
                };
                Obb {
                    center: [pick(1e3), pick(1e3), pick(1e3)],
                    axes: [0; 3].map(|_| [pick(1.0), pick(1.0), pick(1.0)]),
                    half: [pick(10.0).abs(), pick(1.0).abs(), pick(1e-3).abs()],
                    group: k as u32 % 3,
                }
            })
            .collect()
    }

    /// The frame's skew bounds every box's `kappa` from its `hsum` (what the SAT's first pass
    /// relies on), on boxes of every kind and on exactly orthonormal ones, whose skews differ
    /// only by their rounding.
    #[test]
    fn the_skew_bounds_every_kappa() {
        let aligned = (0..100).map(|k| Obb::aligned([k as f64; 3], [0.5, 1e-3, 7.0], 0));
        for obbs in [boxes(1003), aligned.collect()] {
            let mut prepared = Prepared::default();
            let frame = prepared.update(&obbs);
            assert!(frame.skew > 0.0);
            for (k, s) in frame.slack.iter().enumerate() {
                let bound = frame.skew * s.hsum;
                assert!(bound >= s.kappa, "box {k}: {bound} < {}", s.kappa);
            }
        }
    }

    /// Every AABB, slack and group, and the spread, bit for bit as the scalar preparation gives
    /// them, in every vector form this CPU has; also for lengths that leave a scalar tail.
    #[test]
    fn prepare_equals_the_scalar_form() {
        let mut all = boxes(1003);
        // Points at -0 and +0 (no extent).
        for (k, c) in [-0.0, 0.0, -0.0].into_iter().enumerate() {
            all[5 * k + 3] = Obb {
                center: [c, -c, c],
                axes: all[0].axes,
                half: [0.0; 3],
                group: 0,
            };
        }
        for n in [0, 1, 7, 8, 9, 64, 1003] {
            let obbs = &all[..n];
            let run = |vectors: Vectors| {
                let (mut a, mut s, mut g) =
                    (vec![Aabb::EMPTY; n], vec![Slack::default(); n], vec![9; n]);
                let spread = prepare_with(vectors, obbs, &mut a, &mut s, &mut g);
                let bits = |a: &Aabb| -> Vec<u64> {
                    a.min.iter().chain(&a.max).map(|x| x.to_bits()).collect()
                };
                let a: Vec<_> = a.iter().map(bits).collect();
                let s: Vec<_> = s
                    .iter()
                    .map(|s| [s.hsum.to_bits(), s.kappa.to_bits()])
                    .collect();
                let spread = (
                    bits(&spread.bounds),
                    spread.widest.to_bits(),
                    spread.skew.to_bits(),
                );
                (spread, a, s, g)
            };
            for &vectors in Vectors::available() {
                assert_eq!(
                    run(vectors),
                    run(Vectors::Portable),
                    "{vectors:?}, {n} boxes"
                );
            }
        }
    }
}
