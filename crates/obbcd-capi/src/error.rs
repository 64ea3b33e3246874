//! The last error's message, per thread, and the guard that keeps panics on the Rust side.

use crate::types::ObbcdStatus;
use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

thread_local! {
    static LAST: RefCell<CString> = RefCell::new(CString::default());
}

/// Records `message` as this thread's last error and returns `status`.
pub fn fail(status: ObbcdStatus, message: &str) -> ObbcdStatus {
    // A NUL inside would cut the C string short.
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST.with(|l| *l.borrow_mut() = text);
    status
}

/// This thread's last error, valid until the next `fail` on this thread.
pub fn last() -> *const c_char {
    LAST.with(|l| l.borrow().as_ptr())
}

/// Runs `f`: its status, or `Internal` with the panic's message if it panicked.
pub fn guard(f: impl FnOnce() -> Result<(), ObbcdStatus>) -> ObbcdStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => ObbcdStatus::Ok,
        Ok(Err(status)) => status,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| panic.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("a panic");
            fail(
                ObbcdStatus::Internal,
                &format!("internal error in obbcd (please report it): {what}"),
            )
        }
    }
}
