//! Detection engines. Every engine reports the same set: the pairs (i, j), i < j, that the
//! group mask allows and for which [`Frame::collide`] holds, sorted ascending.

mod brute;
pub(crate) mod endpoints;
mod grid;
mod improved_sap;
mod pair_sort;
mod sap;
mod sweep;
mod threads;

pub use brute::Brute;
pub use grid::{Grid, GridStats, Resident, RigidResident};
pub use improved_sap::ImprovedSap;
pub(crate) use pair_sort::PairSorter;
pub use sap::Sap;
pub use sweep::Sweep;
pub use threads::on_this_thread;
pub(crate) use threads::threads;

use crate::groups::GroupMask;
use crate::prepared::Frame;
use std::fmt;
use std::str::FromStr;

/// A colliding pair of box indices, `[i, j]` with i < j.
pub type Pair = [u32; 2];

/// What an engine did in one detection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Pairs the broad phase examined (allowed by the mask): all pairs for `brute`, the per-axis
    /// overlaps summed over x, y, z for `sap`, the index pairs Algorithm 2 visits for
    /// `improved-sap`, the pairs walked for `sweep`, the pairs met inside cells for `grid`.
    pub visits: u64,
    /// Calls of the narrow phase (AABB check and 15-axis SAT).
    pub sat_tests: u64,
    /// Colliding pairs reported.
    pub pairs: u64,
}

impl std::ops::AddAssign for Counters {
    fn add_assign(&mut self, o: Counters) {
        self.visits += o.visits;
        self.sat_tests += o.sat_tests;
        self.pairs += o.pairs;
    }
}

/// A detection engine. Engines keep their buffers between calls.
pub trait Engine: Send {
    fn kind(&self) -> EngineKind;
    /// Fills `out` with the colliding pairs, sorted ascending, and returns the counters.
    fn detect(&mut self, boxes: &Frame, mask: &GroupMask, out: &mut Vec<Pair>) -> Counters;
}

/// The engines, by their command-line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EngineKind {
    Brute,
    Sap,
    ImprovedSap,
    Sweep,
    Grid,
}

impl EngineKind {
    pub const ALL: [EngineKind; 5] = [
        EngineKind::Brute,
        EngineKind::Sap,
        EngineKind::ImprovedSap,
        EngineKind::Sweep,
        EngineKind::Grid,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EngineKind::Brute => "brute",
            EngineKind::Sap => "sap",
            EngineKind::ImprovedSap => "improved-sap",
            EngineKind::Sweep => "sweep",
            EngineKind::Grid => "grid",
        }
    }

    pub fn build(self) -> Box<dyn Engine> {
        match self {
            EngineKind::Brute => Box::new(Brute),
            EngineKind::Sap => Box::<Sap>::default(),
            EngineKind::ImprovedSap => Box::<ImprovedSap>::default(),
            EngineKind::Sweep => Box::<Sweep>::default(),
            EngineKind::Grid => Box::<Grid>::default(),
        }
    }
}

impl fmt::Display for EngineKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EngineKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        EngineKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = EngineKind::ALL.iter().map(|k| k.name()).collect();
                format!("unknown engine `{s}`; one of {}", names.join(", "))
            })
    }
}

/// Runs one engine once on prepared boxes: the convenience form for tests and tools.
pub fn detect(kind: EngineKind, boxes: &Frame, mask: &GroupMask) -> (Vec<Pair>, Counters) {
    let mut out = Vec::new();
    let counters = kind.build().detect(boxes, mask, &mut out);
    (out, counters)
}

/// `[min(i, j), max(i, j)]`: also the compare-exchange of the pair sort's sorting networks,
/// compiled to `min` and `max`, without a branch.
#[inline(always)]
pub(crate) fn ordered(i: u32, j: u32) -> Pair {
    [i.min(j), i.max(j)]
}
