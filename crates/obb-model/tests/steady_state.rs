//! Once warmed up on frames of a given size, the grid engine and the per-frame preparation
//! allocate nothing: every buffer is kept between frames. A counting allocator sees every
//! allocation of the process, the thread pool's included.
//!
//! The frames run inside the thread pool, as a real-time loop would. A call entering the pool
//! from outside (`detect --repeat` does) also costs rayon one queue block per 63 entries.

use obb_model::engines::Grid;
use obb_model::generate::surgical;
use obb_model::{Engine, GroupMask, Prepared};
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;

#[global_allocator]
static COUNTING: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

#[test]
fn grid_allocates_nothing_in_steady_state() {
    // Above the size at which the preparation runs on the thread pool; two different frames
    // (seeds move the instruments and the tissue), each mask in turn.
    let frames = [surgical(6000, 1).unwrap(), surgical(6000, 2).unwrap()];
    assert_ne!(frames[0], frames[1]);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    // Every worker has started (and allocated what a thread allocates as it starts) once it
    // ran a job; else one the system schedules late would allocate among the counted frames.
    pool.broadcast(|_| ());
    for mask in [GroupMask::All, GroupMask::Cross] {
        let mut prepared = Prepared::default();
        let mut grid = Grid::default();
        let mut out = Vec::new();
        let mut run = |counts: &mut Vec<usize>| {
            for scene in &frames {
                let frame = prepared.update(&scene.obbs);
                grid.detect(&frame, &mask, &mut out);
                counts.push(out.len());
            }
        };
        let (warm, allocated) = pool.install(|| {
            let mut warm = Vec::new();
            for _ in 0..3 {
                run(&mut warm);
            }
            let mut steady = Vec::with_capacity(256);
            let region = Region::new(COUNTING);
            for _ in 0..100 {
                run(&mut steady);
            }
            let change = region.change();
            (warm, change.allocations + change.reallocations)
        });
        assert!(warm[0] > 0, "the frames have colliding pairs ({mask})");
        assert_eq!(
            allocated, 0,
            "allocations in 200 steady-state frames with mask {mask}"
        );
    }
}
