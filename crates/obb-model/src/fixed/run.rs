//! One frame through the fixed-point model: run a broad phase on the frame's keys, and send its
//! pairs through the SAT stage (keys on all three axes, then the integer SAT). Every broad
//! phase gives the same pairs; only the work differs.

use super::broad;
use super::config::BroadPhase;
use super::cycles::{frame_cycles, FrameCycles};
use super::frame::ModelFrame;
use super::grid::GridWalk;
use super::work::BroadWork;
use crate::engines::{Counters, Pair};
use crate::groups::GroupMask;

impl ModelFrame {
    /// The grid's walk of this frame under `mask`, visit by visit (`grid_clocks::grid_schedule`
    /// plays it clock by clock).
    pub fn grid_walk(&self, mask: &GroupMask) -> GridWalk {
        let mask = self.frame_mask(mask);
        let (_, walk) = broad::run_keeping(self, BroadPhase::Grid, &mask, |_, _| {});
        walk.expect("the grid keeps its walk")
    }

    /// The frame with the configured broad phase and group mask.
    pub fn run(&self) -> ModelRun {
        self.detect(self.cfg.broad_phase, &self.cfg.groups)
    }

    /// The pairs the core reports with broad phase `mode` and `mask` (`frame_mask`), sorted
    /// ascending: each pair the broad phase emits goes through the SAT stage (keys on all three
    /// axes, then the 15 axes). With the broad phase's work and the modelled cycles.
    pub fn detect(&self, mode: BroadPhase, mask: &GroupMask) -> ModelRun {
        let mut stream = Vec::new();
        let mask = self.frame_mask(mask);
        let work = broad::run(self, mode, &mask, |i, j| {
            // The SAT stage orders the pair (the lower index is box A): the integer test is not
            // symmetric in A and B, and every mode must report the same pairs.
            let (a, b) = (i.min(j), i.max(j));
            if self.keys_overlap(a, b) && self.sat(a, b) {
                stream.push([a as u32, b as u32]);
            }
        });
        let mut pairs = stream.clone();
        pairs.sort_unstable();
        pairs.dedup();
        let cycles = frame_cycles(self.streamed().len() as u64, &work);
        ModelRun {
            pairs,
            stream,
            work,
            cycles,
        }
    }
}

/// What one frame of the model gives.
#[derive(Clone, Debug)]
pub struct ModelRun {
    /// The colliding pairs, sorted, each once.
    pub pairs: Vec<Pair>,
    /// The pairs the SAT stage reports, in the order the core sends them, repeats included:
    /// improved-sap may meet a pair on up to six end points; the other modes meet each pair once.
    pub stream: Vec<Pair>,
    /// What the broad phase did (visits, SAT tests, the grid's work).
    pub work: BroadWork,
    /// The frame's clocks, stage by stage.
    pub cycles: FrameCycles,
}

impl ModelRun {
    /// Pairs the SAT stage reports, repeats included (the core's `pairs` counter).
    pub fn reported(&self) -> u64 {
        self.stream.len() as u64
    }

    /// The counters `detect` prints: index pairs the broad phase visited, pairs it sent to the
    /// SAT stage, pairs reported.
    pub fn counters(&self) -> Counters {
        Counters {
            visits: self.work.visits,
            sat_tests: self.work.sat_tests,
            pairs: self.pairs.len() as u64,
        }
    }
}
