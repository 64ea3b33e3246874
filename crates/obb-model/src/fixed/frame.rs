//! One frame in the core's formats: the scene quantized and projected, its keys, and the
//! per-pair checks the SAT stage makes (`run.rs` runs a broad phase over it).

use super::config::HwConfig;
use super::margins::Margins;
use super::quantize::{keys, project, quantize, Projected, QObb, QuantizeError};
use super::sat::collide;
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
}
