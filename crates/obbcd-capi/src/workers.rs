//! An engine's own thread pool, whose threads have all started when it is made and have ended
//! when it is dropped.
//!
//! A rayon pool dropped only tells its threads to end, and they end later, on their own. A C
//! caller may unload the library (`dlclose`) or check for leaks right after
//! `obbcd_engine_free`: no thread of the engine may still run its code then. (The allocation
//! test also saw a freed engine's worker allocate as it ended, in the middle of the next
//! engine's frames.)

use std::thread::JoinHandle;

#[derive(Debug)]
pub struct Workers {
    /// Dropped first (fields drop in their order): that tells the threads to end.
    pool: rayon::ThreadPool,
    /// Then joined.
    _threads: Joined,
}

/// Threads joined when dropped.
#[derive(Debug)]
struct Joined(Vec<JoinHandle<()>>);

impl Workers {
    /// A pool of `threads` workers (0: one per core), named `obbcd-K`.
    pub fn new(threads: usize) -> Result<Workers, rayon::ThreadPoolBuildError> {
        let mut handles = Vec::new();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|k| format!("obbcd-{k}"))
            .spawn_handler(|thread| {
                let mut b = std::thread::Builder::new();
                if let Some(name) = thread.name() {
                    b = b.name(name.to_owned());
                }
                if let Some(size) = thread.stack_size() {
                    b = b.stack_size(size);
                }
                handles.push(b.spawn(|| thread.run())?);
                Ok(())
            })
            .build()?;
        // Every thread has started once it ran a job: what a thread allocates as it starts
        // is done here, not whenever the system first schedules it (under load, in the middle
        // of the caller's frames).
        pool.broadcast(|_| ());
        Ok(Workers {
            pool,
            _threads: Joined(handles),
        })
    }

    pub fn pool(&self) -> &rayon::ThreadPool {
        &self.pool
    }
}

impl Drop for Joined {
    /// Waits for the threads to end. (Never run on one of them: an engine is freed by its
    /// caller, outside its pool.)
    fn drop(&mut self) {
        for t in self.0.drain(..) {
            // A worker that panicked has ended too.
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Once dropped, none of the pool's threads is left: each one's thread-local value has
    /// been destroyed, as a thread's are when it ends.
    #[test]
    fn dropped_workers_have_ended() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static ENDED: AtomicUsize = AtomicUsize::new(0);
        struct Ends;
        impl Drop for Ends {
            fn drop(&mut self) {
                ENDED.fetch_add(1, Ordering::SeqCst);
            }
        }
        thread_local!(static ENDS: Ends = const { Ends });
        for round in 1..=20 {
            let workers = Workers::new(3).unwrap();
            assert_eq!(workers.pool().current_num_threads(), 3);
            workers.pool().broadcast(|_| ENDS.with(|_| ()));
            drop(workers);
            assert_eq!(ENDED.load(Ordering::SeqCst), 3 * round);
        }
    }
}
