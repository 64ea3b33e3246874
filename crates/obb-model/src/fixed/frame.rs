//! One frame through the fixed-point model: quantize, project, run a broad phase on the keys,
//! and send its pairs through the SAT stage (keys on all three axes, then the integer SAT).
//! Every broad phase gives the same pairs; only the work differs.

use super::broad::{self, BroadWork};
use super::config::{BroadPhase, HwConfig};
use super::cycles::{frame_cycles, FrameCycles};
use super::grid::GridWalk;
use super::margins::Margins;
use super::quantize::{keys, project, quantize, Projected, QObb, QuantizeError};
use super::sat::collide;
use crate::engines::{Counters, Pair};
use crate::groups::GroupMask;
use crate::scene::Scene;

/// A scene in the core's formats, projected.
#[derive(Clone, Debug)]
pub struct ModelFrame {
    pub cfg: HwConfig,
    pub margins: Margins,
    pub obbs: Vec<QObb>,
    pub projected: Vec<Projected>,
    /// Sort keys (min, max) per box.
    pub keys: Vec<([u64; 3], [u64; 3])>,
}

impl ModelFrame {
    /// Quantizes and projects `scene`; fails on a box that does not fit the configuration.
    pub fn new(scene: &Scene, cfg: &HwConfig) -> Result<ModelFrame, QuantizeError> {
        let margins = Margins::new(cfg);
        let obbs = quantize(scene, cfg)?;
        let projected: Vec<Projected> = obbs.iter().map(|b| project(b, cfg, &margins)).collect();
        let keys = projected.iter().map(|p| keys(p, cfg)).collect();
        Ok(ModelFrame {
            cfg: cfg.clone(),
            margins,
            obbs,
            projected,
            keys,
        })
    }

    /// Closed overlap of the sort-key intervals on all three axes.
    pub fn keys_overlap(&self, i: usize, j: usize) -> bool {
        let ((a0, a1), (b0, b1)) = (&self.keys[i], &self.keys[j]);
        (0..3).all(|x| a0[x] <= b1[x] && b0[x] <= a1[x])
    }

    /// The integer SAT on boxes `i` (as A) and `j` (as B).
    pub fn sat(&self, i: usize, j: usize) -> bool {
        collide(
            &self.obbs[i],
            &self.projected[i],
            &self.obbs[j],
            &self.projected[j],
            &self.margins,
            self.cfg.frac_bits(),
        )
    }

    /// The grid's walk of this frame under `mask`, visit by visit (`grid_clocks::grid_schedule`
    /// plays it clock by clock).
    pub fn grid_walk(&self, mask: &GroupMask) -> GridWalk {
        let (_, walk) = broad::run_keeping(self, BroadPhase::Grid, mask, |_, _| {});
        walk.expect("the grid keeps its walk")
    }

    /// The frame with the configured broad phase and group mask.
    pub fn run(&self) -> ModelRun {
        self.detect(self.cfg.broad_phase, &self.cfg.groups)
    }

    /// The pairs the core reports with broad phase `mode` and `mask`, sorted ascending: each
    /// pair the broad phase emits goes through the SAT stage (keys on all three axes, then the
    /// 15 axes). With the broad phase's work and the modelled cycles.
    pub fn detect(&self, mode: BroadPhase, mask: &GroupMask) -> ModelRun {
        let mut stream = Vec::new();
        let work = broad::run(self, mode, mask, |i, j| {
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
        let cycles = frame_cycles(self.obbs.len() as u64, &work);
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
    pub pairs: Vec<Pair>,
    /// The pairs the SAT stage reports, in the order the core sends them, repeats included:
    /// improved-sap may meet a pair on up to six end points; the other modes meet each pair once.
    pub stream: Vec<Pair>,
    pub work: BroadWork,
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
            candidates: self.work.visited,
            sat: self.work.emitted,
            pairs: self.pairs.len() as u64,
        }
    }
}
