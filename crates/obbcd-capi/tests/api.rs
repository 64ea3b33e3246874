//! The C ABI called as C calls it: pairs equal brute force's on a moving scene whose groups
//! change and empty, with resident groups or none, and on rigid bodies placed by poses; every
//! misuse gets a status and a reason.

mod common;

use obb_model::contact::contact;
use obb_model::generate::SurgicalMotion;
use obb_model::pose::Pose;
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

    fn pose(&mut self, group: u32, pose: &Pose) -> ObbcdStatus {
        let p = ObbcdPose {
            rotation: pose.rotation,
            translation: pose.translation,
        };
        // SAFETY: a live engine and a valid pose.
        unsafe { obbcd_set_pose(self.0, group, &p) }
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

/// A turn by `angle` about z, then a translation by `t`.
fn turn(angle: f64, t: [f64; 3]) -> Pose {
    let (s, c) = angle.sin_cos();
    Pose {
        rotation: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        translation: t,
    }
}

/// The surgical motion's grippers as rigid bodies: each's boxes set once in its own frame, a
/// pose a frame (the tissue, static, set when it changes); and a loose body, group 3, of 40
/// tissue boxes taken from a window that slides every frame (its boxes set again in place,
/// its pose kept), turning about z above the tissue. Every frame's pairs equal brute force's
/// on the boxes placed by the poses, and each contact equals the model's on the placed pair.
#[test]
fn posed_bodies_equal_brute_force() {
    let motion = SurgicalMotion::new(700, 11).unwrap();
    for (mask, threads) in [("cross", 1), ("all", 2), ("0-1,2-3", 1)] {
        let parsed: GroupMask = mask.parse().unwrap();
        let mut engine = Engine::new(mask, &[0], threads);
        let bodies = motion.bodies();
        let groups: Vec<u32> = bodies.iter().map(|b| b[0].group).collect();
        for (g, boxes) in groups.iter().zip(&bodies) {
            let c: Vec<ObbcdBox> = boxes.iter().map(to_c).collect();
            assert_eq!(engine.set(*g, &c), ObbcdStatus::Ok, "{}", last_error());
        }
        let mut placed: BTreeMap<u32, Vec<Obb>> = BTreeMap::new();
        let mut tissue = Vec::new();
        let mut loose = Pose::IDENTITY;
        let (mut found, mut contacts) = (0, 0);
        for k in (0..2000).step_by(20) {
            if let Some(t) = motion.tissue(k) {
                let c: Vec<ObbcdBox> = t.iter().map(to_c).collect();
                assert_eq!(engine.set(0, &c), ObbcdStatus::Ok, "{}", last_error());
                placed.insert(0, t.clone());
                tissue = t;
            }
            for ((g, boxes), pose) in groups.iter().zip(&bodies).zip(motion.poses(k)) {
                assert_eq!(engine.pose(*g, &pose), ObbcdStatus::Ok, "{}", last_error());
                placed.insert(*g, boxes.iter().map(|b| pose.apply(b)).collect());
            }
            // The loose body: in its own frame, centred on the window's first box.
            let from = (k / 20) * 7 % (tissue.len() - 40);
            let origin = tissue[from].center;
            let local: Vec<Obb> = tissue[from..from + 40]
                .iter()
                .map(|b| Obb {
                    center: std::array::from_fn(|x| b.center[x] - origin[x]),
                    group: 3,
                    ..b.clone()
                })
                .collect();
            let c: Vec<ObbcdBox> = local.iter().map(to_c).collect();
            assert_eq!(engine.set(3, &c), ObbcdStatus::Ok, "{}", last_error());
            // A new pose every other frame; in between, the last one is kept.
            if k % 40 == 0 {
                loose = turn(0.01 * k as f64, [origin[0], origin[1], origin[2] + 0.3]);
                assert_eq!(engine.pose(3, &loose), ObbcdStatus::Ok, "{}", last_error());
            }
            placed.insert(3, local.iter().map(|b| loose.apply(b)).collect());

            let got = engine.detect();
            let want = common::brute(&placed, &[0], &parsed);
            let pairs: Vec<ObbcdPair> = want.iter().map(|(p, _, _)| *p).collect();
            assert_eq!(got, pairs, "frame {k}, mask {mask}");
            for (c, (_, a, b)) in engine.contacts().iter().zip(&want) {
                let m = contact(a, b);
                assert_eq!((c.normal, c.depth), (m.normal, m.depth), "frame {k}");
                contacts += 1;
            }
            found += got.len();
        }
        assert!(found > 0 && contacts == found, "{mask}: {found} pairs");
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

    // Poses: refused with a reason, changing nothing.
    assert_eq!(e.set(1, &[plate(0.9)]), ObbcdStatus::Ok);
    assert_eq!(e.detect(), before);
    let mut nan = Pose::IDENTITY;
    nan.rotation[1][2] = f64::NAN;
    let mut skew = Pose::IDENTITY;
    skew.rotation[0] = [1.0, 0.1, 0.0];
    for (group, pose, says) in [
        (
            0,
            Pose::IDENTITY,
            "group 0 is static: its boxes are set, not posed",
        ),
        (
            5,
            Pose::IDENTITY,
            "group 5 has no boxes: set them before its pose",
        ),
        (1, nan, "group 1: the pose has NaN, not a finite number"),
        (1, skew, "group 1: the pose's rotation is not orthonormal"),
        (
            1,
            Pose::translation([0.0, -2e6, 0.0]),
            "group 1: the pose has -2000000, beyond ±1e6",
        ),
        (
            1,
            Pose::translation([999_999.5, 0.0, 0.0]),
            "group 1: the pose places box 0's center at [1000000.4",
        ),
    ] {
        assert_eq!(e.pose(group, &pose), ObbcdStatus::InvalidArgument);
        assert!(last_error().contains(says), "{} / {says}", last_error());
        assert_eq!(e.detect(), before);
    }
    // SAFETY: a live engine; a NULL pose is refused before it is read.
    unsafe {
        assert_eq!(obbcd_set_pose(e.0, 1, null()), ObbcdStatus::NullArgument);
        assert!(last_error().contains("pose is NULL"));
    }
    // A pose near the limit is taken; boxes it would place beyond are refused.
    let far = Pose::translation([999_998.0, 0.0, 0.0]);
    assert_eq!(e.pose(1, &far), ObbcdStatus::Ok, "{}", last_error());
    assert_eq!(e.detect(), []);
    assert_eq!(e.set(1, &[plate(1.5)]), ObbcdStatus::Ok);
    assert_eq!(e.set(1, &[plate(1.5), plate(2.5)]), ObbcdStatus::InvalidBox);
    assert!(
        last_error().contains("group 1: the pose places box 1's center at [1000000.5"),
        "{}",
        last_error()
    );
    // Back home, the pairs of the start.
    assert_eq!(e.pose(1, &Pose::IDENTITY), ObbcdStatus::Ok);
    assert_eq!(e.set(1, &[plate(0.9)]), ObbcdStatus::Ok);
    assert_eq!(e.detect(), before);
}
