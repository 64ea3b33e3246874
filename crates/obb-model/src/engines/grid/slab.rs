//! The grid built in slabs of z layers, one task each. The cell's z is the most significant part
//! of a key, so the slabs' sorted entries laid end to end are the whole grid sorted: the threads
//! enter, sort and scan their slabs independently, and nothing is merged.

use super::geometry::GridGeometry;
use super::ranks::Ranks;
use super::{FLAG_BITS, MAX_CELLS_PER_BOX};
use crate::aabb::Aabb;
use crate::prepared::Frame;
use crate::radix::{bits_for, RadixSorter};
use std::ops::Range;

/// A slab needs at least this many sampled boxes, so that a small scene stays on one thread.
const MIN_SAMPLE_PER_SLAB: usize = 256;
/// Boxes sampled to place the slab boundaries.
const SLAB_SAMPLE: usize = 4096;
/// The radix sort's digits: at least this wide, and at most one bit wider than the entries'
/// count needs, up to `MAX_DIGIT_BITS`.
const MIN_DIGIT_BITS: u32 = 8;
const MAX_DIGIT_BITS: u32 = 16;

/// One slab's entries, built on one thread. Aligned to two cache lines: the slabs lie side by
/// side in a Vec and are filled at once on different threads, and a line shared by one slab's
/// Vec lengths and the next one's fields would pass between the cores at every entry (that made
/// the entering on two threads as slow as on one).
#[derive(Debug)]
#[repr(align(128))]
pub(super) struct Slab {
    /// The z layers of cells this slab holds.
    z: Range<u64>,
    keys: Vec<u64>,
    entries: Vec<u32>,
    /// Boxes covering too many cells whose first z layer is in this slab.
    pub large: Vec<u32>,
    /// This slab's cells with pairs to examine, as ranges of the whole grid's entries.
    pub runs: Vec<(u32, u32)>,
    /// The union of the AABBs of the boxes entered in this slab's cells, when a group probes
    /// (else empty).
    pub bounds: Aabb,
    radix: RadixSorter<u32>,
}

impl Default for Slab {
    fn default() -> Self {
        Slab {
            z: 0..0,
            keys: Vec::new(),
            entries: Vec::new(),
            large: Vec::new(),
            runs: Vec::new(),
            bounds: Aabb::EMPTY,
            radix: RadixSorter::new(MAX_DIGIT_BITS),
        }
    }
}

/// What every slab reads while it is built.
pub(super) struct Layout<'a> {
    pub geometry: &'a GridGeometry,
    pub ranks: &'a Ranks,
    pub boxes: &'a Frame<'a>,
    /// The group whose boxes probe instead of being entered.
    pub prober: Option<u32>,
    pub key_bits: u32,
}

impl Slab {
    pub(super) fn len(&self) -> usize {
        self.keys.len()
    }

    /// Enters the chosen boxes' cells in this slab's layers, then sorts them by key.
    pub(super) fn build(&mut self, l: &Layout) {
        #[cfg(target_arch = "x86_64")]
        if is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("avx512vl")
        {
            // SAFETY: this CPU has the features `build_avx512` enables.
            return unsafe { self.build_avx512(l) };
        }
        #[cfg(target_arch = "x86_64")]
        if is_x86_feature_detected!("avx2") {
            // SAFETY: this CPU has the feature `build_avx2` enables.
            return unsafe { self.build_avx2(l) };
        }
        self.enter(l, |b| l.geometry.range(b));
        self.sort(l);
    }

    /// [`Slab::build`] with each box's cell range from [`GridGeometry::range_avx2`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn build_avx2(&mut self, l: &Layout) {
        self.enter(l, |b| l.geometry.range_avx2(b));
        self.sort(l);
    }

    /// [`Slab::build`] with each box's cell range from [`GridGeometry::range_avx512`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx512vl")]
    fn build_avx512(&mut self, l: &Layout) {
        self.enter(l, |b| l.geometry.range_avx512(b));
        self.sort(l);
    }

    /// Enters the chosen boxes' cells in this slab's layers, each box's cell range from `range`.
    #[inline(always)]
    fn enter(&mut self, l: &Layout, range: impl Fn(&Aabb) -> ([u64; 3], [u64; 3])) {
        let class_bits = l.ranks.class_bits();
        self.keys.clear();
        self.entries.clear();
        self.large.clear();
        self.bounds = Aabb::EMPTY;
        for (i, b) in l.boxes.aabbs.iter().enumerate() {
            // The group, then the z range: most boxes probe, or lie in other slabs; then whether
            // the box may meet any box it pairs with.
            if Some(l.boxes.groups[i]) == l.prober {
                continue;
            }
            let (c0, c1) = range(b);
            let (z0, z1) = (c0[2], c1[2]);
            if z1 < self.z.start || z0 >= self.z.end || !l.ranks.may_pair(i, b) {
                continue;
            }
            if GridGeometry::cells_in(c0, c1) > MAX_CELLS_PER_BOX {
                if self.z.contains(&z0) {
                    self.large.push(i as u32);
                }
                continue;
            }
            // Only the probing needs the entered boxes' bounds.
            if l.prober.is_some() {
                self.bounds = self.bounds.union(b);
            }
            let rank = l.ranks.rank(i) << FLAG_BITS;
            // Keys along a row of cells differ only in x: each is the row's first key plus
            // its x offset, with the start flags of its axes.
            for z in z0.max(self.z.start)..=z1.min(self.z.end - 1) {
                let z_flag = u64::from(z == c0[2]) << 2;
                for y in c0[1]..=c1[1] {
                    let flags = z_flag | u64::from(y == c0[1]) << 1;
                    let row = (l.geometry.key([c0[0], y, z]) << class_bits) | rank;
                    self.keys.push(row | flags | 1);
                    self.entries.push(i as u32);
                    for dx in 1..=c1[0] - c0[0] {
                        self.keys.push((row + (dx << class_bits)) | flags);
                        self.entries.push(i as u32);
                    }
                }
            }
        }
    }

    /// Sorts the entered keys (and their boxes).
    fn sort(&mut self, l: &Layout) {
        // By cell and rank only: the scan needs a cell's entries together and its ranks in
        // order (see `find_runs`), not its start flags in order, and three bits fewer often
        // save a pass. Digits one bit wider than the entries' count needs (up to 16 bits) take
        // the fewest passes whose counts still fit the caches beside the entries, and whose
        // counts cost less to clear than the entries to sort: on the surgical scene one pass
        // of 16 bits where there were two of 10 (0.1 ms less a frame).
        let digit = (bits_for(self.keys.len() as u64) + 1).clamp(MIN_DIGIT_BITS, MAX_DIGIT_BITS);
        self.radix.set_max_digit_bits(digit);
        self.radix
            .sort_bits(&mut self.keys, &mut self.entries, FLAG_BITS, l.key_bits);
    }

    /// Copies the sorted entries to `keys` and `entries` (this slab's part of the whole grid,
    /// starting at entry `offset`), and finds its runs (`find_runs`).
    pub(super) fn publish(
        &mut self,
        keys: &mut [u64],
        entries: &mut [u32],
        offset: usize,
        ranks: &Ranks,
    ) {
        keys.copy_from_slice(&self.keys);
        entries.copy_from_slice(&self.entries);
        self.find_runs(keys, offset, ranks);
    }

    /// [`Slab::publish`] for the only slab: its entries are the whole grid, so the buffers
    /// change hands instead of being copied (the slab refills the grid's old ones next frame).
    pub(super) fn publish_whole(
        &mut self,
        keys: &mut Vec<u64>,
        entries: &mut Vec<u32>,
        ranks: &Ranks,
    ) {
        std::mem::swap(keys, &mut self.keys);
        std::mem::swap(entries, &mut self.entries);
        self.keys.clear();
        self.entries.clear();
        self.find_runs(keys, 0, ranks);
    }

    /// Finds this slab's runs in its sorted `keys` (the whole grid's from entry `offset`): the
    /// cells with two or more entries, except those holding one rank whose own pairs the mask
    /// excludes (an instrument's cells, for cross-group detection).
    fn find_runs(&mut self, keys: &[u64], offset: usize, ranks: &Ranks) {
        let class_bits = ranks.class_bits();
        let class_mask = ranks.class_mask();
        let rank = |k: u64| ((k & class_mask) >> FLAG_BITS) as usize;
        self.runs.clear();
        let mut start = 0;
        for p in 1..=keys.len() {
            if p == keys.len() || keys[p] >> class_bits != keys[start] >> class_bits {
                // Ranks ascend inside a cell: the first and last entries hold the extremes.
                let (r0, r1) = (rank(keys[start]), rank(keys[p - 1]));
                if p - start >= 2 && (r0 != r1 || ranks.allowed[r0][r0]) {
                    self.runs
                        .push(((offset + start) as u32, (offset + p) as u32));
                }
                start = p;
            }
        }
    }
}

/// Sets the slabs' layers so that each gets about the same share of the entered boxes, judged
/// from an evenly spaced sample of their first z layers; one slab per thread at most.
pub(super) fn place(slabs: &mut Vec<Slab>, threads: usize, l: &Layout, scratch: &mut Vec<u64>) {
    let g = l.geometry;
    let (aabbs, groups) = (l.boxes.aabbs, l.boxes.groups);
    scratch.clear();
    scratch.extend(
        (0..aabbs.len())
            .step_by(aabbs.len().div_ceil(SLAB_SAMPLE).max(1))
            .filter(|&i| Some(groups[i]) != l.prober && l.ranks.may_pair(i, &aabbs[i]))
            .map(|i| g.coord(aabbs[i].min[2], 2)),
    );
    let n = threads.min(scratch.len() / MIN_SAMPLE_PER_SLAB).max(1);
    if slabs.len() != n {
        slabs.resize_with(n, Slab::default);
    }
    let mut start = 0;
    for (s, slab) in slabs.iter_mut().enumerate() {
        let end = if s + 1 == n {
            g.dims[2]
        } else {
            let at = scratch.len() * (s + 1) / n;
            let (_, &mut z, _) = scratch.select_nth_unstable(at);
            z.max(start)
        };
        slab.z = start..end;
        start = end;
    }
}

/// Runs `f` on every slab with its part of `keys` and `entries` and that part's offset, the
/// slabs in parallel (by `rayon::join`, which needs no allocation).
pub(super) fn for_each_part<F>(
    slabs: &mut [Slab],
    keys: &mut [u64],
    entries: &mut [u32],
    offset: usize,
    f: &F,
) where
    F: Fn(&mut Slab, &mut [u64], &mut [u32], usize) + Sync,
{
    match slabs {
        [] => {}
        [one] => f(one, keys, entries, offset),
        _ => {
            let (a, b) = slabs.split_at_mut(slabs.len() / 2);
            let n = a.iter().map(Slab::len).sum();
            let (ka, kb) = keys.split_at_mut(n);
            let (ea, eb) = entries.split_at_mut(n);
            rayon::join(
                || for_each_part(a, ka, ea, offset, f),
                || for_each_part(b, kb, eb, offset + n, f),
            );
        }
    }
}
