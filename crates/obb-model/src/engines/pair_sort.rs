//! The engines' final pair sort, in parts of the box range on all threads.

use super::{ordered, Pair};
use std::mem::MaybeUninit;

/// `PairSorter` sorts by comparison when there are fewer pairs than boxes / this.
const SMALL_SORT_RATIO: usize = 16;
/// A part sorts at least this many pairs: each part reads every pair, and a thread's hand-off
/// costs about as much as sorting a few thousand.
const MIN_PAIRS_PER_PART: usize = 16_384;

/// Sorts pairs ascending and removes repeats, on buffers kept between calls: a counting sort on
/// the first index (one bucket per box), then each bucket's few second indices sorted in place.
/// The box range is cut into parts, one per thread: each part counts and places the pairs whose
/// first index it holds, so the parts write disjoint stretches and need no merge.
#[derive(Debug, Default)]
pub(crate) struct PairSorter {
    /// Per box: its bucket's start, then (after the scatter) its end, within its part.
    starts: Vec<u32>,
    seconds: Vec<u32>,
    sorted: Vec<Pair>,
    parts: Vec<Part>,
}

/// One part of the box range and its stretch of the output.
#[derive(Debug, Default, Clone, Copy)]
struct Part {
    first_box: usize,
    /// Pairs whose first index is in this part.
    pairs: usize,
    /// Of those, the distinct ones.
    kept: usize,
}

impl PairSorter {
    /// Sorts `pairs` ascending (by i, then j) and drops duplicates; `n` is the number of boxes.
    pub fn sort_dedup(&mut self, pairs: &mut Vec<Pair>, n: usize) {
        if few(pairs.len(), n) {
            pairs.sort_unstable();
            pairs.dedup();
            return;
        }
        let mut sorted = std::mem::take(&mut self.sorted);
        self.bucket(std::iter::once(&pairs[..]), pairs.len(), n, &mut sorted);
        self.sorted = std::mem::replace(pairs, sorted);
    }

    /// [`PairSorter::sort_dedup`] on the pairs of every run of `runs` together, into `out` (its
    /// pairs replaced): the runs are read where they are, not copied together first.
    pub fn sort_dedup_runs<'a, R>(&mut self, runs: R, out: &mut Vec<Pair>, n: usize)
    where
        R: Iterator<Item = &'a [Pair]> + Clone + Sync,
    {
        let len = runs.clone().map(<[Pair]>::len).sum();
        if few(len, n) {
            out.clear();
            runs.for_each(|r| out.extend_from_slice(r));
            out.sort_unstable();
            out.dedup();
            return;
        }
        self.bucket(runs, len, n, out);
    }

    /// The bucket sort of the `len` pairs of `runs` among `n` boxes, into `out` (its pairs
    /// replaced). The pairs are placed in `out`'s spare capacity: zeroed first, its half
    /// megabyte of pairs was written twice a frame on the surgical scene.
    fn bucket<'a, R>(&mut self, runs: R, len: usize, n: usize, out: &mut Vec<Pair>)
    where
        R: Iterator<Item = &'a [Pair]> + Clone + Sync,
    {
        let parts = crate::engines::threads()
            .min(len / MIN_PAIRS_PER_PART)
            .clamp(1, n);
        let per_part = n.div_ceil(parts);
        self.parts.clear();
        self.parts
            .extend((0..n).step_by(per_part).map(|first_box| Part {
                first_box,
                ..Part::default()
            }));
        self.starts.clear();
        self.starts.resize(n, 0);
        self.seconds.resize(len, 0);
        out.clear();
        out.reserve(len);
        let sorted = &mut out.spare_capacity_mut()[..len];
        split(
            &mut self.parts,
            &mut self.starts,
            &mut [],
            &mut [],
            &|part, starts, _, _| part.pairs = count(runs.clone(), part.first_box, starts),
        );
        split(
            &mut self.parts,
            &mut self.starts,
            &mut self.seconds,
            sorted,
            &|part, starts, seconds, sorted| {
                part.kept = place(runs.clone(), part.first_box, starts, seconds, sorted);
            },
        );
        // Parts that dropped repeats leave gaps: close them.
        let (mut at, mut kept) = (0, 0);
        for part in &self.parts {
            // (The first part, and every part after one that dropped none, is in place.)
            if at != kept {
                sorted.copy_within(at..at + part.kept, kept);
            }
            at += part.pairs;
            kept += part.kept;
        }
        // SAFETY: each part wrote its first `part.kept` places (`place`), and those stretches
        // now lie end to end from the start.
        unsafe { out.set_len(kept) };
    }
}

/// Where a part places its pairs: not yet written, so not read before `place` writes them.
type Places<'a> = &'a mut [MaybeUninit<Pair>];

/// Few pairs among many boxes (cross-group detection): the buckets would cost more than a
/// comparison sort. (Two or more pairs mean two or more boxes.)
fn few(pairs: usize, n: usize) -> bool {
    pairs < 2 || pairs * SMALL_SORT_RATIO < n
}

/// Runs `f` on each part with its boxes' `starts` and its stretch of `seconds` and `sorted` (empty
/// slices stay empty), the parts in parallel by `rayon::join`, which needs no allocation.
fn split<F>(parts: &mut [Part], starts: &mut [u32], seconds: &mut [u32], sorted: Places, f: &F)
where
    F: Fn(&mut Part, &mut [u32], &mut [u32], Places) + Sync,
{
    match parts {
        [] => {}
        [one] => f(one, starts, seconds, sorted),
        _ => {
            let (a, b) = parts.split_at_mut(parts.len() / 2);
            let (sa, sb) = starts.split_at_mut(b[0].first_box - a[0].first_box);
            // Before the count (empty stretches) the parts' pair counts are last call's.
            let pairs = a.iter().map(|p| p.pairs).sum::<usize>().min(seconds.len());
            let (ca, cb) = seconds.split_at_mut(pairs);
            let (oa, ob) = sorted.split_at_mut(pairs);
            rayon::join(|| split(a, sa, ca, oa, f), || split(b, sb, cb, ob, f));
        }
    }
}

/// Counts the pairs of each box of the part from `first_box` (`starts` holds its boxes) and
/// turns the counts into the buckets' starts; returns the part's pairs.
fn count<'a>(
    runs: impl Iterator<Item = &'a [Pair]>,
    first_box: usize,
    starts: &mut [u32],
) -> usize {
    // (A loop per run: flattened, the runs cost a state check per pair.)
    for run in runs {
        for p in run {
            if let Some(c) = starts.get_mut((p[0] as usize).wrapping_sub(first_box)) {
                *c += 1;
            }
        }
    }
    let mut sum = 0;
    for s in starts.iter_mut() {
        (*s, sum) = (sum, sum + *s);
    }
    sum as usize
}

/// Places the part's second indices in their buckets, sorts each, and writes the part's distinct
/// pairs to the front of `sorted`; returns how many.
fn place<'a>(
    runs: impl Iterator<Item = &'a [Pair]>,
    first_box: usize,
    starts: &mut [u32],
    seconds: &mut [u32],
    sorted: Places,
) -> usize {
    // `starts[b]` runs ahead as bucket b fills, ending where bucket b + 1 starts.
    for run in runs {
        for p in run {
            if let Some(at) = starts.get_mut((p[0] as usize).wrapping_sub(first_box)) {
                seconds[*at as usize] = p[1];
                *at += 1;
            }
        }
    }
    write_buckets(first_box, starts, seconds, sorted)
}

/// Sorts each bucket of the part from `first_box` (bucket `b` ends at `starts[b]`) and writes
/// its distinct pairs to the front of `sorted`; returns how many. Compiled with SSE4.1 where the
/// CPU has it: a bucket of four, the surgical scene's usual one, is then sorted and written in
/// vector registers (`four_distinct`), which took the pass from about 150-180 to 70-90 µs a
/// frame (the frame's pairs sorted over and over on the Intel CPU of docs/engines.md).
#[multiversion::multiversion(targets("x86_64+sse4.1"))]
fn write_buckets(first_box: usize, starts: &[u32], seconds: &mut [u32], sorted: Places) -> usize {
    let (mut kept, mut begin) = (0, 0);
    for (b, &end) in starts.iter().enumerate() {
        let bucket = &mut seconds[begin..end as usize];
        begin = end as usize;
        let first = (first_box + b) as u32;
        multiversion::target::match_target! {
            "x86_64+sse4.1" => {
                if let (Ok(four), Some(Ok(out))) = (
                    <&mut [u32; 4]>::try_from(&mut *bucket),
                    sorted.get_mut(kept..kept + 4).map(<&mut [_; 4]>::try_from),
                ) {
                    // SAFETY: this form of the function runs only where the CPU has SSE4.1.
                    if unsafe { four_distinct(first, four, out) } {
                        kept += 4;
                        continue;
                    }
                }
            }
            _ => {}
        }
        sort_bucket(bucket);
        // No index reaches `u32::MAX` (at most 2^32 - 2 boxes), so it marks "no previous
        // second".
        let mut last = u32::MAX;
        for &j in bucket.iter() {
            sorted[kept].write([first, j]);
            kept += usize::from(j != last);
            last = j;
        }
    }
    kept
}

/// Sorts a bucket of four second indices in a vector register (the network of `sort_bucket`)
/// and, when no two are equal, writes its four pairs with first index `first` to `out` and
/// returns true; else leaves the bucket sorted, writes nothing and returns false.
/// SAFETY: the CPU must have SSE4.1.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse4.1")]
unsafe fn four_distinct(
    first: u32,
    bucket: &mut [u32; 4],
    out: &mut [MaybeUninit<Pair>; 4],
) -> bool {
    use std::arch::x86_64::*;
    // SAFETY: the loads and stores are of the bucket's and `out`'s own 16 and 32 bytes.
    unsafe {
        let mut x = _mm_loadu_si128(bucket.as_ptr().cast());
        // Each stage compares every lane with the one the shuffle brings to it, and the blend
        // keeps the minimum in the lower lane of each compared pair (16-bit lanes: two per
        // index): lanes (0, 1) and (2, 3), then (0, 2) and (1, 3), then (1, 2).
        let y = _mm_shuffle_epi32::<0b10_11_00_01>(x);
        x = _mm_blend_epi16::<0b1100_1100>(_mm_min_epu32(x, y), _mm_max_epu32(x, y));
        let y = _mm_shuffle_epi32::<0b01_00_11_10>(x);
        x = _mm_blend_epi16::<0b1111_0000>(_mm_min_epu32(x, y), _mm_max_epu32(x, y));
        let y = _mm_shuffle_epi32::<0b11_01_10_00>(x);
        x = _mm_blend_epi16::<0b0011_0000>(_mm_min_epu32(x, y), _mm_max_epu32(x, y));
        // Lane k against lane k + 1, for k = 0, 1, 2.
        let next = _mm_shuffle_epi32::<0b11_11_10_01>(x);
        let equal = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(x, next))) & 0b0111;
        if equal != 0 {
            _mm_storeu_si128(bucket.as_mut_ptr().cast(), x);
            return false;
        }
        // `[first, j]` pairs: the first index in the even lanes.
        let f = _mm_set1_epi32(first as i32);
        let at = out.as_mut_ptr().cast::<__m128i>();
        _mm_storeu_si128(at, _mm_unpacklo_epi32(f, x));
        _mm_storeu_si128(at.add(1), _mm_unpackhi_epi32(f, x));
    }
    true
}

/// Sorts a bucket's second indices. On the surgical scene 16,219 of the 17,492 buckets hold
/// four pairs, and two in three of them come unsorted: the sorting networks up to four, without
/// a branch, took the pass over the buckets from about 290 to 200 µs a frame (the frame's pairs
/// sorted over and over on the Intel CPU of docs/engines.md), where an insertion sort and a call
/// of `sort_unstable` per bucket took the same.
#[inline(always)]
fn sort_bucket(bucket: &mut [u32]) {
    match bucket {
        [] | [_] => {}
        [a, b] => [*a, *b] = ordered(*a, *b),
        [a, b, c] => {
            [*a, *b] = ordered(*a, *b);
            [*b, *c] = ordered(*b, *c);
            [*a, *b] = ordered(*a, *b);
        }
        [a, b, c, d] => {
            [*a, *b] = ordered(*a, *b);
            [*c, *d] = ordered(*c, *d);
            [*a, *c] = ordered(*a, *c);
            [*b, *d] = ordered(*b, *d);
            [*b, *c] = ordered(*b, *c);
        }
        _ => bucket.sort_unstable(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every bucket of up to six indices drawn from four values (repeats and ties included)
    /// comes out sorted: the networks for two to four, and the longer ones.
    #[test]
    fn buckets_sort_whatever_their_order() {
        for len in 0..=6u32 {
            for code in 0..4usize.pow(len) {
                let bucket: Vec<u32> = (0..len).map(|k| (code >> (2 * k) & 3) as u32).collect();
                let mut got = bucket.clone();
                sort_bucket(&mut got);
                let mut want = bucket.clone();
                want.sort_unstable();
                assert_eq!(got, want, "{bucket:?}");
            }
        }
    }

    /// Buckets of four pairs, each of the 256 orders of four second indices drawn from four
    /// values (repeats included), sorted and deduplicated as the comparison sort does: the
    /// vector form of a bucket of four, and its way back to the networks on repeats.
    #[test]
    fn buckets_of_four_sort_and_dedup() {
        let values = [1000, 1001, 1002, 1003];
        let mut pairs: Vec<Pair> = (0..256u32)
            .flat_map(|code| (0..4).map(move |k| [code, values[(code >> (2 * k) & 3) as usize]]))
            .collect();
        // A few buckets of other lengths between them.
        pairs.extend([
            [300, 1000],
            [301, 1002],
            [301, 1001],
            [302, 1003],
            [302, 1003],
        ]);
        pairs.reverse();
        let mut want = pairs.clone();
        want.sort_unstable();
        want.dedup();
        let mut sorter = PairSorter::default();
        sorter.sort_dedup(&mut pairs, 1004);
        assert_eq!(pairs, want);
    }

    /// Pairs with repeats, sorted by each part count against the comparison sort, whole and in
    /// runs.
    #[test]
    fn parts_sort_and_dedup_as_one() {
        let n = 3000;
        let mut state = 12345u64;
        let mut next = |m: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % m
        };
        let mut pairs: Vec<Pair> = (0..70_000)
            .map(|_| {
                let i = next(n - 1);
                [i as u32, (i + 1 + next(n - 1 - i)) as u32]
            })
            .collect();
        pairs.extend_from_within(..500);
        let mut want = pairs.clone();
        want.sort_unstable();
        want.dedup();
        assert!(want.len() < pairs.len(), "the input repeats pairs");
        for threads in [1, 2, 3, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut sorter = PairSorter::default();
            let mut got = pairs.clone();
            pool.install(|| sorter.sort_dedup(&mut got, n as usize));
            assert_eq!(got, want, "{threads} threads");
            // Again on the same buffers, as the engines call it frame after frame.
            let mut again = pairs.clone();
            pool.install(|| sorter.sort_dedup(&mut again, n as usize));
            assert_eq!(again, want, "{threads} threads, second call");
            // The same pairs in runs (one of them empty), read where they lie.
            let (a, rest) = pairs.split_at(12_345);
            let (b, c) = rest.split_at(0);
            let mut runs = vec![[7, 8]];
            pool.install(|| sorter.sort_dedup_runs([a, b, c].into_iter(), &mut runs, n as usize));
            assert_eq!(runs, want, "{threads} threads, in runs");
        }
    }
}
