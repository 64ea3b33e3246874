//! `on_this_thread` makes no rayon call: whole frames of the surgical scene, large enough that
//! the engines share them on a pool, run to the end on a plain thread while every worker of
//! the global pool is held, and give the pairs they give on the pool. (A process of its own:
//! holding the global pool would stall other tests.)

use obb_model::engines::{on_this_thread, Grid};
use obb_model::generate::surgical;
use obb_model::{Counters, Engine, GroupMask, Pair, Prepared};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// Every worker of the global pool, each held in a job until this is dropped.
struct Held {
    released: Arc<(Mutex<bool>, Condvar)>,
}

impl Held {
    fn hold_all() -> Held {
        let workers = rayon::current_num_threads();
        let released = Arc::new((Mutex::new(false), Condvar::new()));
        let started = Arc::new(AtomicUsize::new(0));
        for _ in 0..workers {
            let (released, started) = (released.clone(), started.clone());
            rayon::spawn(move || {
                started.fetch_add(1, Ordering::SeqCst);
                let (lock, wake) = &*released;
                let mut done = lock.lock().unwrap();
                while !*done {
                    done = wake.wait(done).unwrap();
                }
            });
        }
        // Each worker takes one job and stays in it, so all of them start.
        while started.load(Ordering::SeqCst) < workers {
            std::thread::sleep(Duration::from_millis(1));
        }
        Held { released }
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        let (lock, wake) = &*self.released;
        *lock.lock().unwrap() = true;
        wake.notify_all();
    }
}

fn frame(obbs: &[obb_model::Obb], mask: &GroupMask) -> (Vec<Pair>, Counters) {
    let mut prepared = Prepared::default();
    let mut out = Vec::new();
    let counters = Grid::default().detect(&prepared.update(obbs), mask, &mut out);
    (out, counters)
}

#[test]
fn frames_on_this_thread_need_no_pool() {
    let scene = surgical(17500, 1).unwrap();
    for mask in [GroupMask::All, GroupMask::Cross] {
        let pooled = frame(&scene.obbs, &mask);
        assert!(!pooled.0.is_empty(), "the scene has pairs ({mask})");
        let held = Held::hold_all();
        let (send, receive) = mpsc::channel();
        let (obbs, m) = (scene.obbs.clone(), mask.clone());
        let runner = std::thread::spawn(move || {
            let _ = send.send(on_this_thread(|| frame(&obbs, &m)));
        });
        let alone = receive.recv_timeout(Duration::from_secs(60));
        drop(held);
        runner.join().unwrap();
        let alone = alone.unwrap_or_else(|_| panic!("the frame waited for the held pool ({mask})"));
        assert_eq!(alone, pooled, "{mask}");
    }
}
