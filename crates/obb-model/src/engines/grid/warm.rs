//! Keeps a second worker of the thread pool looking for work through a whole frame, where it
//! would otherwise fall asleep in each serial stretch (the corner layout's counting sort, the
//! hand-over between phases) and be woken at the next parallel one.
//!
//! On this 2-core machine kind a sleeping worker is a halted virtual CPU: waking it costs the
//! waker a trip through the kernel (5 % of a 2-thread frame's samples, in
//! `_raw_spin_unlock_irqrestore`) and the frame the time the other CPU takes to come back,
//! several times a frame. Kept looking, the worker takes each phase's jobs as soon as they are
//! pushed; it is woken once, when the frame starts.

use std::sync::atomic::{AtomicBool, Ordering};

/// Pause instructions between two looks for work that found none: short, so that a job
/// pushed is taken within a fraction of a microsecond.
const PAUSES: usize = 8;

/// Runs `frame` on the calling thread while another worker of the current pool (when it is
/// free) takes the jobs the frame pushes, and looks for more in between instead of sleeping,
/// until `frame` returns or panics. Allocates nothing: `rayon::join` keeps both halves on the
/// stack. Call it only for frames that have parallel phases on two threads or more: it wakes
/// a worker.
///
/// If no other worker takes the second half before `frame` returns, the calling thread runs
/// it then and it returns at once. A worker keeping warm may also run jobs that are not the
/// frame's (of another frame run on the same pool, say); the frame then waits for them, as it
/// would for any job of a `join`.
pub(super) fn while_warm<R: Send>(frame: impl FnOnce() -> R + Send) -> R {
    /// Ends the keeping warm when the frame returns or unwinds: `join` waits for both halves,
    /// so a panicking frame must not leave the other one looking for work.
    struct Done<'a>(&'a AtomicBool);
    impl Drop for Done<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    let done = AtomicBool::new(false);
    let (result, ()) = rayon::join(
        || {
            let _done = Done(&done);
            frame()
        },
        || {
            while !done.load(Ordering::Acquire) {
                if rayon::yield_now() != Some(rayon::Yield::Executed) {
                    for _ in 0..PAUSES {
                        std::hint::spin_loop();
                    }
                }
            }
        },
    );
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    /// The frame's result comes back and the worker is free again, on one thread and on two,
    /// frame after frame, with parallel phases inside.
    #[test]
    fn a_frame_returns_and_frees_the_worker() {
        for threads in [1, 2, 3] {
            let pool = pool(threads);
            for frame in 0..200usize {
                let sum = pool.install(|| {
                    while_warm(|| {
                        let halves = rayon::join(|| frame, || 2 * frame);
                        halves.0 + halves.1
                    })
                });
                assert_eq!(sum, 3 * frame, "{threads} threads");
            }
            // Both workers take jobs again: each half waits until the other has started.
            let started = AtomicUsize::new(0);
            let meet = || {
                started.fetch_add(1, Ordering::SeqCst);
                while started.load(Ordering::SeqCst) < 2 {
                    std::hint::spin_loop();
                }
            };
            if threads > 1 {
                pool.install(|| rayon::join(meet, meet));
            }
        }
    }

    /// A frame that panics ends the keeping warm: the panic reaches the caller, and the pool
    /// runs the next frame. (On a thread of its own, so that a hang fails the test.)
    #[test]
    fn a_panicking_frame_does_not_hang_the_pool() {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let pool = pool(2);
            let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                pool.install(|| while_warm(|| -> usize { panic!("the frame fails") }))
            }));
            let next = pool.install(|| while_warm(|| 7));
            tx.send((caught.is_err(), next)).unwrap();
        });
        let (panicked, next) = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("the pool hangs after a panicking frame");
        assert!(panicked, "the panic reaches the caller");
        assert_eq!(next, 7);
    }

    /// Called from outside any pool, it runs the frame on the global pool's terms and returns.
    #[test]
    fn outside_a_pool_it_runs_the_frame() {
        assert_eq!(while_warm(|| 5), 5);
    }
}
