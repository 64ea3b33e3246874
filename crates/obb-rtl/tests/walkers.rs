//! The broad-phase walkers on their own, clock by clock, under back-pressure (`stall`): the
//! brute walker (`walker.rs`) and the sweep walker (`sweep.rs`) against visit orders written
//! here from the broad phases' definitions, and the clocks against the model's
//! `broad::walk_cycles`. The brute walker's Verilog (Verilator) equals its rust-hdl simulation
//! on every output, every clock. (The improved-sap walker drives the radix sort: it is checked
//! with it, in the core's tests.)

mod common;

use obb_model::fixed::broad::{walk_cycles, BroadWork};
use obb_model::fixed::BroadPhase;
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::uval;
use obb_rtl::sweep::{SweepWalker, RUN_ON};
use obb_rtl::walker::{WalkMode, Walker};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use rust_hdl::prelude::*;

const A: usize = 7;
const C: usize = 8;

/// When the receiver holds the walker back: never, one clock in three, or at random (each
/// clock with probability one half, seeded).
#[derive(Clone, Copy, Debug)]
enum Stall {
    Never,
    EveryThird,
    Random(u64),
}

impl Stall {
    fn pattern(self, clocks: usize) -> Vec<bool> {
        match self {
            Stall::Never => vec![false; clocks],
            Stall::EveryThird => (0..clocks).map(|t| t % 3 == 2).collect(),
            Stall::Random(seed) => {
                let mut rng = StdRng::seed_from_u64(seed);
                (0..clocks).map(|_| rng.random_bool(0.5)).collect()
            }
        }
    }
}

const STALLS: [Stall; 4] = [
    Stall::Never,
    Stall::EveryThird,
    Stall::Random(1),
    Stall::Random(2),
];

/// Brute force visits every pair (i, j), i < j, in order.
fn brute_order(n: usize) -> Vec<(u64, u64)> {
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i as u64, j as u64)))
        .collect()
}

/// A walk as the block made it: the visits in order, the clock of each (from the clock after
/// `start`), and the clock `finished` was first seen high.
#[derive(Debug, Default)]
struct Walk {
    visits: Vec<(u64, u64)>,
    at: Vec<usize>,
    finished: usize,
}

/// The ports every walker has, for one driver.
trait WalkerPorts: Block {
    fn drive(&mut self, start: bool, n: u64, stall: bool);
    fn set_clock(&mut self, high: bool);
    fn visit(&self) -> Option<(u64, u64)>;
    fn finished(&self) -> bool;
}

macro_rules! walker_ports {
    ($t:ty) => {
        impl WalkerPorts for $t {
            fn drive(&mut self, start: bool, n: u64, stall: bool) {
                self.start.next = start;
                self.n.next = n.into();
                self.stall.next = stall;
            }
            fn set_clock(&mut self, high: bool) {
                self.clock.next = high.into();
            }
            fn visit(&self) -> Option<(u64, u64)> {
                self.visit
                    .val()
                    .then(|| (uval(self.vi.val()), uval(self.vj.val())))
            }
            fn finished(&self) -> bool {
                self.finished.val()
            }
        }
    };
}
walker_ports!(Walker<A, C>);
walker_ports!(SweepWalker<A, C>);

/// Runs a walker on `n` boxes: `start` on clock 0, then `stall[t]` on clock t + 1. The
/// outputs are read before each rising edge, with the clock's inputs applied: what the edge
/// takes. `read` takes what the memories see at the edge, `answer` puts their data on the
/// inputs after it.
fn run_walk<W: WalkerPorts, T>(
    u: &mut W,
    n: usize,
    stall: &[bool],
    read: impl Fn(&W) -> T,
    answer: impl Fn(&mut W, T),
) -> Walk {
    u.connect_all();
    let mut walk = Walk::default();
    for t in 0..=stall.len() {
        u.drive(t == 0, n as u64, t > 0 && stall[t - 1]);
        u.set_clock(false);
        assert!(simulate(u, 1000), "settles");
        if t > 0 {
            if let Some(v) = u.visit() {
                walk.visits.push(v);
                walk.at.push(t);
            }
            if u.finished() {
                walk.finished = t;
                return walk;
            }
        }
        let seen = read(u);
        u.set_clock(true);
        assert!(simulate(u, 1000), "settles");
        answer(u, seen);
    }
    panic!("n = {n}: not finished after {} clocks", stall.len());
}

/// The brute walker on `n` boxes (it reads no memory).
fn brute_walk(n: usize, stall: &[bool]) -> Walk {
    let mut u = Walker::<A, C>::new(WalkMode::Brute);
    run_walk(&mut u, n, stall, |_| (), |_, ()| {})
}

#[test]
fn brute_walker_visits_every_pair_once_in_order_under_stalls() {
    for n in [0usize, 1, 2, 3, 17, 40] {
        let want = brute_order(n);
        for s in STALLS {
            let stall = s.pattern(4 * want.len() + 10);
            let walk = brute_walk(n, &stall);
            assert_eq!(walk.visits, want, "n = {n}, {s:?}");
            // No visit on a stalled clock, and one on every other clock of the walk.
            for &t in &walk.at {
                assert!(
                    !stall[t - 1],
                    "n = {n}, {s:?}: a visit on stalled clock {t}"
                );
            }
            let work = BroadWork {
                visited: want.len() as u64,
                ..BroadWork::default()
            };
            let free = walk_cycles(BroadPhase::Brute, n as u64, &work) as usize;
            let stalled = walk
                .at
                .last()
                .map_or(0, |&t| stall[..t].iter().filter(|&&s| s).count());
            assert_eq!(
                walk.at.last().copied().unwrap_or(0),
                free + stalled,
                "n = {n}, {s:?}: the last visit's clock"
            );
            assert!(
                walk.finished <= walk.at.last().copied().unwrap_or(0) + 2,
                "n = {n}, {s:?}: finished on clock {} after the last visit",
                walk.finished
            );
        }
    }
}

/// The brute walker's Verilog in Verilator equals its rust-hdl simulation on every output at
/// every clock, on a walk with random stalls and a second `start` in the middle of it.
#[test]
fn brute_walker_verilog_equals_its_rust_hdl_simulation() {
    let n = 12u64;
    let stall = Stall::Random(3).pattern(200);
    // start, n, stall, then the improved-sap inputs at zero; a restart at clock 40.
    let vectors: Vec<Vec<u64>> = (0..200)
        .map(|t| {
            let mut v = vec![u64::from(t == 0 || t == 40), n, u64::from(stall[t])];
            v.resize(3 + 8, 0);
            v
        })
        .collect();
    let mut inputs = vec![
        Port::new("start", 1),
        Port::new("n", C),
        Port::new("stall", 1),
        Port::new("rd_val", obb_rtl::radix::VAL),
        Port::new("sort_done", 1),
    ];
    for end in ["min", "max"] {
        for x in ["x", "y", "z"] {
            inputs.push(Port::new(
                format!("a_{end}_{x}"),
                obb_rtl::projection::CENTER,
            ));
        }
    }
    let outputs = [
        Port::new("visit", 1),
        Port::new("vi", A),
        Port::new("vj", A),
        Port::new("a_addr", A),
        Port::new("b_addr", A),
        Port::new("finished", 1),
    ];
    let mut u = Walker::<A, C>::new(WalkMode::Brute);
    let verilog = obb_rtl::flow::emit::verilog(&mut u, "walker").unwrap();
    let got = common::run_verilator(&verilog, "walker", &inputs, &outputs, &vectors);
    let mut u = Walker::<A, C>::new(WalkMode::Brute);
    let want = common::run_rust_hdl(
        &mut u,
        &vectors,
        |u, v| {
            u.start.next = v[0] == 1;
            u.n.next = v[1].into();
            u.stall.next = v[2] == 1;
        },
        |u, c| u.clock.next = c.into(),
        |u| {
            vec![
                u64::from(u.visit.val()),
                uval(u.vi.val()),
                uval(u.vj.val()),
                uval(u.a_addr.val()),
                uval(u.b_addr.val()),
                u64::from(u.finished.val()),
            ]
        },
    );
    assert_eq!(got, want, "Verilator against rust-hdl, clock by clock");
    assert!(want.iter().any(|o| o[5] == 1), "the walk finishes");
}

/// The sweep's visits: the boxes sorted stably by min x key; each walks its successors while
/// their min key is within its own max key.
fn sweep_order(keys: &[(u64, u64)]) -> Vec<(u64, u64)> {
    let mut order: Vec<usize> = (0..keys.len()).collect();
    order.sort_by_key(|&b| keys[b].0);
    let mut visits = Vec::new();
    for (p, &i) in order.iter().enumerate() {
        for &j in &order[p + 1..] {
            if keys[j].0 > keys[i].1 {
                break;
            }
            visits.push((i as u64, j as u64));
        }
    }
    visits
}

/// Runs the sweep walker on boxes with x keys `keys` (min, max): the sorted entries and the
/// key table are memories of read latency 1 modelled here (the address taken at an edge, its
/// data on the inputs after it). `start` on clock 0, `stall[t]` on clock t + 1.
fn sweep_walk(keys: &[(u64, u64)], stall: &[bool]) -> Walk {
    let mut sorted: Vec<usize> = (0..keys.len()).collect();
    sorted.sort_by_key(|&b| keys[b].0);
    let mut u = SweepWalker::<A, C>::default();
    run_walk(
        &mut u,
        keys.len(),
        stall,
        |u| {
            (
                uval(u.rd_addr.val()) as usize,
                uval(u.a_addr.val()) as usize,
            )
        },
        |u, (rd, a)| {
            // Past the last entry the memory holds whatever: the walker must ignore it.
            let entry = sorted.get(rd).copied();
            u.rd_key.next = entry.map_or(0, |b| keys[b].0).into();
            u.rd_val.next = (entry.unwrap_or(0) as u64).into();
            u.a_max.next = keys.get(a).map_or(0, |k| k.1).into();
        },
    )
}

/// Random x keys of `n` boxes: many ties, boxes inside boxes, some far apart.
fn sweep_keys(n: usize, seed: u64) -> Vec<(u64, u64)> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let min = rng.random_range(0..(4 * n as u64 + 1));
            (min, min + rng.random_range(0..12))
        })
        .collect()
}

#[test]
fn sweep_walker_visits_in_the_sweep_order_under_stalls() {
    let mut scenes: Vec<(String, Vec<(u64, u64)>)> = vec![
        ("none".into(), vec![]),
        ("one".into(), vec![(3, 5)]),
        ("two apart".into(), vec![(0, 1), (2, 3)]),
        ("all equal".into(), vec![(7, 7); 9]),
        (
            "one long".into(),
            vec![(0, 100), (5, 6), (50, 60), (101, 102)],
        ),
    ];
    scenes.extend((0..4).map(|s| (format!("random {s}"), sweep_keys(30 + 10 * s, s as u64))));
    for (name, keys) in &scenes {
        let want = sweep_order(keys);
        let n = keys.len() as u64;
        for s in STALLS {
            let stall = s.pattern(8 * (want.len() + keys.len()) + 40);
            let walk = sweep_walk(keys, &stall);
            assert_eq!(walk.visits, want, "{name}, {s:?}");
            // Without stalls: the model's clocks (`finished` rises the clock after the last
            // restart), and a stall lets through at most RUN_ON visits.
            if let Stall::Never = s {
                let work = BroadWork {
                    visited: want.len() as u64,
                    ..BroadWork::default()
                };
                let free = walk_cycles(BroadPhase::Sweep, n, &work) as usize;
                let expected = if n < 2 { 1 } else { free + 1 };
                assert_eq!(walk.finished, expected, "{name}: finished");
            }
            // While `stall` stays high, at most RUN_ON visits still come out.
            let mut run = 0;
            for t in 1..=walk.finished {
                if stall[t - 1] {
                    run += usize::from(walk.at.contains(&t));
                    assert!(
                        run as u64 <= RUN_ON,
                        "{name}, {s:?}: {run} visits into the stall that holds on clock {t}"
                    );
                } else {
                    run = 0;
                }
            }
        }
    }
}
