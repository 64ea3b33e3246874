//! How many threads a frame may use: the current rayon pool's, or one on a thread that runs its
//! frames itself ([`on_this_thread`]).

use std::cell::Cell;

thread_local! {
    /// Inside [`on_this_thread`] on this thread.
    static HERE: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` with every frame it detects on this thread alone: the engines see one thread and
/// make no rayon call, so no pool is entered or woken. For a caller outside any pool whose
/// frames are too small to share: handing a frame to a pool and back costs a wake-up of
/// another CPU each way, 0.1 ms or more on this project's virtual machines, where a haptic
/// frame takes 0.02 ms. Nests, and restores the setting on return and on unwinding.
pub fn on_this_thread<R>(f: impl FnOnce() -> R) -> R {
    struct Restore(bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            HERE.set(self.0);
        }
    }
    let _restore = Restore(HERE.replace(true));
    f()
}

/// The threads a frame may use: 1 inside [`on_this_thread`], else the current pool's (the
/// global pool's outside any). Every parallel step of the engines asks this, and with 1 runs
/// on the calling thread without a rayon call.
pub(crate) fn threads() -> usize {
    if HERE.get() {
        1
    } else {
        rayon::current_num_threads()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_thread_inside_and_the_pools_again_after_a_return_or_a_panic() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        pool.install(|| {
            assert_eq!(threads(), 3);
            assert_eq!(on_this_thread(|| on_this_thread(threads) + threads()), 2);
            assert_eq!(threads(), 3);
            let unwound = std::panic::catch_unwind(|| on_this_thread(|| panic!("in the frame")));
            assert!(unwound.is_err());
            assert_eq!(threads(), 3);
        });
    }
}
