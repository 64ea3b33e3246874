//! One frame through the fixed-point model: quantize, project, then every pair whose keys
//! overlap on all three axes (and that the mask allows) through the integer SAT. The result is
//! the set of pairs the core reports, whatever its broad phase; the broad phases' candidate
//! orders and cycle counts are modelled stage by stage on top of it.

use super::config::HwConfig;
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

    /// The integer SAT on boxes `i` and `j`.
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

    /// The pairs the core reports under `mask`: keys overlapping on all axes, then the SAT.
    /// Found by a sweep over the x keys; sorted ascending. `candidates` counts the pairs whose
    /// keys overlap on x, `sat` those that reach the SAT.
    pub fn pairs(&self, mask: &GroupMask) -> (Vec<Pair>, Counters) {
        let mut order: Vec<u32> = (0..self.obbs.len() as u32).collect();
        order.sort_by_key(|&i| (self.keys[i as usize].0[0], i));
        let mut c = Counters::default();
        let mut out = Vec::new();
        for (p, &i) in order.iter().enumerate() {
            let i = i as usize;
            for &j in &order[p + 1..] {
                let j = j as usize;
                if self.keys[j].0[0] > self.keys[i].1[0] {
                    break;
                }
                c.candidates += 1;
                if !mask.allows(self.obbs[i].group, self.obbs[j].group) || !self.keys_overlap(i, j)
                {
                    continue;
                }
                c.sat += 1;
                if self.sat(i, j) {
                    out.push([i.min(j) as u32, i.max(j) as u32]);
                }
            }
        }
        out.sort_unstable();
        c.pairs = out.len() as u64;
        (out, c)
    }
}
