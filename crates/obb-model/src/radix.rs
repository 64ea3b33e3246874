//! Stable LSD radix sort of u64 keys with a payload, on buffers kept between calls.
//!
//! The hardware sorts the same way (histogram, prefix sum, stable scatter per digit), and a stable
//! sort by key has exactly one result, so this is also the order the hardware produces.

/// Sorts `keys` (and `vals` alongside) by the low `key_bits` bits of each key, stably, in
/// `ceil(key_bits / max_digit_bits)` passes of equal digits. Scratch space is kept, so repeated
/// calls on inputs of similar size do not allocate.
#[derive(Debug)]
pub struct RadixSorter<V> {
    max_digit_bits: u32,
    tmp_keys: Vec<u64>,
    tmp_vals: Vec<V>,
    /// Digit histograms; u32 halves their cache footprint (at most 2^32 - 1 keys are sorted).
    counts: Vec<u32>,
}

impl<V: Copy> RadixSorter<V> {
    /// `max_digit_bits` from 1 to 16.
    pub fn new(max_digit_bits: u32) -> Self {
        let mut sorter = RadixSorter {
            max_digit_bits: 1,
            tmp_keys: Vec::new(),
            tmp_vals: Vec::new(),
            counts: Vec::new(),
        };
        sorter.set_max_digit_bits(max_digit_bits);
        sorter
    }

    /// Sets the widest digit, 1 to 16 bits, for the sorts that follow.
    pub fn set_max_digit_bits(&mut self, max_digit_bits: u32) {
        assert!(
            (1..=16).contains(&max_digit_bits),
            "radix digit width must be 1..=16 bits, got {max_digit_bits}"
        );
        self.max_digit_bits = max_digit_bits;
    }

    /// Number of passes needed for `key_bits`-bit keys.
    pub fn passes(&self, key_bits: u32) -> u32 {
        key_bits.div_ceil(self.max_digit_bits)
    }

    /// Digit width for `key_bits`-bit keys: the passes split the key evenly, so that (say) 24
    /// bits take two passes of 12 rather than 12 + 12 of a wider table or 11 + 11 + 2.
    pub fn digit_bits(&self, key_bits: u32) -> u32 {
        key_bits.div_ceil(self.passes(key_bits).max(1))
    }

    pub fn sort(&mut self, keys: &mut Vec<u64>, vals: &mut Vec<V>, key_bits: u32) {
        self.sort_bits(keys, vals, 0, key_bits);
    }

    /// Sorts `keys` (and `vals` alongside) stably by their bits `low..key_bits` only: keys
    /// equal in those bits keep their order, whatever their lower bits.
    pub fn sort_bits(&mut self, keys: &mut Vec<u64>, vals: &mut Vec<V>, low: u32, key_bits: u32) {
        assert_eq!(keys.len(), vals.len(), "one payload per key");
        assert!(keys.len() < u32::MAX as usize, "at most 2^32 - 2 keys");
        let n = keys.len();
        let key_bits = key_bits.min(64);
        let low = low.min(key_bits);
        let passes = self.passes(key_bits - low);
        if n < 2 || passes == 0 {
            return;
        }
        let digit_bits = self.digit_bits(key_bits - low);
        let radix = 1usize << digit_bits;
        let mask = (radix - 1) as u64;
        // All digit histograms in one read of the keys (the hardware counts the next digit's
        // histogram during the current pass to the same effect).
        self.counts.clear();
        self.counts.resize(radix * passes as usize, 0);
        for &k in keys.iter() {
            for (p, hist) in self.counts.chunks_exact_mut(radix).enumerate() {
                hist[((k >> (low + p as u32 * digit_bits)) & mask) as usize] += 1;
            }
        }
        // Every slot of the scratch is written by each pass (a stable scatter is a
        // permutation), so only its length matters, not its contents.
        self.tmp_keys.resize(n, 0);
        if self.tmp_vals.len() != n {
            self.tmp_vals.clear();
            self.tmp_vals.extend_from_slice(vals);
        }
        for p in 0..passes as usize {
            let hist = &mut self.counts[p * radix..(p + 1) * radix];
            // A digit that is the same in every key leaves the order as it is.
            if hist.contains(&(n as u32)) {
                continue;
            }
            let mut sum = 0;
            for c in hist.iter_mut() {
                let here = *c;
                *c = sum;
                sum += here;
            }
            let shift = low + p as u32 * digit_bits;
            let (tk, tv) = (&mut self.tmp_keys[..n], &mut self.tmp_vals[..n]);
            for (&k, &v) in keys.iter().zip(vals.iter()) {
                let d = ((k >> shift) & mask) as usize;
                let at = hist[d] as usize;
                hist[d] += 1;
                tk[at] = k;
                tv[at] = v;
            }
            std::mem::swap(keys, &mut self.tmp_keys);
            std::mem::swap(vals, &mut self.tmp_vals);
        }
    }
}

/// Bits needed to hold `max` (0 for 0).
pub fn bits_for(max: u64) -> u32 {
    64 - max.leading_zeros()
}
