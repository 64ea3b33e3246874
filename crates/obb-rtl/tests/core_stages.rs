//! The core's own stages, each on its own, clock by clock, in rust-hdl and in Verilog
//! (Verilator): the load (`BoxLoad`) against the stream protocol written here, and, between the
//! broad phase and the SAT, the key check (`KeyCheck`) and the geometry fetch
//! (`GeometryFetch`), against references written here from the clock table in `core.rs`, on
//! random traffic with ties, the keys' extremes and every group pair.

use crate::common;

use common::{in_verilator, ports, raw, run_rust_hdl, signed};
use obb_model::fixed::HwConfig;
use obb_rtl::box_load::BoxLoad;
use obb_rtl::flow::verilator::Port;
use obb_rtl::geometry_fetch::GeometryFetch;
use obb_rtl::key_check::{KeyCheck, MASK};
use obb_rtl::leaf::{sbits, sval, uval};
use obb_rtl::projection::{CENTER, HALF, MARGIN, ROT};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rust_hdl::prelude::*;

/// Box indices of 5 bits: small enough that equal and swapped pairs come often.
const A: usize = 5;
const GROUP: usize = obb_model::fixed::config::GROUP_BITS as usize;
const CLOCKS: usize = 600;

/// A key: mostly from a few small values (ties between one box's min and the other's max come
/// often), sometimes anywhere in the key's range, its largest value included (the compare is
/// unsigned).
fn key(rng: &mut StdRng) -> u64 {
    match rng.random_range(0..8) {
        0 => (1 << CENTER) - 1,
        1 => rng.random_range(0..1u64 << CENTER),
        _ => rng.random_range(0..6),
    }
}

/// The key check's inputs, in the order of `KEY_CHECK_INPUTS`.
struct CheckIn {
    visit: bool,
    i: u64,
    j: u64,
    /// Box i's and box j's min keys, then their max keys, x, y, z.
    min_a: [u64; 3],
    min_b: [u64; 3],
    max_a: [u64; 3],
    max_b: [u64; 3],
    margin_a: u64,
    margin_b: u64,
    group_a: u64,
    group_b: u64,
    mask: u64,
    unchecked: bool,
    idle: bool,
}

impl CheckIn {
    fn from(v: &[u64]) -> CheckIn {
        let three = |k: usize| [v[k], v[k + 1], v[k + 2]];
        CheckIn {
            visit: v[0] == 1,
            i: v[1],
            j: v[2],
            min_a: three(3),
            min_b: three(6),
            max_a: three(9),
            max_b: three(12),
            margin_a: v[15],
            margin_b: v[16],
            group_a: v[17],
            group_b: v[18],
            mask: v[19],
            unchecked: v[20] == 1,
            idle: v[21] == 1,
        }
    }
}

fn key_check_inputs() -> Vec<Port> {
    let mut p = vec![Port::new("visit", 1), Port::new("i", A), Port::new("j", A)];
    for name in ["min_a", "min_b", "max_a", "max_b"] {
        p.extend(ports(name, 3, CENTER));
    }
    p.extend([
        Port::new("margin_a", MARGIN),
        Port::new("margin_b", MARGIN),
        Port::new("group_a", GROUP),
        Port::new("group_b", GROUP),
        Port::new("mask", MASK),
        Port::new("unchecked", 1),
        Port::new("idle", 1),
    ]);
    p
}

fn key_check_outputs() -> Vec<Port> {
    vec![
        Port::new("visited", 1),
        Port::new("overlap", 1),
        Port::new("test_valid", 1),
        Port::new("test_a", A),
        Port::new("test_b", A),
        Port::new("test_ma", MARGIN),
        Port::new("test_mb", MARGIN),
    ]
}

/// Random key-check traffic: visits on about two clocks in three, the mode inputs held for
/// stretches (as the core holds them for a frame) and a random group mask per stretch.
fn key_check_traffic(seed: u64) -> Vec<Vec<u64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let (mut mask, mut unchecked, mut idle) = (0u64, 0u64, 0u64);
    (0..CLOCKS)
        .map(|t| {
            if t % 100 == 0 {
                mask = rng.random();
                unchecked = u64::from(t % 300 == 100);
                idle = u64::from(t % 300 == 200);
            }
            let mut v = vec![
                u64::from(rng.random_bool(0.7)),
                rng.random_range(0..1 << A),
                rng.random_range(0..1 << A),
            ];
            v.extend((0..12).map(|_| key(&mut rng)));
            v.extend([
                rng.random_range(0..1 << MARGIN),
                rng.random_range(0..1 << MARGIN),
                rng.random_range(0..1 << GROUP),
                rng.random_range(0..1 << GROUP),
                mask,
                unchecked,
                idle,
            ]);
            v
        })
        .collect()
}

/// What the key check must give, read after each clock's rising edge (the clock's inputs still
/// applied): a visit applied on clock V is counted after V's edge; its keys, margins and groups
/// come with clock V+1's inputs and their overlap shows after that edge; the mask and the mode
/// are those of clock V+2, after whose edge the test shows, its boxes in index order with their
/// margins. Mask bit `8 g_i + g_j` pairs box i's group with box j's.
fn key_check_reference(v: &[Vec<u64>]) -> Vec<Vec<u64>> {
    let ins: Vec<CheckIn> = v.iter().map(|x| CheckIn::from(x)).collect();
    // The registers' reset value, before the first inputs are through.
    let reset = CheckIn::from(&[0; 22]);
    let overlaps =
        |k: &CheckIn| (0..3).all(|x| k.min_a[x] <= k.max_b[x] && k.min_b[x] <= k.max_a[x]);
    (0..ins.len())
        .map(|t| {
            let now = &ins[t];
            let mut out = vec![u64::from(now.visit), u64::from(overlaps(now))];
            let visit = if t >= 2 { &ins[t - 2] } else { &reset };
            let keys = if t >= 1 { &ins[t - 1] } else { &reset };
            let paired = now.mask >> (8 * keys.group_a + keys.group_b) & 1 == 1;
            let test = visit.visit && (overlaps(keys) || now.unchecked) && paired && !now.idle;
            let (a, b, ma, mb) = if visit.j < visit.i {
                (visit.j, visit.i, keys.margin_b, keys.margin_a)
            } else {
                (visit.i, visit.j, keys.margin_a, keys.margin_b)
            };
            out.extend([u64::from(test), a, b, ma, mb]);
            out
        })
        .collect()
}

fn apply_key_check(u: &mut KeyCheck<A>, v: &[u64]) {
    let k = CheckIn::from(v);
    u.visit.next = k.visit;
    u.i.next = k.i.into();
    u.j.next = k.j.into();
    for x in 0..3 {
        u.min_a[x].next = k.min_a[x].into();
        u.min_b[x].next = k.min_b[x].into();
        u.max_a[x].next = k.max_a[x].into();
        u.max_b[x].next = k.max_b[x].into();
    }
    u.margin_a.next = k.margin_a.into();
    u.margin_b.next = k.margin_b.into();
    u.group_a.next = k.group_a.into();
    u.group_b.next = k.group_b.into();
    u.mask.next = k.mask.into();
    u.unchecked.next = k.unchecked;
    u.idle.next = k.idle;
}

fn key_check_read(u: &KeyCheck<A>) -> Vec<u64> {
    vec![
        u64::from(u.visited.val()),
        u64::from(u.overlap.val()),
        u64::from(u.test_valid.val()),
        uval(u.test_a.val()),
        uval(u.test_b.val()),
        uval(u.test_ma.val()),
        uval(u.test_mb.val()),
    ]
}

/// The key check in rust-hdl and in Verilog against the reference, every output at every
/// clock: the overlap with ties on every axis and the keys' largest value, the mask read at
/// the test's group pair, the improved-sap mode (every allowed visit a test) and the grid mode
/// (none), the pair put in index order with its margins.
#[test]
fn key_check_matches_its_clock_table() {
    for seed in [1, 2] {
        let v = key_check_traffic(seed);
        let want = key_check_reference(&v);
        // The traffic reaches every case the reference distinguishes.
        let tests = want.iter().filter(|o| o[2] == 1).count();
        let refused = (2..v.len())
            .filter(|&t| v[t - 2][0] == 1 && want[t][2] == 0)
            .count();
        assert!(
            tests > 50 && refused > 50,
            "seed {seed}: {tests} tests, {refused} refused"
        );
        assert!(want.iter().any(|o| o[1] == 1) && want.iter().any(|o| o[1] == 0));
        let got = run_rust_hdl(
            &mut KeyCheck::<A>::default(),
            &v,
            apply_key_check,
            |u, c| u.clock.next = Clock::from(c),
            key_check_read,
        );
        assert_eq!(got, want, "rust-hdl, seed {seed}");
        let got = in_verilator(
            &mut KeyCheck::<A>::default(),
            "key_check",
            &key_check_inputs(),
            &key_check_outputs(),
            &v,
        );
        assert_eq!(got, want, "Verilog, seed {seed}");
    }
}

/// One box's geometry as the tables hold it: center, half-lengths, axes (raw bits).
#[derive(Clone)]
struct Geometry {
    center: [u64; 3],
    half: [u64; 3],
    axes: [u64; 9],
}

impl Geometry {
    fn random(rng: &mut StdRng) -> Geometry {
        let some = |rng: &mut StdRng, bits: usize| match rng.random_range(0..4) {
            0 => (1 << bits) - 1,
            1 => 1 << (bits - 1),
            _ => rng.random_range(0..1u64 << bits),
        };
        Geometry {
            center: std::array::from_fn(|_| some(rng, CENTER)),
            half: std::array::from_fn(|_| some(rng, HALF)),
            axes: std::array::from_fn(|_| some(rng, ROT)),
        }
    }
}

/// Inputs: the test (valid, a, b, ma, mb), then the tables' answers for ports A and B
/// (centers, half-lengths, axes); as `apply_fetch` reads them.
fn fetch_inputs() -> Vec<Port> {
    let mut p = vec![
        Port::new("test_valid", 1),
        Port::new("test_a", A),
        Port::new("test_b", A),
        Port::new("test_ma", MARGIN),
        Port::new("test_mb", MARGIN),
    ];
    for side in ["a", "b"] {
        p.extend(ports(&format!("read_center_{side}"), 3, CENTER));
    }
    for side in ["a", "b"] {
        p.extend(ports(&format!("read_half_{side}"), 3, HALF));
    }
    for side in ["a", "b"] {
        p.extend(ports(&format!("read_axes_{side}"), 9, ROT));
    }
    p
}

fn fetch_outputs() -> Vec<Port> {
    let mut p = vec![
        Port::new("addr_a", A),
        Port::new("addr_b", A),
        Port::new("fetching", 1),
        Port::new("valid", 1),
        Port::new("a", A),
        Port::new("b", A),
        Port::new("ma", MARGIN),
        Port::new("mb", MARGIN),
    ];
    for (name, bits) in [("center", CENTER), ("half", HALF)] {
        p.extend(ports(&format!("{name}_a"), 3, bits));
        p.extend(ports(&format!("{name}_b"), 3, bits));
    }
    p.extend(ports("axes_a", 9, ROT));
    p.extend(ports("axes_b", 9, ROT));
    p
}

/// Tests on about half the clocks, back to back at times; the tables answer as block RAMs do:
/// the data of the address a clock's inputs gave comes with the next clock's inputs (the
/// reference checks that the block gives the tables the test's boxes as addresses).
fn fetch_traffic(seed: u64, table: &[Geometry]) -> Vec<Vec<u64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut v: Vec<Vec<u64>> = Vec::new();
    for t in 0..CLOCKS {
        let test = vec![
            u64::from(rng.random_bool(0.5)),
            rng.random_range(0..1 << A),
            rng.random_range(0..1 << A),
            rng.random_range(0..1 << MARGIN),
            rng.random_range(0..1 << MARGIN),
        ];
        let (a, b) = match t {
            0 => (&table[0], &table[0]),
            _ => (&table[v[t - 1][1] as usize], &table[v[t - 1][2] as usize]),
        };
        let mut x = test;
        x.extend(a.center.iter().chain(&b.center));
        x.extend(a.half.iter().chain(&b.half));
        x.extend(a.axes.iter().chain(&b.axes));
        v.push(x);
    }
    v
}

/// What the fetch must give after each clock's edge: the tables' addresses are the test's
/// boxes at once; the test is counted (`fetching`) after its own clock's edge; it reaches the
/// SAT's inputs after the next edge, with its margins and the geometry of its two boxes.
fn fetch_reference(v: &[Vec<u64>], table: &[Geometry]) -> Vec<Vec<u64>> {
    (0..v.len())
        .map(|t| {
            let mut out = vec![v[t][1], v[t][2], v[t][0]];
            // Before the first test is through: the registers' reset value, and the tables'
            // answer to address 0.
            let test = if t >= 1 { &v[t - 1][..5] } else { &[0; 5] };
            out.extend(test);
            let (a, b) = (&table[test[1] as usize], &table[test[2] as usize]);
            out.extend(a.center.iter().chain(&b.center));
            out.extend(a.half.iter().chain(&b.half));
            out.extend(a.axes.iter().chain(&b.axes));
            out
        })
        .collect()
}

fn apply_fetch(u: &mut GeometryFetch<A>, v: &[u64]) {
    u.test_valid.next = v[0] == 1;
    u.test_a.next = v[1].into();
    u.test_b.next = v[2].into();
    u.test_ma.next = v[3].into();
    u.test_mb.next = v[4].into();
    let (centers, halves, axes) = (&v[5..11], &v[11..17], &v[17..35]);
    for x in 0..3 {
        u.read_center_a[x].next = centers[x].into();
        u.read_center_b[x].next = centers[3 + x].into();
        u.read_half_a[x].next = halves[x].into();
        u.read_half_b[x].next = halves[3 + x].into();
    }
    for k in 0..9 {
        u.read_axes_a[k].next = sbits(signed(axes[k], ROT));
        u.read_axes_b[k].next = sbits(signed(axes[9 + k], ROT));
    }
}

fn fetch_read(u: &GeometryFetch<A>) -> Vec<u64> {
    let mut out = vec![
        uval(u.addr_a.val()),
        uval(u.addr_b.val()),
        u64::from(u.fetching.val()),
        u64::from(u.valid.val()),
        uval(u.a.val()),
        uval(u.b.val()),
        uval(u.ma.val()),
        uval(u.mb.val()),
    ];
    out.extend(u.center_a.iter().chain(&u.center_b).map(|s| uval(s.val())));
    out.extend(u.half_a.iter().chain(&u.half_b).map(|s| uval(s.val())));
    out.extend(
        u.axes_a
            .iter()
            .chain(&u.axes_b)
            .map(|s| raw(sval(s.val()), ROT)),
    );
    out
}

/// The geometry fetch in rust-hdl and in Verilog against the reference, every output at every
/// clock: each test's two boxes' geometry (the fields' extremes and the axes' sign included)
/// beside the test and its margins, one clock after it is counted.
#[test]
fn geometry_fetch_matches_its_clock_table() {
    let mut rng = StdRng::seed_from_u64(7);
    let table: Vec<Geometry> = (0..1 << A).map(|_| Geometry::random(&mut rng)).collect();
    let v = fetch_traffic(8, &table);
    let want = fetch_reference(&v, &table);
    assert!(want.iter().filter(|o| o[3] == 1).count() > CLOCKS / 3);
    let got = run_rust_hdl(
        &mut GeometryFetch::<A>::default(),
        &v,
        apply_fetch,
        |u, c| u.clock.next = Clock::from(c),
        fetch_read,
    );
    assert_eq!(got, want, "rust-hdl");
    let got = in_verilator(
        &mut GeometryFetch::<A>::default(),
        "geometry_fetch",
        &fetch_inputs(),
        &fetch_outputs(),
        &v,
    );
    assert_eq!(got, want, "Verilog");
}

/// The load's tables: 6 boxes (indices of 3 bits, counts of 4).
const LOAD_A: usize = 3;
const LOAD_C: usize = 4;
const LOAD_CAPACITY: u64 = 6;

fn load_config(resident: &[u32]) -> HwConfig {
    HwConfig {
        capacity: LOAD_CAPACITY as u32,
        resident_groups: resident.to_vec(),
        ..HwConfig::default()
    }
}

/// The load as its protocol says (`box_load.rs`): its state between clocks.
#[derive(Clone, Copy, Default)]
struct LoadState {
    loading: bool,
    room: bool,
    count: u64,
    resident_count: u64,
    resident_room: bool,
    haptic: bool,
    streamed_seen: bool,
    /// An update frame has loaded whole since the last began (haptic frames may follow); a
    /// resident box was refused in this frame.
    resident_ok: bool,
    spoiled: bool,
}

/// A clock's inputs: frame_start, frame_update, obb_valid, obb_last, obb_group, credit; the
/// core's registers live, restart_go, restart_update.
fn load_inputs() -> Vec<Port> {
    vec![
        Port::new("frame_start", 1),
        Port::new("frame_update", 1),
        Port::new("obb_valid", 1),
        Port::new("obb_last", 1),
        Port::new("obb_group", GROUP),
        Port::new("credit", 1),
        Port::new("live", 1),
        Port::new("restart_go", 1),
        Port::new("restart_update", 1),
    ]
}

fn load_outputs() -> Vec<Port> {
    vec![
        Port::new("obb_ready", 1),
        Port::new("accept", 1),
        Port::new("index", LOAD_A),
        Port::new("loaded", LOAD_C),
        Port::new("loading", 1),
        Port::new("ended", 1),
        Port::new("refused", 1),
        Port::new("first", LOAD_C),
        Port::new("frame_begin", 1),
        Port::new("update", 1),
        Port::new("frame_abort", 1),
    ]
}

/// The outputs of state `s` under the clock's inputs `v`, in `load_outputs`' order.
fn load_outputs_of(s: &LoadState, v: &[u64], resident: &[u32]) -> Vec<u64> {
    let (start, valid, last, group, credit) = (v[0] == 1, v[2] == 1, v[3] == 1, v[4], v[5] == 1);
    let (live, go) = (v[6] == 1, v[7] == 1);
    // A frame begins on a frame_start with none under way, or when the core restarts after an
    // abort; a frame_start during a frame aborts it. The frame_start's update is the later.
    let begin = (start && !live) || go;
    let abort = start && live && !go;
    let update = if start { v[1] == 1 } else { v[8] == 1 };
    // A box is taken when the load is on and the broad phase has room for it; past the
    // capacity it is taken whatever the credit, and dropped. Nothing is taken on a
    // frame_start's clock.
    let ready = s.loading && !start && (credit || !s.room);
    let accept = ready && valid && s.room;
    let is_resident = resident.contains(&(group as u32));
    let out_of_place = accept && is_resident && (s.haptic || s.streamed_seen);
    // A haptic frame with no whole update frame before it is refused.
    let unsure = s.haptic && !s.resident_ok;
    let refused = (s.loading && ((valid && !s.room) || unsure)) || out_of_place;
    let ended = s.loading && !start && last && (ready || !valid);
    let first = if !resident.is_empty() && !update {
        s.resident_count
    } else {
        0
    };
    [
        u64::from(ready),
        u64::from(accept),
        s.count % (1 << LOAD_A),
        s.count,
        u64::from(s.loading),
        u64::from(ended),
        u64::from(refused),
        first,
        u64::from(begin),
        u64::from(update),
        u64::from(abort),
    ]
    .to_vec()
}

/// The state after a clock's edge.
fn load_step(s: &LoadState, v: &[u64], resident: &[u32]) -> LoadState {
    let out = load_outputs_of(s, v, resident);
    let (accept, ended, refused) = (out[1] == 1, out[5] == 1, out[6] == 1);
    let (begin, update, abort) = (out[8] == 1, out[9] == 1, out[10] == 1);
    let box_resident = resident.contains(&(v[4] as u32));
    let mut n = *s;
    if accept {
        n.count = s.count + 1;
        n.room = s.count + 1 < LOAD_CAPACITY;
        if resident.contains(&(v[4] as u32)) {
            if !(s.haptic || s.streamed_seen) {
                n.resident_count = s.count + 1;
                n.resident_room = s.count + 1 < LOAD_CAPACITY;
            }
        } else {
            n.streamed_seen = true;
        }
    }
    if refused && box_resident {
        n.spoiled = true;
        n.resident_ok = false;
    }
    if ended {
        n.loading = false;
        if !(s.haptic || s.spoiled || (refused && box_resident)) {
            n.resident_ok = true;
        }
    }
    if abort {
        n.loading = false;
    }
    if begin {
        let has_resident = !resident.is_empty();
        n.loading = true;
        n.streamed_seen = false;
        n.spoiled = false;
        n.haptic = has_resident && !update;
        (n.count, n.room) = (0, true);
        if has_resident && update {
            (n.resident_count, n.resident_room) = (0, true);
            n.resident_ok = false;
        } else if has_resident {
            (n.count, n.room) = (s.resident_count, s.resident_room);
        }
    }
    n
}

/// What the load gives after each clock's edge, the clock's inputs still applied (`after`),
/// and before it: what the edge does (`before`: a box taken, the load's end, a refusal).
fn load_reference(v: &[Vec<u64>], resident: &[u32], after: bool) -> Vec<Vec<u64>> {
    let mut s = LoadState::default();
    v.iter()
        .map(|x| {
            let before = load_outputs_of(&s, x, resident);
            s = load_step(&s, x, resident);
            if after {
                load_outputs_of(&s, x, resident)
            } else {
                before
            }
        })
        .collect()
}

/// Frames of 0 to 9 boxes (past the capacity of 6 at times) in groups 0 to 3, boxes on about
/// 7 clocks in 10, the credit withheld on about 1 in 5, update frames and haptic ones at
/// random, `obb_last` with the last box or alone, and now and then a `frame_start` in the middle
/// of a load. A frame begins on `frame_start` with no frame live, or aborts a live one and
/// begins on the core's `restart_go` a few clocks later (now and then on the same clock as
/// another `frame_start`, whose update wins). The sender moves on to its next box when the
/// protocol says the box was taken.
fn load_traffic(seed: u64, resident: &[u32]) -> Vec<Vec<u64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut v = Vec::new();
    let mut s = LoadState::default();
    let mut send = |v: &mut Vec<Vec<u64>>, x: Vec<u64>| {
        let before = load_outputs_of(&s, &x, resident);
        s = load_step(&s, &x, resident);
        v.push(x);
        (before[0] == 1, before[5] == 1)
    };
    while v.len() < CLOCKS {
        let update = u64::from(rng.random_bool(0.5));
        if rng.random_bool(0.25) {
            send(&mut v, vec![1, update, 0, 0, 0, 1, 1, 0, 0]);
            for _ in 0..rng.random_range(0..3) {
                send(&mut v, vec![0, 0, 0, 0, 0, 1, 1, 0, 0]);
            }
            let again = u64::from(rng.random_bool(0.2));
            send(&mut v, vec![again, 1 - update, 0, 0, 0, 1, 0, 1, update]);
        } else {
            send(&mut v, vec![1, update, 0, 0, 0, 1, 0, 0, 0]);
        }
        let boxes = rng.random_range(0..10);
        let abort = rng.random_bool(0.1);
        let mut sent = 0;
        for _ in 0..40 {
            if abort && sent == boxes / 2 {
                break;
            }
            let valid = sent < boxes && rng.random_bool(0.7);
            let last = (valid && sent + 1 == boxes) || (!valid && sent == boxes);
            let group = rng.random_range(0..4);
            let credit = rng.random_bool(0.8);
            let (ready, ended) = send(
                &mut v,
                vec![
                    0,
                    0,
                    u64::from(valid),
                    u64::from(last),
                    group,
                    u64::from(credit),
                    0,
                    0,
                    0,
                ],
            );
            sent += usize::from(valid && ready);
            if ended {
                break;
            }
        }
        for _ in 0..rng.random_range(0..3) {
            send(&mut v, vec![0, 0, 0, 0, 0, 1, 0, 0, 0]);
        }
    }
    v
}

fn apply_load(u: &mut BoxLoad<LOAD_A, LOAD_C>, v: &[u64]) {
    u.frame_start.next = v[0] == 1;
    u.frame_update.next = v[1] == 1;
    u.obb_valid.next = v[2] == 1;
    u.obb_last.next = v[3] == 1;
    u.obb_group.next = v[4].into();
    u.credit.next = v[5] == 1;
    u.live.next = v[6] == 1;
    u.restart_go.next = v[7] == 1;
    u.restart_update.next = v[8] == 1;
}

fn load_read(u: &BoxLoad<LOAD_A, LOAD_C>) -> Vec<u64> {
    vec![
        u64::from(u.obb_ready.val()),
        u64::from(u.accept.val()),
        uval(u.index.val()),
        uval(u.loaded.val()),
        u64::from(u.loading.val()),
        u64::from(u.ended.val()),
        u64::from(u.refused.val()),
        uval(u.first.val()),
        u64::from(u.frame_begin.val()),
        u64::from(u.update.val()),
        u64::from(u.frame_abort.val()),
    ]
}

/// The load in rust-hdl and in Verilog against its protocol, every output at every clock: boxes
/// taken only while loading with the credit and room, stored at consecutive indices; past the
/// capacity taken, dropped and the frame refused; the load's end with its last box or with
/// `obb_last` alone; a `frame_start` mid-load restarting it, or aborting it (the core's `live`)
/// until `restart_go`; with resident groups (0 and 2), update frames keeping their resident
/// count, haptic frames starting after it (refused until an update frame has loaded whole), and
/// a resident box out of place refusing the frame.
#[test]
fn box_load_follows_the_stream_protocol() {
    for (seed, resident) in [(1, vec![]), (2, vec![0, 2])] {
        let v = load_traffic(seed, &resident);
        let want = load_reference(&v, &resident, true);
        let edges = load_reference(&v, &resident, false);
        let count = |k: usize| edges.iter().filter(|o| o[k] == 1).count();
        let (accepted, ended, refused, aborted) = (count(1), count(5), count(6), count(10));
        assert!(
            accepted > 100 && ended > 20 && refused > 5 && aborted > 5,
            "seed {seed}: {accepted} taken, {ended} ends, {refused} refusals, {aborted} aborts"
        );
        assert!(
            want.iter().any(|o| o[3] == LOAD_CAPACITY),
            "the tables filled"
        );
        if !resident.is_empty() {
            assert!(
                want.iter().any(|o| o[7] > 0),
                "a haptic frame after residents"
            );
        }
        let config = load_config(&resident);
        let got = run_rust_hdl(
            &mut BoxLoad::<LOAD_A, LOAD_C>::new(&config),
            &v,
            apply_load,
            |u, c| u.clock.next = Clock::from(c),
            load_read,
        );
        assert_eq!(got, want, "rust-hdl, resident {resident:?}");
        let name = format!("box_load_{seed}");
        let got = in_verilator(
            &mut BoxLoad::<LOAD_A, LOAD_C>::new(&config),
            &name,
            &load_inputs(),
            &load_outputs(),
            &v,
        );
        assert_eq!(got, want, "Verilog, resident {resident:?}");
    }
}
