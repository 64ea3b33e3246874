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
    /// A haptic frame (`resident_groups`): how many boxes, the first, are the last update
    /// frame's resident boxes, already in the core; the frame streams only the others. `None`:
    /// the frame loads every box (with resident groups, an update frame).
    pub resident: Option<usize>,
}

impl ModelFrame {
    /// Quantizes and projects `scene`; fails on a box that does not fit the configuration.
    pub fn new(scene: &Scene, cfg: &HwConfig) -> Result<ModelFrame, QuantizeError> {
        let margins = Margins::new(cfg);
        let obbs = quantize(scene, cfg)?;
        let projected: Vec<Projected> = obbs.iter().map(|b| project(b, cfg, &margins)).collect();
        let keys = projected.iter().map(|p| keys(p, cfg)).collect();
        // An update frame loads the resident groups' boxes first: the core keeps those
        // indices for the haptic frames.
        let resident = obbs.iter().take_while(|b| cfg.is_resident(b.group)).count();
        if let Some(k) = (resident..obbs.len()).find(|&k| cfg.is_resident(obbs[k].group)) {
            return Err(QuantizeError::ResidentOrder {
                index: k,
                group: obbs[k].group,
                after: resident,
            });
        }
        Ok(ModelFrame {
            cfg: cfg.clone(),
            margins,
            obbs,
            projected,
            keys,
            resident: None,
        })
    }

    /// The haptic frame that follows this one (an update frame, or a haptic frame after one):
    /// its resident boxes stay, `streamed` (boxes of the other groups) follows them.
    pub fn haptic(&self, streamed: &Scene) -> Result<ModelFrame, QuantizeError> {
        let kept = self.resident_boxes();
        if let Some((index, b)) = streamed
            .obbs
            .iter()
            .enumerate()
            .find(|(_, b)| self.cfg.is_resident(b.group))
        {
            return Err(QuantizeError::ResidentStreamed {
                index,
                group: b.group,
            });
        }
        if kept + streamed.obbs.len() > self.cfg.capacity as usize {
            return Err(QuantizeError::Capacity {
                count: kept + streamed.obbs.len(),
                capacity: self.cfg.capacity,
            });
        }
        let mut next = ModelFrame::new(streamed, &self.cfg)?;
        next.obbs.splice(0..0, self.obbs[..kept].iter().copied());
        next.projected
            .splice(0..0, self.projected[..kept].iter().copied());
        next.keys.splice(0..0, self.keys[..kept].iter().copied());
        next.resident = Some(kept);
        Ok(next)
    }

    /// How many boxes, the first, are resident: in the core when the next haptic frame starts.
    pub fn resident_boxes(&self) -> usize {
        self.resident.unwrap_or_else(|| {
            self.obbs
                .iter()
                .take_while(|b| self.cfg.is_resident(b.group))
                .count()
        })
    }

    /// The boxes the frame streams into the core: all but a haptic frame's resident ones.
    pub fn streamed(&self) -> &[QObb] {
        &self.obbs[self.resident.unwrap_or(0)..]
    }

    /// The group mask the core applies to this frame: `mask`, but a haptic frame reports no
    /// pair of two resident groups (the update frame did).
    pub fn frame_mask(&self, mask: &GroupMask) -> GroupMask {
        match self.resident {
            None => mask.clone(),
            Some(_) => HwConfig {
                groups: mask.clone(),
                ..self.cfg.clone()
            }
            .haptic_mask(),
        }
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
