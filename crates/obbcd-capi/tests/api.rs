//! The C ABI called as C calls it: pairs equal brute force's on a moving scene whose groups
//! change and empty, with resident groups or none, and every misuse gets a status and a reason.

mod common;

use obb_model::generate::SurgicalMotion;
use obb_model::{GroupMask, Obb};
use obbcd_c::*;
use std::collections::BTreeMap;
use std::ffi::{CStr, CString};
use std::ptr::{null, null_mut};

fn to_c(b: &Obb) -> ObbcdBox {
    ObbcdBox {
        center: b.center,
        axes: b.axes,
        half: b.half,
    }
}

fn last_error() -> String {
    // SAFETY: obbcd_last_error returns a NUL-terminated string.
    unsafe { CStr::from_ptr(obbcd_last_error()) }
        .to_str()
        .unwrap()
        .to_string()
}

/// An engine, freed on drop.
struct Engine(*mut ObbcdEngine);

impl Engine {
    fn new(mask: &str, statics: &[u32], threads: u32) -> Engine {
        let mask = CString::new(mask).unwrap();
        let mut e = null_mut();
        // SAFETY: valid string, slice and output.
        let st = unsafe {
            obbcd_engine_new(
                mask.as_ptr(),
                statics.as_ptr(),
                statics.len(),
                threads,
                &mut e,
            )
        };
        assert_eq!(st, ObbcdStatus::Ok, "{}", last_error());
        Engine(e)
    }

    fn set(&mut self, group: u32, boxes: &[ObbcdBox]) -> ObbcdStatus {
        // SAFETY: a live engine and a valid slice.
        unsafe { obbcd_set_boxes(self.0, group, boxes.as_ptr(), boxes.len()) }
    }

    fn pairs(&mut self) -> Vec<ObbcdPair> {
        let (mut p, mut n) = (null(), 0);
        // SAFETY: a live engine; the pointer is read before the next call.
        unsafe {
            assert_eq!(obbcd_pairs(self.0, &mut p, &mut n), ObbcdStatus::Ok);
            std::slice::from_raw_parts(p, n).to_vec()
        }
    }

    fn detect(&mut self) -> Vec<ObbcdPair> {
        let mut n = usize::MAX;
        // SAFETY: a live engine.
        let st = unsafe { obbcd_detect(self.0, &mut n) };
        assert_eq!(st, ObbcdStatus::Ok, "{}", last_error());
        let pairs = self.pairs();
        assert_eq!(pairs.len(), n);
        pairs
    }

    fn contacts(&mut self) -> Vec<ObbcdContact> {
        let (mut c, mut n) = (null(), 0);
        // SAFETY: a live engine; the pointer is read before the next call.
        unsafe {
            assert_eq!(obbcd_contacts(self.0, &mut c, &mut n), ObbcdStatus::Ok);
            std::slice::from_raw_parts(c, n).to_vec()
        }
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: created by obbcd_engine_new, freed once.
        unsafe { obbcd_engine_free(self.0) }
    }
}

/// The surgical motion through the C ABI, with a fourth group (a loose instrument) that grows,
/// shrinks and empties, so groups are laid out again between frames.
fn run_motion(mask: &str, statics: &[u32], threads: u32) -> usize {
    let motion = SurgicalMotion::new(700, 11).unwrap();
    let parsed: GroupMask = mask.parse().unwrap();
    let mut engine = Engine::new(mask, statics, threads);
    let mut groups: BTreeMap<u32, Vec<Obb>> = BTreeMap::new();
    let mut found = 0;
    for k in (0..2000).step_by(25) {
        let f = motion.frame(k);
        for &g in &f.replace {
            let boxes: Vec<Obb> = f.obbs.iter().filter(|b| b.group == g).cloned().collect();
            let c: Vec<ObbcdBox> = boxes.iter().map(to_c).collect();
            assert_eq!(engine.set(g, &c), ObbcdStatus::Ok, "{}", last_error());
            groups.insert(g, boxes);
        }
        // Group 3: k % 7 boxes copied from the tissue's first ones, shifted up a little.
        let loose: Vec<Obb> = groups[&0]
            .iter()
            .take(k % 7)
            .map(|b| {
                let mut b = b.clone();
                b.center[2] += 0.1;
                b.group = 3;
                b
            })
            .collect();
        assert_eq!(
            engine.set(3, &loose.iter().map(to_c).collect::<Vec<_>>()),
            ObbcdStatus::Ok
        );
        groups.insert(3, loose);
        let got = engine.detect();
        let want: Vec<ObbcdPair> = common::brute(&groups, statics, &parsed)
            .into_iter()
            .map(|(p, _, _)| p)
            .collect();
        assert_eq!(got, want, "frame {k}, mask {mask}");
        let contacts = engine.contacts();
        assert_eq!(contacts.len(), got.len());
        assert!(contacts
            .iter()
            .all(|c| c.depth >= 0.0
                && (c.normal.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12));
        found += got.len();
    }
    found
}

#[test]
fn moving_scene_equals_brute_force() {
    for (mask, statics, threads) in [
        ("cross", &[0][..], 1),
        ("all", &[0][..], 2),
        ("0-1,0-3,1-2", &[0, 3][..], 1),
        ("cross", &[][..], 2),
    ] {
        assert!(
            run_motion(mask, statics, threads) > 0,
            "{mask}: no pairs at all"
        );
    }
}

#[test]
fn misuse_gets_a_status_and_a_reason() {
    let mut out = null_mut();
    let cross = CString::new("cross").unwrap();
    // SAFETY: every pointer is valid or NULL, as each case says.
    unsafe {
        assert_eq!(
            obbcd_engine_new(cross.as_ptr(), null(), 0, 1, null_mut()),
            ObbcdStatus::NullArgument
        );
        assert_eq!(
            obbcd_engine_new(null(), null(), 0, 1, &mut out),
            ObbcdStatus::NullArgument
        );
        assert!(last_error().contains("group_mask is NULL"));
        assert_eq!(
            obbcd_engine_new(cross.as_ptr(), null(), 2, 1, &mut out),
            ObbcdStatus::NullArgument
        );
        let bad = CString::new("0-x").unwrap();
        assert_eq!(
            obbcd_engine_new(bad.as_ptr(), null(), 0, 1, &mut out),
            ObbcdStatus::InvalidArgument
        );
        assert!(
            last_error().contains("`x` in `0-x` is not a group number"),
            "{}",
            last_error()
        );
        let latin1 = [0xe9u8, 0];
        assert_eq!(
            obbcd_engine_new(latin1.as_ptr().cast(), null(), 0, 1, &mut out),
            ObbcdStatus::InvalidArgument
        );
        assert_eq!(
            obbcd_engine_new(cross.as_ptr(), null(), 0, 100_000, &mut out),
            ObbcdStatus::InvalidArgument
        );
        assert!(last_error().contains("threads is 100000, more than the limit of 256"));
        assert!(out.is_null());
        assert_eq!(
            obbcd_set_boxes(null_mut(), 0, null(), 0),
            ObbcdStatus::NullArgument
        );
        assert_eq!(
            obbcd_detect(null_mut(), null_mut()),
            ObbcdStatus::NullArgument
        );
        assert!(last_error().contains("engine is NULL"));
        obbcd_engine_free(null_mut());
    }

    let mut e = Engine::new("cross", &[0], 1);
    let plate = |x: f64| to_c(&Obb::aligned([x, 0.0, 0.0], [0.5, 0.5, 0.1], 0));
    assert_eq!(e.set(0, &[plate(0.0), plate(1.0)]), ObbcdStatus::Ok);
    assert_eq!(e.set(1, &[plate(0.9)]), ObbcdStatus::Ok);
    let before = e.detect();
    assert_eq!(before.len(), 2);
    // Bad boxes are refused, name their group, index and field, and change nothing.
    let mut nan = plate(5.0);
    nan.center[1] = f64::NAN;
    let mut skew = plate(5.0);
    skew.axes[0] = [1.0, 0.1, 0.0];
    let mut negative = plate(5.0);
    negative.half[2] = -0.1;
    for (bad, says) in [
        (nan, "group 1: obb 1: field `center` has NaN"),
        (skew, "group 1: obb 1: field `axes` are not orthonormal"),
        (negative, "group 1: obb 1: field `half` has -0.1"),
    ] {
        assert_eq!(e.set(1, &[plate(0.9), bad]), ObbcdStatus::InvalidBox);
        assert!(last_error().contains(says), "{} / {says}", last_error());
        assert_eq!(e.detect(), before);
    }
    // SAFETY: a live engine; NULL boxes with a count are refused before any read.
    unsafe {
        assert_eq!(
            obbcd_set_boxes(e.0, 1, null(), 3),
            ObbcdStatus::NullArgument
        );
        // A count no array can have is refused before the boxes are read.
        let one = plate(0.9);
        assert_eq!(
            obbcd_set_boxes(e.0, 1, &one, usize::MAX),
            ObbcdStatus::InvalidArgument
        );
        assert!(
            last_error().contains("more than the limit of 268435456 boxes"),
            "{}",
            last_error()
        );
        assert_eq!(
            obbcd_pairs(e.0, null_mut(), null_mut()),
            ObbcdStatus::NullArgument
        );
        assert_eq!(obbcd_set_boxes(e.0, 1, null(), 0), ObbcdStatus::Ok);
    }
    // Setting boxes drops the last detection's pairs and contacts.
    assert!(e.pairs().is_empty() && e.contacts().is_empty());
    assert_eq!(e.detect(), []);
}
