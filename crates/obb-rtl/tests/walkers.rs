//! The broad-phase walkers on their own, clock by clock, under back-pressure (`stall`): the
//! brute and improved-sap walkers (`walker.rs`) and the sweep walker (`sweep.rs`) against visit
//! orders written here from the broad phases' definitions, and the clocks against the model's
//! `broad::walk_cycles`; the memories and the sort they drive are behavioural models here. Each
//! walker's Verilog (Verilator) equals its rust-hdl simulation on every output, every clock,
//! driven with the inputs of a closed-loop walk.

use crate::common;

use obb_model::fixed::broad::{walk_cycles, BroadWork};
use obb_model::fixed::BroadPhase;
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::uval;
use obb_rtl::sweep::{self, SweepWalker};
use obb_rtl::walker::{self, WalkMode, Walker};
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
    /// Stalls of 20 clocks, 9 clocks apart: long enough for every run-on to show.
    Bursts,
    Random(u64),
}

impl Stall {
    fn pattern(self, clocks: usize) -> Vec<bool> {
        match self {
            Stall::Never => vec![false; clocks],
            Stall::EveryThird => (0..clocks).map(|t| t % 3 == 2).collect(),
            Stall::Bursts => (0..clocks).map(|t| t % 29 >= 9).collect(),
            Stall::Random(seed) => {
                let mut rng = StdRng::seed_from_u64(seed);
                (0..clocks).map(|_| rng.random_bool(0.5)).collect()
            }
        }
    }
}

const STALLS: [Stall; 5] = [
    Stall::Never,
    Stall::EveryThird,
    Stall::Bursts,
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
    /// Every clock's inputs, as `Replay::inputs` reads them (to replay the closed loop open).
    inputs: Vec<Vec<u64>>,
}

/// The ports every walker has, for one driver.
trait WalkerPorts: Block {
    fn drive(&mut self, start: bool, n: u64, stall: bool);
    fn set_clock(&mut self, high: bool);
    fn visit(&self) -> Option<(u64, u64)>;
    fn finished(&self) -> bool;
    /// `start`, `n`, `stall`, as `common_inputs` lists them.
    fn control(&self) -> Vec<u64>;
    /// The visit and the addresses, as `common_outputs` lists them.
    fn visit_outputs(&self) -> Vec<u64>;
}

/// A walker's every input and output as vectors, to drive its rust-hdl model and its Verilog
/// with the same inputs and compare every output.
trait Replay: WalkerPorts {
    fn input_ports() -> Vec<Port>;
    fn output_ports() -> Vec<Port>;
    fn inputs(&self) -> Vec<u64>;
    fn apply(&mut self, v: &[u64]);
    fn outputs(&self) -> Vec<u64>;
}

/// The input and output ports the walkers share: the control and the visit.
fn common_inputs() -> Vec<Port> {
    vec![
        Port::new("start", 1),
        Port::new("n", C),
        Port::new("stall", 1),
    ]
}

fn common_outputs() -> Vec<Port> {
    vec![
        Port::new("visit", 1),
        Port::new("vi", A),
        Port::new("vj", A),
        Port::new("rd_addr", A),
        Port::new("a_addr", A),
        Port::new("b_addr", A),
        Port::new("finished", 1),
    ]
}

/// The walker's sides of the key table's port A (min and max keys per axis).
const KEY_PORTS: [&str; 6] = [
    "a_min_x", "a_min_y", "a_min_z", "a_max_x", "a_max_y", "a_max_z",
];
const SORT_OUTPUTS: [(&str, usize); 5] = [
    ("sort_start", 1),
    ("sort_valid", 1),
    ("sort_key", obb_rtl::radix::KEY),
    ("sort_val", obb_rtl::radix::VAL),
    ("sort_go", 1),
];

impl Replay for Walker<A, C> {
    fn input_ports() -> Vec<Port> {
        let mut p = common_inputs();
        p.push(Port::new("rd_val", obb_rtl::radix::VAL));
        p.push(Port::new("sort_done", 1));
        p.extend(KEY_PORTS.map(|k| Port::new(k, obb_rtl::projection::CENTER)));
        p
    }
    fn output_ports() -> Vec<Port> {
        let mut p = common_outputs();
        p.extend(SORT_OUTPUTS.map(|(name, bits)| Port::new(name, bits)));
        p
    }
    fn inputs(&self) -> Vec<u64> {
        let mut v = self.control();
        v.extend([
            uval(self.rd_val.val()),
            u64::from(self.sort_done.val()),
            uval(self.a_min_x.val()),
            uval(self.a_min_y.val()),
            uval(self.a_min_z.val()),
            uval(self.a_max_x.val()),
            uval(self.a_max_y.val()),
            uval(self.a_max_z.val()),
        ]);
        v
    }
    fn apply(&mut self, v: &[u64]) {
        self.drive(v[0] == 1, v[1], v[2] == 1);
        self.rd_val.next = v[3].into();
        self.sort_done.next = v[4] == 1;
        self.a_min_x.next = v[5].into();
        self.a_min_y.next = v[6].into();
        self.a_min_z.next = v[7].into();
        self.a_max_x.next = v[8].into();
        self.a_max_y.next = v[9].into();
        self.a_max_z.next = v[10].into();
    }
    fn outputs(&self) -> Vec<u64> {
        let mut v = self.visit_outputs();
        v.extend([
            u64::from(self.sort_start.val()),
            u64::from(self.sort_valid.val()),
            uval(self.sort_key.val()),
            uval(self.sort_val.val()),
            u64::from(self.sort_go.val()),
        ]);
        v
    }
}

impl Replay for SweepWalker<A, C> {
    fn input_ports() -> Vec<Port> {
        let mut p = common_inputs();
        p.push(Port::new("rd_key", obb_rtl::radix::KEY));
        p.push(Port::new("rd_val", obb_rtl::radix::VAL));
        p.push(Port::new("a_max", obb_rtl::projection::CENTER));
        p
    }
    fn output_ports() -> Vec<Port> {
        common_outputs()
    }
    fn inputs(&self) -> Vec<u64> {
        let mut v = self.control();
        v.extend([
            uval(self.rd_key.val()),
            uval(self.rd_val.val()),
            uval(self.a_max.val()),
        ]);
        v
    }
    fn apply(&mut self, v: &[u64]) {
        self.drive(v[0] == 1, v[1], v[2] == 1);
        self.rd_key.next = v[3].into();
        self.rd_val.next = v[4].into();
        self.a_max.next = v[5].into();
    }
    fn outputs(&self) -> Vec<u64> {
        self.visit_outputs()
    }
}

/// The walker's Verilog in Verilator against its rust-hdl simulation, both driven with
/// `vectors` (one per clock: the inputs applied, a rising edge, the outputs read): equal on
/// every output at every clock, and the walk finishes.
fn verilog_equals_rust_hdl<W: Replay>(make: impl Fn() -> W, name: &str, vectors: &[Vec<u64>]) {
    let verilog = obb_rtl::flow::emit::verilog(&mut make(), name).unwrap();
    let got = common::run_verilator(
        &verilog,
        name,
        &W::input_ports(),
        &W::output_ports(),
        vectors,
    );
    let want = common::run_rust_hdl(
        &mut make(),
        vectors,
        |u, v| u.apply(v),
        |u, c| u.set_clock(c),
        |u| u.outputs(),
    );
    assert_eq!(
        got, want,
        "{name}: Verilator against rust-hdl, clock by clock"
    );
    assert!(want.iter().any(|o| o[6] == 1), "{name}: the walk finishes");
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
            fn control(&self) -> Vec<u64> {
                vec![
                    u64::from(self.start.val()),
                    uval(self.n.val()),
                    u64::from(self.stall.val()),
                ]
            }
            fn visit_outputs(&self) -> Vec<u64> {
                vec![
                    u64::from(self.visit.val()),
                    uval(self.vi.val()),
                    uval(self.vj.val()),
                    uval(self.rd_addr.val()),
                    uval(self.a_addr.val()),
                    uval(self.b_addr.val()),
                    u64::from(self.finished.val()),
                ]
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
fn run_walk<W: Replay, T>(
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
        walk.inputs.push(u.inputs());
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
                visits: want.len() as u64,
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
            v.resize(Walker::<A, C>::input_ports().len(), 0);
            v
        })
        .collect();
    verilog_equals_rust_hdl(|| Walker::<A, C>::new(WalkMode::Brute), "walker", &vectors);
}

/// The improved-sap and sweep walkers' Verilog against their rust-hdl simulations, driven with
/// the inputs a closed-loop walk under random stalls gave them (the sort and the memories'
/// answers included): equal on every output at every clock.
#[test]
fn improved_sap_and_sweep_walkers_verilog_equal_their_rust_hdl_simulations() {
    let stall = Stall::Random(4).pattern(2000);
    let keys = sap_keys(14, 9);
    let (walk, _) = improved_sap_walk(&keys, 2, &stall);
    verilog_equals_rust_hdl(
        || Walker::<A, C>::new(WalkMode::ImprovedSap),
        "walker_sap",
        &walk.inputs,
    );
    let keys = sweep_keys(30, 5);
    let walk = sweep_walk(&keys, &stall);
    verilog_equals_rust_hdl(SweepWalker::<A, C>::default, "sweep_walker", &walk.inputs);
}

/// While `stall` stays high, at most `run_on` visits still come out (the pair FIFO's headroom
/// counts on the walker's `RUN_ON`).
fn assert_run_on(walk: &Walk, stall: &[bool], run_on: u64, what: &str) {
    let mut run = 0;
    for t in 1..=walk.finished {
        if stall[t - 1] {
            run += usize::from(walk.at.contains(&t));
            assert!(
                run as u64 <= run_on,
                "{what}: {run} visits into the stall that holds on clock {t}"
            );
        } else {
            run = 0;
        }
    }
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
            // restart), and a stall lets through at most its RUN_ON visits.
            if let Stall::Never = s {
                let work = BroadWork {
                    visits: want.len() as u64,
                    ..BroadWork::default()
                };
                let free = walk_cycles(BroadPhase::Sweep, n, &work) as usize;
                let expected = if n < 2 { 1 } else { free + 1 };
                assert_eq!(walk.finished, expected, "{name}: finished");
            }
            assert_run_on(&walk, &stall, sweep::RUN_ON, &format!("{name}, {s:?}"));
        }
    }
}

/// A box's keys (min, max) on x, y, z.
type Keys3 = [(u64, u64); 3];

/// Improved-sap's visits (the paper's Algorithm 2): per axis, the 2n end points (box 0 min,
/// box 0 max, box 1 min, ...) sorted stably by value with a min before a max of the same
/// value; from each min end point of box i, every end point read before i's own max is a visit
/// (i, its box), repeats included. Fewer than two boxes: no walk.
fn improved_sap_order(keys: &[Keys3]) -> Vec<(u64, u64)> {
    let mut visits = Vec::new();
    for axis in (0..3).filter(|_| keys.len() >= 2) {
        let mut ends: Vec<(u64, usize, bool)> = keys
            .iter()
            .enumerate()
            .flat_map(|(b, k)| [(k[axis].0, b, false), (k[axis].1, b, true)])
            .collect();
        ends.sort_by_key(|&(v, _, is_max)| (v, is_max));
        for (p, &(_, i, is_max)) in ends.iter().enumerate() {
            if is_max {
                continue;
            }
            for &(_, j, _) in ends[p + 1..].iter().take_while(|e| e.1 != i) {
                visits.push((i as u64, j as u64));
            }
        }
    }
    visits
}

/// The sort the improved-sap walker drives, as a behavioural model: `sort_start` empties it,
/// each `sort_valid` clock appends an entry, `sort_go` sorts the entries stably by key and
/// raises `sort_done` `delay` clocks after the go clock, until the next start. Its read port
/// (`rd_addr` to `rd_val`) and the key table's port A have a read latency of one clock.
struct SapHarness {
    keys: Vec<Keys3>,
    delay: usize,
    entries: Vec<(u64, u64)>,
    /// The entries each sort was given, in order.
    loads: Vec<Vec<(u64, u64)>>,
    done_in: Option<usize>,
}

/// What the walker shows the memories at a rising edge.
struct SapEdge {
    start: bool,
    valid: Option<(u64, u64)>,
    go: bool,
    rd: usize,
    a: usize,
}

impl SapHarness {
    fn edge(&mut self, e: SapEdge, u: &mut Walker<A, C>) {
        if e.start {
            self.entries.clear();
            self.done_in = None;
        }
        if let Some(entry) = e.valid {
            self.entries.push(entry);
        }
        if e.go {
            self.loads.push(self.entries.clone());
            self.entries.sort_by_key(|&(k, _)| k);
            self.done_in = Some(self.delay);
        }
        let done = match self.done_in {
            Some(0) => true,
            Some(d) => {
                self.done_in = Some(d - 1);
                false
            }
            None => false,
        };
        u.sort_done.next = done;
        // Past the last entry the memory holds whatever: the walker must not visit it.
        u.rd_val.next = self.entries.get(e.rd).map_or(0, |&(_, v)| v).into();
        let k = self.keys.get(e.a).copied().unwrap_or_default();
        u.a_min_x.next = k[0].0.into();
        u.a_min_y.next = k[1].0.into();
        u.a_min_z.next = k[2].0.into();
        u.a_max_x.next = k[0].1.into();
        u.a_max_y.next = k[1].1.into();
        u.a_max_z.next = k[2].1.into();
    }
}

/// Runs the improved-sap walker on boxes with keys `keys` (min, max per axis), its sort taking
/// `delay` clocks after `sort_go`. Returns the walk and the entries each sort was given.
fn improved_sap_walk(keys: &[Keys3], delay: usize, stall: &[bool]) -> (Walk, Vec<Vec<(u64, u64)>>) {
    let harness = std::cell::RefCell::new(SapHarness {
        keys: keys.to_vec(),
        delay,
        entries: Vec::new(),
        loads: Vec::new(),
        done_in: None,
    });
    let mut u = Walker::<A, C>::new(WalkMode::ImprovedSap);
    let walk = run_walk(
        &mut u,
        keys.len(),
        stall,
        |u| SapEdge {
            start: u.sort_start.val(),
            valid: u
                .sort_valid
                .val()
                .then(|| (uval(u.sort_key.val()), uval(u.sort_val.val()))),
            go: u.sort_go.val(),
            rd: uval(u.rd_addr.val()) as usize,
            a: uval(u.a_addr.val()) as usize,
        },
        |u, e| harness.borrow_mut().edge(e, u),
    );
    (walk, harness.into_inner().loads)
}

/// Random keys of `n` boxes on three axes: ties, nested and disjoint intervals.
fn sap_keys(n: usize, seed: u64) -> Vec<Keys3> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            std::array::from_fn(|_| {
                let min = rng.random_range(0..(3 * n as u64 + 1));
                (min, min + rng.random_range(0..8))
            })
        })
        .collect()
}

/// The improved-sap walker loads each axis's end points into the sort (box 0 min, box 0 max,
/// ...: key `2 v + is_max`, value `2 b + is_max`), then visits in Algorithm 2's order, none lost
/// or repeated beyond the algorithm's own repeats, under stalls; at most `walker::RUN_ON` visits
/// come into a stall; without stalls the walk takes the model's `walk_cycles` plus, per axis, the
/// clock of `sort_go` and the sort's own clocks.
#[test]
fn improved_sap_walker_visits_in_algorithm_2s_order_under_stalls() {
    let mut scenes: Vec<(String, Vec<Keys3>)> = vec![
        ("none".into(), vec![]),
        ("one".into(), vec![[(3, 5); 3]]),
        ("two apart".into(), vec![[(0, 1); 3], [(2, 3); 3]]),
        ("all equal".into(), vec![[(7, 7); 3]; 6]),
        (
            "one long".into(),
            vec![
                [(0, 100), (0, 1), (5, 5)],
                [(5, 6), (0, 1), (5, 5)],
                [(50, 60), (2, 3), (4, 6)],
            ],
        ),
    ];
    scenes.extend((0..3).map(|s| (format!("random {s}"), sap_keys(12 + 8 * s, s as u64))));
    for (name, keys) in &scenes {
        let want = improved_sap_order(keys);
        let n = keys.len();
        for delay in [0usize, 3] {
            for s in STALLS {
                let stall = s.pattern(8 * (want.len() + 6 * n + 3 * delay) + 60);
                let (walk, loads) = improved_sap_walk(keys, delay, &stall);
                assert_eq!(walk.visits, want, "{name}, sort delay {delay}, {s:?}");
                let axes = if n >= 2 { 3 } else { 0 };
                let expected_loads: Vec<Vec<(u64, u64)>> = (0..axes)
                    .map(|axis| {
                        keys.iter()
                            .enumerate()
                            .flat_map(|(b, k)| {
                                let b = b as u64;
                                [(k[axis].0 << 1, b << 1), (k[axis].1 << 1 | 1, b << 1 | 1)]
                            })
                            .collect()
                    })
                    .collect();
                assert_eq!(loads, expected_loads, "{name}, {s:?}: the sorts' entries");
                if let Stall::Never = s {
                    let work = BroadWork {
                        visits: want.len() as u64,
                        ..BroadWork::default()
                    };
                    let free = walk_cycles(BroadPhase::ImprovedSap, n as u64, &work) as usize;
                    let expected = if n < 2 {
                        1
                    } else {
                        free + axes * (1 + delay) + 1
                    };
                    assert_eq!(
                        walk.finished, expected,
                        "{name}, sort delay {delay}: finished"
                    );
                }
                assert_run_on(&walk, &stall, walker::RUN_ON, &format!("{name}, {s:?}"));
            }
        }
    }
}
