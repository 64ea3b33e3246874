//! After warm-up, a haptic frame through the C ABI (set the instruments' boxes, or their poses,
//! detect, read the pairs and contacts) allocates nothing in obbcd: every allocation of the
//! process is counted. A haptic frame runs on the calling thread; were it handed to the pool,
//! rayon's queue would allocate a block every 63 frames (`crossbeam_deque::Injector::push`
//! under `Registry::inject`, seen with gdb). Nor does the ABI start rayon's global pool, whose
//! threads allocate as they start, when the system gets round to them (under load, in the
//! middle of the counted frames); an engine's own pool has ended when it is freed.

use obb_model::generate::SurgicalMotion;
use obbcd_c::*;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;
use std::ffi::CString;
use std::ptr::{null, null_mut};

/// Counts the allocations and reallocations of every thread.
#[global_allocator]
static COUNTING: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// The motion's frame where the run starts: the grippers slide in the tissue.
const START: usize = 800;

/// One haptic frame's boxes by group, and the instruments' poses by group (their boxes in
/// their own frames being the bodies').
struct Frame {
    boxes: Vec<(u32, Vec<ObbcdBox>)>,
    poses: Vec<(u32, ObbcdPose)>,
}

/// The tissue, the instruments' boxes in their own frames by group, and `count` haptic frames.
#[allow(clippy::type_complexity)]
fn haptic_frames(n: usize, count: usize) -> (Vec<ObbcdBox>, Vec<(u32, Vec<ObbcdBox>)>, Vec<Frame>) {
    let motion = SurgicalMotion::new(n, 4).unwrap();
    let to_c = |b: &obb_model::Obb| ObbcdBox {
        center: b.center,
        axes: b.axes,
        half: b.half,
    };
    // A tissue update in the middle of the slide along the tissue, and the haptic frames after.
    let first = motion.frame(START);
    assert!(first.replace.contains(&0));
    let tissue = first
        .obbs
        .iter()
        .filter(|b| b.group == 0)
        .map(to_c)
        .collect();
    let frames = (START + 1..=START + count)
        .map(|k| {
            let f = motion.frame(k);
            assert!(!f.replace.contains(&0), "frame {k} is a tissue update");
            let boxes = f
                .replace
                .iter()
                .map(|&g| {
                    (
                        g,
                        f.obbs.iter().filter(|b| b.group == g).map(to_c).collect(),
                    )
                })
                .collect();
            let poses = motion
                .bodies()
                .iter()
                .zip(motion.poses(k))
                .map(|(body, p)| {
                    let pose = ObbcdPose {
                        rotation: p.rotation,
                        translation: p.translation,
                    };
                    (body[0].group, pose)
                })
                .collect();
            Frame { boxes, poses }
        })
        .collect();
    let bodies = motion
        .bodies()
        .iter()
        .map(|b| (b[0].group, b.iter().map(to_c).collect()))
        .collect();
    (tissue, bodies, frames)
}

#[test]
fn a_haptic_frame_allocates_nothing_after_warm_up() {
    let (tissue, bodies, frames) = haptic_frames(7000, 39);
    let mask = CString::new("cross").unwrap();
    for (threads, posed) in [(1, false), (2, false), (1, true), (2, true)] {
        let mut e = null_mut();
        let (mut pairs, mut contacts, mut n) = (null(), null(), 0);
        let mut found = 0;
        // SAFETY: valid pointers throughout; the engine is freed at the end.
        unsafe {
            let st = obbcd_engine_new(mask.as_ptr(), [0].as_ptr(), 1, threads, &mut e);
            assert_eq!(st, ObbcdStatus::Ok);
            assert_eq!(
                obbcd_set_boxes(e, 0, tissue.as_ptr(), tissue.len()),
                ObbcdStatus::Ok
            );
            if posed {
                for (g, boxes) in &bodies {
                    let st = obbcd_set_boxes(e, *g, boxes.as_ptr(), boxes.len());
                    assert_eq!(st, ObbcdStatus::Ok);
                }
            }
            for pass in 0..3 {
                let region = Region::new(COUNTING);
                for f in &frames {
                    if posed {
                        for (g, pose) in &f.poses {
                            assert_eq!(obbcd_set_pose(e, *g, pose), ObbcdStatus::Ok);
                        }
                    } else {
                        for (g, boxes) in &f.boxes {
                            let st = obbcd_set_boxes(e, *g, boxes.as_ptr(), boxes.len());
                            assert_eq!(st, ObbcdStatus::Ok);
                        }
                    }
                    assert_eq!(obbcd_detect(e, null_mut()), ObbcdStatus::Ok);
                    assert_eq!(obbcd_pairs(e, &mut pairs, &mut n), ObbcdStatus::Ok);
                    assert_eq!(obbcd_contacts(e, &mut contacts, &mut n), ObbcdStatus::Ok);
                    found += n;
                }
                let change = region.change();
                let allocated = change.allocations + change.reallocations;
                // The first pass is the warm-up: buffers grow to the run's largest frame.
                if pass > 0 {
                    assert_eq!(
                        allocated,
                        0,
                        "{threads} threads, posed {posed}, pass {pass}: allocations in {} frames",
                        frames.len()
                    );
                }
            }
            obbcd_engine_free(e);
        }
        assert!(
            found > 0,
            "the grippers never touched the tissue (posed {posed})"
        );
    }
    // The engines ran on the calling thread and on pools of their own: rayon's global pool,
    // whose threads would start (and allocate) whenever the system schedules them, was never
    // started. (Building it fails once it has been.)
    assert!(
        rayon::ThreadPoolBuilder::new().build_global().is_ok(),
        "the C ABI started rayon's global pool"
    );
}
