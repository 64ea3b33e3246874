//! Classes below the cell in a key: group ranks and start flags, and which class pairs are wanted.

use super::{ALL_STARTS, FLAG_BITS};
use crate::aabb::Aabb;
use crate::groups::GroupMask;
use crate::prepared::Frame;
use crate::radix::bits_for;

/// Group ranks in a key at most (3 bits): with more groups the mask is checked pair by pair.
pub(super) const MAX_RANKS: usize = 8;

/// How one frame's groups enter the keys.
#[derive(Debug, Default)]
pub(super) struct Ranks {
    /// The distinct groups (up to `MAX_RANKS`) with their sizes, ascending by group.
    groups: Vec<(u32, usize)>,
    /// Each box's rank (its group's place in `groups`), empty when `bits` is 0.
    rank: Vec<u8>,
    /// Rank bits in a key.
    pub(super) bits: u32,
    /// `allowed[a][b]`: the mask allows pairs of ranks a and b.
    pub(super) allowed: [[bool; MAX_RANKS]; MAX_RANKS],
    /// More groups than ranks: every pair's groups are checked against the mask.
    pub(super) pairwise: bool,
    /// The most populous group, when the mask excludes its own pairs (see `Grid::build`).
    pub(super) sparse: Option<u32>,
    /// The union of each rank's AABBs, when the mask tells ranks apart (`bits` > 0).
    bounds: [Aabb; MAX_RANKS],
}

impl Ranks {
    pub(super) fn update(&mut self, boxes: &Frame, mask: &GroupMask) {
        self.groups.clear();
        self.rank.clear();
        self.bits = 0;
        self.allowed = [[false; MAX_RANKS]; MAX_RANKS];
        self.pairwise = false;
        self.sparse = None;
        if *mask == GroupMask::All {
            // Every pair is wanted: one rank.
            self.allowed[0][0] = true;
            return;
        }
        // Boxes of one group mostly lie together: count runs, not boxes.
        for run in boxes.groups.chunk_by(|a, b| a == b) {
            let (g, len) = (run[0], run.len());
            if let Some((_, n)) = self.groups.iter_mut().find(|(h, _)| *h == g) {
                *n += len;
            } else if self.groups.len() < MAX_RANKS {
                self.groups.push((g, len));
            } else {
                self.groups.clear();
                self.allowed[0][0] = true;
                self.pairwise = true;
                return;
            }
        }
        self.groups.sort_unstable();
        for (a, &(ga, _)) in self.groups.iter().enumerate() {
            for (b, &(gb, _)) in self.groups.iter().enumerate() {
                self.allowed[a][b] = mask.allows(ga, gb);
            }
        }
        self.bits = bits_for(self.groups.len().saturating_sub(1) as u64);
        self.bounds = [Aabb::EMPTY; MAX_RANKS];
        if self.bits > 0 {
            let mut at = 0;
            for run in boxes.groups.chunk_by(|a, b| a == b) {
                let r = self.groups.iter().position(|(h, _)| *h == run[0]);
                let r = r.expect("every group was counted");
                self.rank.extend(std::iter::repeat_n(r as u8, run.len()));
                let run_aabbs = &boxes.aabbs[at..at + run.len()];
                self.bounds[r] = self.bounds[r].union(&Aabb::union_of(run_aabbs));
                at += run.len();
            }
        }
        self.sparse = self
            .groups
            .iter()
            .max_by_key(|(g, n)| (*n, std::cmp::Reverse(*g)))
            .filter(|&&(g, _)| self.groups.len() > 1 && !mask.allows(g, g))
            .map(|&(g, _)| g);
    }

    /// Whether box `i`, of AABB `b`, may overlap a box of a group the mask pairs it with: the
    /// AABB of every such box lies in its group's bounds, so a box meeting none of those bounds
    /// has no pair, and the grid leaves it out. (An instrument's boxes far from the tissue and
    /// from the other instrument: in the surgical scene, cross-group, all but a few dozen.)
    #[inline]
    pub(super) fn may_pair(&self, i: usize, b: &Aabb) -> bool {
        if self.bits == 0 {
            return true;
        }
        let allowed = &self.allowed[self.rank(i) as usize];
        (0..self.groups.len()).any(|r| allowed[r] && b.overlaps(&self.bounds[r]))
    }

    /// Whether any pair may exist: some two ranks (or one with itself) that the mask pairs and
    /// whose bounds meet. When none, the grid has nothing to do (two instruments apart, for a
    /// resident tissue's haptic frame).
    pub(super) fn any_pair(&self) -> bool {
        if self.bits == 0 {
            return self.allowed[0][0];
        }
        let n = self.groups.len();
        (0..n)
            .any(|a| (a..n).any(|b| self.allowed[a][b] && self.bounds[a].overlaps(&self.bounds[b])))
    }

    pub(super) fn rank(&self, i: usize) -> u64 {
        self.rank.get(i).map_or(0, |&r| u64::from(r))
    }

    /// Bits below the cell in a key.
    pub(super) fn class_bits(&self) -> u32 {
        self.bits + FLAG_BITS
    }

    /// The class part of a key.
    pub(super) fn class_mask(&self) -> u64 {
        (1 << self.class_bits()) - 1
    }

    /// Pairs of classes `a` and `b` are at home in their cell and wanted by the mask.
    #[inline]
    pub(super) fn pairs_wanted(&self, a: u64, b: u64) -> bool {
        (a | b) & ALL_STARTS == ALL_STARTS
            && self.allowed[(a >> FLAG_BITS) as usize][(b >> FLAG_BITS) as usize]
    }
}
