//! The occupied cells of a sorted grid, for probing and for the corner layout's stretches: a
//! bitmap with a rank per word, so that a box finds a cell's entries, and a cell its
//! neighbours', in constant time instead of two binary searches.

use crate::aabb::Aabb;

/// Occupancy of the cells, and where each occupied cell's entries lie in the sorted keys.
#[derive(Debug)]
pub(super) struct Occupied {
    /// Bit `c % 64` of word `c / 64`: cell `c` holds an entry.
    bits: Vec<u64>,
    /// Occupied cells before word `w`.
    rank: Vec<u32>,
    /// Start of each occupied cell's entries, in cell order, and the end of the last.
    starts: Vec<u32>,
    /// The union of the entered boxes' AABBs: a probing box outside it meets no entry, and
    /// most tissue lies outside the instruments' bounds.
    pub bounds: Aabb,
}

impl Default for Occupied {
    fn default() -> Self {
        Occupied {
            bits: Vec::new(),
            rank: Vec::new(),
            starts: Vec::new(),
            bounds: Aabb::EMPTY,
        }
    }
}

impl Occupied {
    pub(super) fn clear(&mut self) {
        self.bounds = Aabb::EMPTY;
        self.bits.clear();
        self.rank.clear();
        self.starts.clear();
    }

    /// Indexes sorted entries over a grid of `cells` cells, given each entry's cell in order;
    /// the entered boxes lie in `bounds`.
    pub(super) fn index(
        &mut self,
        entry_cells: impl Iterator<Item = u64>,
        cells: u64,
        bounds: Aabb,
    ) {
        self.clear();
        self.bounds = bounds;
        let words = cells.div_ceil(64) as usize;
        self.bits.resize(words, 0);
        let (mut last, mut len) = (None, 0);
        for (p, cell) in entry_cells.enumerate() {
            if last != Some(cell) {
                self.bits[(cell / 64) as usize] |= 1 << (cell % 64);
                self.starts.push(p as u32);
                last = Some(cell);
            }
            len = p + 1;
        }
        self.starts.push(len as u32);
        self.rank_words();
    }

    /// Indexes the entries of unsorted `keys`, cells of a grid of `cells` cells, where a
    /// counting sort by cell would place them (stable: a cell's entries in the order of
    /// `keys`): the bitmap, its ranks, and each occupied cell's start; and each key's ordinal
    /// into `ordinals`. The caller places each entry at the next place of its cell (`starts`).
    #[inline(always)]
    pub(super) fn count(&mut self, keys: &[u64], cells: u64, ordinals: &mut Vec<u32>) {
        self.clear();
        self.bits.resize(cells.div_ceil(64) as usize, 0);
        for &k in keys {
            self.bits[(k / 64) as usize] |= 1 << (k % 64);
        }
        let occupied = self.rank_words();
        // Each cell's count in the slot after its own, then summed: the slots become starts.
        self.starts.resize(occupied + 1, 0);
        // (A plain loop: a closure would be compiled without the caller's popcount.)
        ordinals.resize(keys.len(), 0);
        for (o, &k) in ordinals.iter_mut().zip(keys) {
            let cell = self.ordinal(k);
            self.starts[cell + 1] += 1;
            *o = cell as u32;
        }
        for r in 1..self.starts.len() {
            self.starts[r] += self.starts[r - 1];
        }
    }

    /// The occupied cells before each word of the bitmap; returns all the occupied cells.
    #[inline(always)]
    fn rank_words(&mut self) -> usize {
        let mut sum = 0;
        self.rank.extend(self.bits.iter().map(|w| {
            let before = sum;
            sum += w.count_ones();
            before
        }));
        sum as usize
    }

    /// Where each occupied cell's entries start, in cell order, and the end of the last.
    pub(super) fn starts(&self) -> &[u32] {
        &self.starts
    }

    /// The occupied cells before `cell`: the place of `cell` among them when it is occupied.
    #[inline(always)]
    pub(super) fn ordinal(&self, cell: u64) -> usize {
        self.before(cell).0
    }

    /// Whether `index` has run since the last `clear`.
    pub(super) fn is_indexed(&self) -> bool {
        !self.bits.is_empty()
    }

    /// The occupied cells before `cell`, and whether `cell` is occupied.
    #[inline(always)]
    fn before(&self, cell: u64) -> (usize, bool) {
        let (w, b) = ((cell / 64) as usize, cell % 64);
        let word = self.bits[w];
        let ordinal = self.rank[w] + (word & ((1 << b) - 1)).count_ones();
        (ordinal as usize, word & (1 << b) != 0)
    }

    /// The range of sorted entries in `cell`, empty when it holds none.
    #[inline]
    pub(super) fn entries(&self, cell: u64) -> std::ops::Range<usize> {
        match self.before(cell) {
            (ordinal, true) => self.starts[ordinal] as usize..self.starts[ordinal + 1] as usize,
            (_, false) => 0..0,
        }
    }
}
