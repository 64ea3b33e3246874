//! obbcd's C ABI: the CPU collision engine for a C or C++ control loop.
//!
//! An engine keeps boxes by group. Groups named static at creation (the tissue) are resident:
//! their grid is rebuilt only when one of them is set; the other groups (the instruments) are
//! tested against it and each other at every detection. A moving group's boxes may be given
//! once in the group's own frame and placed by a pose each frame (`obbcd_set_pose`, a rigid
//! instrument): only the boxes near something are placed and tested. The pairs are those of
//! every obbcd engine: all colliding pairs the group mask allows, never a miss (docs/sat.md).
//! After the first frames, a detection with unchanged box counts allocates nothing in the
//! engine.
//!
//! Every function returns an [`ObbcdStatus`]; on a failure `obbcd_last_error` gives the reason.
//! No panic crosses the boundary: one is caught, reported as `OBBCD_STATUS_INTERNAL`, and the
//! engine is marked unusable. An engine may move between threads but must not be used by two
//! at once. `include/obbcd.h` is generated from this file and types.rs by cbindgen
//! (tests/header.rs checks it).

mod engine;
mod error;
mod types;
mod workers;

pub use types::{ObbcdBox, ObbcdContact, ObbcdPair, ObbcdPose, ObbcdStatus};

use engine::{Engine, Refusal};
use error::{fail, guard};
use obb_model::pose::Pose;
use obb_model::scene::MAX_OBBS;
use std::ffi::{c_char, CStr};

/// An engine (opaque to C).
pub struct ObbcdEngine {
    engine: Engine,
    /// A panic left the engine in an unknown state: every later call is refused.
    broken: bool,
}

/// The engine behind `engine`, or the status that refuses the call.
///
/// # Safety
/// `engine` is NULL or a pointer from `obbcd_engine_new` not yet freed.
unsafe fn engine_mut<'a>(engine: *mut ObbcdEngine) -> Result<&'a mut ObbcdEngine, ObbcdStatus> {
    // SAFETY: the caller's contract.
    match unsafe { engine.as_mut() } {
        None => Err(fail(ObbcdStatus::NullArgument, "engine is NULL")),
        Some(e) if e.broken => Err(fail(
            ObbcdStatus::Internal,
            "the engine failed in an earlier call and can only be freed",
        )),
        Some(e) => Ok(e),
    }
}

/// Runs `f` on the engine; a panic inside marks it broken.
///
/// # Safety
/// As [`engine_mut`].
unsafe fn with_engine(
    engine: *mut ObbcdEngine,
    f: impl FnOnce(&mut Engine) -> Result<(), ObbcdStatus>,
) -> ObbcdStatus {
    // SAFETY: the caller's contract.
    let e = match unsafe { engine_mut(engine) } {
        Ok(e) => e,
        Err(status) => return status,
    };
    let status = guard(|| f(&mut e.engine));
    e.broken = status == ObbcdStatus::Internal;
    status
}

fn refused(r: Refusal) -> ObbcdStatus {
    match r {
        Refusal::Argument(m) => fail(ObbcdStatus::InvalidArgument, &m),
        Refusal::Box(m) => fail(ObbcdStatus::InvalidBox, &m),
    }
}

/// Creates an engine in `*out`.
///
/// `group_mask`: which group pairs are reported, as on obbcd's command line: `"all"`,
/// `"cross"` (boxes of different groups only) or a list such as `"0-1,0-2"` (`"1-1"`: pairs
/// inside group 1). `static_groups`, `static_count`: the groups kept resident (may be NULL when
/// the count is 0). `threads`: worker threads of the engine's own pool, 0 for one per core, at
/// most 256. The pool rebuilds a static group after it changed (with 1 thread there is no
/// pool); every other detection runs on the calling thread: a frame of a few hundred moving
/// boxes takes a small part of a millisecond there, where handing it to a pool costs a wake-up
/// of another CPU each way. The pool's threads have all started when this returns, and no other
/// thread is started (rayon's global pool neither).
///
/// # Safety
/// `group_mask` is a NUL-terminated string; `static_groups` points to `static_count` values;
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn obbcd_engine_new(
    group_mask: *const c_char,
    static_groups: *const u32,
    static_count: usize,
    threads: u32,
    out: *mut *mut ObbcdEngine,
) -> ObbcdStatus {
    if out.is_null() {
        return fail(ObbcdStatus::NullArgument, "out is NULL");
    }
    // SAFETY: checked not NULL; the caller's contract.
    unsafe { *out = std::ptr::null_mut() };
    if group_mask.is_null() {
        return fail(ObbcdStatus::NullArgument, "group_mask is NULL");
    }
    if static_groups.is_null() && static_count > 0 {
        return fail(
            ObbcdStatus::NullArgument,
            "static_groups is NULL but static_count is not 0",
        );
    }
    guard(|| {
        // SAFETY: the caller's contract.
        let mask = unsafe { CStr::from_ptr(group_mask) }
            .to_str()
            .map_err(|_| {
                fail(
                    ObbcdStatus::InvalidArgument,
                    "group_mask is not a UTF-8 string",
                )
            })?;
        let mask = mask
            .parse()
            .map_err(|m: String| fail(ObbcdStatus::InvalidArgument, &m))?;
        let statics = match static_count {
            0 => &[][..],
            // SAFETY: not NULL (checked); the caller's contract.
            n => unsafe { std::slice::from_raw_parts(static_groups, n) },
        };
        let engine = Engine::new(mask, statics, threads as usize).map_err(refused)?;
        let engine = Box::new(ObbcdEngine {
            engine,
            broken: false,
        });
        // SAFETY: checked not NULL above.
        unsafe { *out = Box::into_raw(engine) };
        Ok(())
    })
}

/// Frees an engine (NULL is ignored). Pointers to its pairs and contacts become invalid. Returns
/// once the engine's own threads (`threads` of `obbcd_engine_new`) have ended: none runs the
/// library's code after it.
///
/// # Safety
/// `engine` is NULL or a pointer from `obbcd_engine_new` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn obbcd_engine_free(engine: *mut ObbcdEngine) {
    if !engine.is_null() {
        // SAFETY: the caller's contract: it came from Box::into_raw and is freed once.
        let engine = unsafe { Box::from_raw(engine) };
        // A panic in a destructor would otherwise unwind into C.
        let _ = guard(|| {
            drop(engine);
            Ok(())
        });
    }
}

/// Sets the boxes of `group` (replacing the ones it had; `count` 0 empties it, and `boxes`
/// may then be NULL; at most 2^28 boxes in all), in the group's frame: a moving group's pose
/// (`obbcd_set_pose`, the identity until set) places them. Every box is checked first, and
/// where its group's pose places it: on `OBBCD_STATUS_INVALID_BOX` nothing changed. The last
/// detection's pairs and contacts are dropped. With the group's count unchanged, the boxes
/// are copied in place and nothing is allocated.
///
/// # Safety
/// `engine` as in `obbcd_engine_free`; `boxes` points to `count` boxes.
#[no_mangle]
pub unsafe extern "C" fn obbcd_set_boxes(
    engine: *mut ObbcdEngine,
    group: u32,
    boxes: *const ObbcdBox,
    count: usize,
) -> ObbcdStatus {
    if boxes.is_null() && count > 0 {
        return fail(
            ObbcdStatus::NullArgument,
            "boxes is NULL but count is not 0",
        );
    }
    // Before the slice is made: a count this large cannot be the caller's array.
    if count > MAX_OBBS {
        return fail(
            ObbcdStatus::InvalidArgument,
            &format!("count is {count}, more than the limit of {MAX_OBBS} boxes"),
        );
    }
    let boxes = match count {
        0 => &[][..],
        // SAFETY: not NULL (checked); the caller's contract.
        n => unsafe { std::slice::from_raw_parts(boxes, n) },
    };
    // SAFETY: the caller's contract.
    unsafe { with_engine(engine, |e| e.set_boxes(group, boxes).map_err(refused)) }
}

/// Places the boxes of the moving group `group` by `*pose` from the next detection on: box
/// centers `c` at `rotation c + translation`, axes `a` as `rotation a`. A group's pose is the
/// identity until set, and is kept when its boxes are set again (they are in the group's
/// frame). Refused with `OBBCD_STATUS_INVALID_ARGUMENT`, changing nothing, for a static group,
/// a group whose boxes were never set, an entry that is not finite, a rotation not
/// orthonormal within 1e-5 (an entry of R·Rᵀ - I), a translation beyond ±1e6, or a pose
/// placing a box's center beyond ±1e6. The last detection's pairs and contacts are dropped.
/// Costs no allocation.
///
/// # Safety
/// `engine` as in `obbcd_engine_free`; `pose` points to a pose.
#[no_mangle]
pub unsafe extern "C" fn obbcd_set_pose(
    engine: *mut ObbcdEngine,
    group: u32,
    pose: *const ObbcdPose,
) -> ObbcdStatus {
    // SAFETY: the caller's contract.
    let Some(&ObbcdPose {
        rotation,
        translation,
    }) = (unsafe { pose.as_ref() })
    else {
        return fail(ObbcdStatus::NullArgument, "pose is NULL");
    };
    let pose = Pose {
        rotation,
        translation,
    };
    // SAFETY: the caller's contract.
    unsafe { with_engine(engine, |e| e.set_pose(group, pose).map_err(refused)) }
}

/// Finds every colliding pair of the boxes set so far, each moving group placed by its pose;
/// `*pair_count` (if not NULL) receives their number. Read them with `obbcd_pairs`.
///
/// # Safety
/// `engine` as in `obbcd_engine_free`; `pair_count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn obbcd_detect(
    engine: *mut ObbcdEngine,
    pair_count: *mut usize,
) -> ObbcdStatus {
    // SAFETY: the caller's contract.
    unsafe {
        with_engine(engine, |e| {
            let n = e.detect().len();
            if let Some(c) = pair_count.as_mut() {
                *c = n;
            }
            Ok(())
        })
    }
}

/// Points `*items` and `*count` at the slice `list` gives of the engine.
///
/// # Safety
/// As [`engine_mut`]; `items` and `count` are NULL or writable.
unsafe fn list_out<T>(
    engine: *mut ObbcdEngine,
    items: *mut *const T,
    count: *mut usize,
    list: fn(&mut Engine) -> &[T],
) -> ObbcdStatus {
    if items.is_null() || count.is_null() {
        return fail(ObbcdStatus::NullArgument, "an output pointer is NULL");
    }
    // SAFETY: the caller's contract; the outputs are checked not NULL.
    unsafe {
        with_engine(engine, |e| {
            let l = list(e);
            (*items, *count) = (l.as_ptr(), l.len());
            Ok(())
        })
    }
}

/// The last detection's pairs, sorted: `*pairs` points to `*count` of them, valid until the
/// engine's next `obbcd_set_boxes`, `obbcd_set_pose`, `obbcd_detect` or `obbcd_engine_free`.
///
/// # Safety
/// `engine` as in `obbcd_engine_free`; `pairs` and `count` are writable.
#[no_mangle]
pub unsafe extern "C" fn obbcd_pairs(
    engine: *mut ObbcdEngine,
    pairs: *mut *const ObbcdPair,
    count: *mut usize,
) -> ObbcdStatus {
    // SAFETY: the caller's contract.
    unsafe { list_out(engine, pairs, count, Engine::pairs) }
}

/// The contact of each of the last detection's pairs, in the pairs' order (computed on the
/// first call after a detection): `*contacts` points to `*count` of them, valid as the pairs.
///
/// # Safety
/// `engine` as in `obbcd_engine_free`; `contacts` and `count` are writable.
#[no_mangle]
pub unsafe extern "C" fn obbcd_contacts(
    engine: *mut ObbcdEngine,
    contacts: *mut *const ObbcdContact,
    count: *mut usize,
) -> ObbcdStatus {
    // SAFETY: the caller's contract.
    unsafe { list_out(engine, contacts, count, Engine::contacts) }
}

/// Why the last failing call on this thread failed: a NUL-terminated UTF-8 string, valid until
/// the next failing call on this thread; empty if none failed.
#[no_mangle]
pub extern "C" fn obbcd_last_error() -> *const c_char {
    error::last()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CString;

    fn last_error() -> String {
        // SAFETY: a NUL-terminated string.
        unsafe { CStr::from_ptr(obbcd_last_error()) }
            .to_string_lossy()
            .into_owned()
    }

    /// A panic inside a call comes back as `Internal` with its message, and the engine refuses
    /// every later call but `obbcd_engine_free`.
    #[test]
    fn a_panic_stays_on_this_side_and_breaks_the_engine() {
        let mask = CString::new("cross").unwrap();
        let mut e = std::ptr::null_mut();
        // SAFETY: valid arguments; the engine is freed at the end.
        unsafe {
            assert_eq!(
                obbcd_engine_new(mask.as_ptr(), std::ptr::null(), 0, 1, &mut e),
                ObbcdStatus::Ok
            );
            let status = with_engine(e, |_| panic!("a test's panic"));
            assert_eq!(status, ObbcdStatus::Internal);
            assert!(last_error().contains("a test's panic"), "{}", last_error());
            assert_eq!(obbcd_detect(e, std::ptr::null_mut()), ObbcdStatus::Internal);
            assert!(
                last_error().contains("can only be freed"),
                "{}",
                last_error()
            );
            obbcd_engine_free(e);
        }
    }
}
