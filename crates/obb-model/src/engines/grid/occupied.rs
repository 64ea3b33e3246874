//! The occupied cells of a sorted grid, for probing: a bitmap with a rank per word, so that a
//! probing box finds a cell's entries in constant time instead of two binary searches.

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
        let mut sum = 0;
        self.rank.extend(self.bits.iter().map(|w| {
            let before = sum;
            sum += w.count_ones();
            before
        }));
    }

    /// Whether `index` has run since the last `clear`.
    pub(super) fn is_indexed(&self) -> bool {
        !self.bits.is_empty()
    }

    /// The range of sorted entries in `cell`, empty when it holds none.
    #[inline]
    pub(super) fn entries(&self, cell: u64) -> std::ops::Range<usize> {
        let (w, b) = ((cell / 64) as usize, cell % 64);
        let word = self.bits[w];
        if word & (1 << b) == 0 {
            return 0..0;
        }
        let ordinal = (self.rank[w] + (word & ((1 << b) - 1)).count_ones()) as usize;
        self.starts[ordinal] as usize..self.starts[ordinal + 1] as usize
    }
}
