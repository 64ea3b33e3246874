//! `obbcd replay --capi`: the frames through the C ABI (crate obbcd-capi) as a C control loop
//! calls it, the tissue (group 0) resident: each replaced group's boxes set, then a detection;
//! with `--rigid`, each instrument's boxes set once and a pose per frame.

use anyhow::{bail, Result};
use obb_model::generate::FrameUpdate;
use obb_model::pose::Pose;
use obb_model::{GroupMask, Obb};
use obbcd_c::{
    obbcd_detect, obbcd_engine_free, obbcd_engine_new, obbcd_last_error, obbcd_set_boxes,
    obbcd_set_pose, ObbcdBox, ObbcdEngine, ObbcdPose, ObbcdStatus,
};
use std::collections::BTreeMap;
use std::ffi::{CStr, CString};
use std::ptr::null_mut;

pub struct CapiRun {
    engine: *mut ObbcdEngine,
    /// The frame's boxes in the ABI's records, by group.
    staged: BTreeMap<u32, Vec<ObbcdBox>>,
}

/// `status`, or an error with the ABI's reason.
fn check(what: &str, status: ObbcdStatus) -> Result<()> {
    if status != ObbcdStatus::Ok {
        // SAFETY: obbcd_last_error returns a NUL-terminated string.
        let why = unsafe { CStr::from_ptr(obbcd_last_error()) };
        bail!("{what}: {}", why.to_string_lossy());
    }
    Ok(())
}

impl CapiRun {
    pub fn new(mask: &GroupMask, threads: usize) -> Result<CapiRun> {
        let mask = CString::new(mask.to_string())?;
        let mut engine = null_mut();
        // SAFETY: a NUL-terminated mask, one static group, a writable output.
        let status = unsafe {
            obbcd_engine_new(mask.as_ptr(), [0].as_ptr(), 1, threads as u32, &mut engine)
        };
        check("obbcd_engine_new", status)?;
        Ok(CapiRun {
            engine,
            staged: BTreeMap::new(),
        })
    }

    /// The frame's boxes as the ABI takes them, by group (not timed: a C caller has them so).
    pub fn stage(&mut self, f: &FrameUpdate) {
        for &g in &f.replace {
            self.stage_group(g, f.obbs.iter().filter(|b| b.group == g));
        }
    }

    /// `group`'s boxes as the ABI takes them.
    pub fn stage_group<'a>(&mut self, group: u32, obbs: impl Iterator<Item = &'a Obb>) {
        let boxes = self.staged.entry(group).or_default();
        boxes.clear();
        boxes.extend(obbs.map(|b| ObbcdBox {
            center: b.center,
            axes: b.axes,
            half: b.half,
        }));
    }

    /// The scene's boxes: every group's as last staged.
    pub fn len(&self) -> usize {
        self.staged.values().map(Vec::len).sum()
    }

    /// Sets the staged boxes of the groups `replace` names and detects: the number of pairs.
    pub fn detect(&mut self, replace: &[u32]) -> Result<usize> {
        for g in replace {
            self.set(*g)?;
        }
        self.detect_only()
    }

    /// Sets the staged boxes of `group`.
    pub fn set(&mut self, group: u32) -> Result<()> {
        let boxes = &self.staged[&group];
        // SAFETY: a live engine and `boxes.len()` boxes.
        let status = unsafe { obbcd_set_boxes(self.engine, group, boxes.as_ptr(), boxes.len()) };
        check(&format!("obbcd_set_boxes (group {group})"), status)
    }

    /// Sets the staged tissue (group 0) if `tissue`, the pose of each of `groups`, and
    /// detects: the number of pairs.
    pub fn detect_posed(&mut self, tissue: bool, groups: &[u32], poses: &[Pose]) -> Result<usize> {
        if tissue {
            self.set(0)?;
        }
        for (g, p) in groups.iter().zip(poses) {
            let pose = ObbcdPose {
                rotation: p.rotation,
                translation: p.translation,
            };
            // SAFETY: a live engine and a pose.
            let status = unsafe { obbcd_set_pose(self.engine, *g, &pose) };
            check(&format!("obbcd_set_pose (group {g})"), status)?;
        }
        self.detect_only()
    }

    /// Detects: the number of pairs.
    fn detect_only(&mut self) -> Result<usize> {
        let mut n = 0;
        // SAFETY: a live engine, a writable count.
        check("obbcd_detect", unsafe { obbcd_detect(self.engine, &mut n) })?;
        Ok(n)
    }
}

// SAFETY: the ABI lets an engine move between threads while no two use it at once; the run
// owns its engine and uses it from one thread at a time.
unsafe impl Send for CapiRun {}

impl Drop for CapiRun {
    fn drop(&mut self) {
        // SAFETY: from obbcd_engine_new, freed once.
        unsafe { obbcd_engine_free(self.engine) }
    }
}
