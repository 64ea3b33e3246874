//! The radix sort against `obb_model::radix::RadixSorter`: the same order (a stable sort has
//! one), and `done` exactly the model's `sort_cycles` clocks after `go`, in rust-hdl and in
//! Verilator; with the core's 24-bit keys and with the 63-bit keys a grid's cells need.

use crate::common;

use obb_model::radix::RadixSorter;
use obb_rtl::leaf::uval;
use obb_rtl::radix::{RadixSort, ENTRY, KEY};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use rust_hdl::prelude::*;

const A: usize = 8;
const C: usize = 9;

type Sorter<const K: usize, const E: usize> = RadixSort<A, C, K, E>;
/// The widest keys: a grid cell key (three 20-bit coordinates and three flags).
const WIDE: usize = 63;
const WIDE_ENTRY: usize = WIDE + obb_rtl::radix::VAL;

fn tick<const K: usize, const E: usize>(u: &mut Sorter<K, E>) {
    u.clock.next = Clock::from(false);
    assert!(simulate(u, 1000));
    u.clock.next = Clock::from(true);
    assert!(simulate(u, 1000));
}

/// Sorts in rust-hdl; returns the sorted (key, value) pairs and the clocks from `go` to `done`.
fn rust_hdl_sort<const K: usize, const E: usize>(
    keys: &[u64],
    key_bits: u32,
    digit: u32,
) -> (Vec<(u64, u64)>, u64) {
    let mut u = Sorter::<K, E>::new(key_bits, digit);
    u.connect_all();
    sort_on(&mut u, keys, false)
}

/// One sort on `u` as it is (it may be in the middle of another): `start`, the loads, `go` (with
/// the last load, or the clock after), then the reads once `done`.
fn sort_on<const K: usize, const E: usize>(
    u: &mut Sorter<K, E>,
    keys: &[u64],
    go_with_last: bool,
) -> (Vec<(u64, u64)>, u64) {
    u.start.next = true;
    tick(u);
    u.start.next = false;
    for (i, &k) in keys.iter().enumerate() {
        u.in_valid.next = true;
        u.in_key.next = k.into();
        u.in_val.next = (i as u64).into();
        u.go.next = go_with_last && i + 1 == keys.len();
        tick(u);
    }
    u.in_valid.next = false;
    let mut clocks = 1;
    if !go_with_last || keys.is_empty() {
        u.go.next = true;
        tick(u);
    }
    u.go.next = false;
    while !u.done.val() {
        tick(u);
        clocks += 1;
        assert!(clocks < 100_000, "never done");
    }
    let mut out = Vec::new();
    for i in 0..keys.len() {
        u.rd_addr.next = (i as u64).into();
        tick(u);
        out.push((uval(u.rd_key.val()), uval(u.rd_val.val())));
    }
    (out, clocks)
}

/// A sort cut short at every stage (loading, settling, prefix sum, scatter, between passes)
/// leaves nothing behind: the next sort on the same block, started at once, equals the model;
/// `go` may come with the last entry; and a finished sort is followed by another.
#[test]
fn radix_sort_restarts_cleanly_in_rust_hdl() {
    let (key_bits, digit) = (12u32, 4u32);
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut keys = |n: usize| -> Vec<u64> {
        proptest::collection::vec(0..(1u64 << key_bits), n..=n)
            .new_tree(&mut runner)
            .unwrap()
            .current()
    };
    let first = keys(40);
    let (_, full) = model_sort(&first, key_bits, digit);
    for cut in [3u64, 41, 43, 50, 70, 100, full - 2, full + 5] {
        let mut u = Sorter::<KEY, ENTRY>::new(key_bits, digit);
        u.connect_all();
        u.start.next = true;
        tick(&mut u);
        u.start.next = false;
        // `cut` clocks from the first load: in the loads, or after `go` (clock 41).
        for c in 0..cut {
            let k = c as usize;
            u.in_valid.next = k < first.len();
            u.in_key.next = first.get(k).copied().unwrap_or(0).into();
            u.in_val.next = (k as u64).into();
            u.go.next = k == first.len();
            tick(&mut u);
        }
        let second = keys(30);
        let (got, clocks) = sort_on(&mut u, &second, cut % 2 == 0);
        let (want, want_clocks) = model_sort(&second, key_bits, digit);
        assert_eq!(got, want, "cut after {cut} clocks");
        assert_eq!(clocks, want_clocks, "clocks, cut after {cut} clocks");
        let third = keys(17);
        assert_eq!(
            sort_on(&mut u, &third, true),
            model_sort(&third, key_bits, digit)
        );
    }
}

fn model_sort(keys: &[u64], key_bits: u32, digit: u32) -> (Vec<(u64, u64)>, u64) {
    let mut sorter = RadixSorter::<u32>::new(digit);
    let mut k = keys.to_vec();
    let mut v: Vec<u32> = (0..keys.len() as u32).collect();
    sorter.sort(&mut k, &mut v, key_bits);
    // The model's cycle count for a sort: the hardware must take exactly this.
    let clocks = obb_model::fixed::cycles::sort_cycles(
        keys.len() as u64,
        sorter.passes(key_bits),
        sorter.digit_bits(key_bits),
    );
    (
        k.into_iter().zip(v.into_iter().map(u64::from)).collect(),
        clocks,
    )
}

#[test]
fn radix_sort_matches_the_model_in_rust_hdl() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    for (n, key_bits, digit) in [
        (0usize, 8u32, 8u32),
        (1, 8, 4),
        (37, 12, 4),
        (200, 20, 8),
        (256, 23, 6),
        (120, 63, 8),
        (90, 40, 5),
    ] {
        let keys: Vec<u64> = proptest::collection::vec(
            prop_oneof![
                Just(0u64),
                Just((1u64 << key_bits) - 1),
                0..(1u64 << key_bits),
                0..4u64
            ],
            n..=n,
        )
        .new_tree(&mut runner)
        .unwrap()
        .current();
        let (got, clocks) = if key_bits as usize > KEY {
            rust_hdl_sort::<WIDE, WIDE_ENTRY>(&keys, key_bits, digit)
        } else {
            rust_hdl_sort::<KEY, ENTRY>(&keys, key_bits, digit)
        };
        let (want, want_clocks) = model_sort(&keys, key_bits, digit);
        assert_eq!(got, want, "n={n} key_bits={key_bits} digit={digit}");
        assert_eq!(
            clocks, want_clocks,
            "clocks, n={n} key_bits={key_bits} digit={digit}"
        );
    }
}

/// One vector per clock: start, in_valid, in_key, in_val, go, rd_addr. The same sequence as
/// `rust_hdl_sort`: start, the loads, go, `wait` clocks, then one read per entry.
fn vectors(keys: &[u64], wait: u64) -> Vec<Vec<u64>> {
    let mut v = vec![vec![1, 0, 0, 0, 0, 0]];
    v.extend(
        keys.iter()
            .enumerate()
            .map(|(i, &k)| vec![0, 1, k, i as u64, 0, 0]),
    );
    v.push(vec![0, 0, 0, 0, 1, 0]);
    v.extend((1..wait).map(|_| vec![0; 6]));
    v.extend((0..keys.len() as u64).map(|i| vec![0, 0, 0, 0, 0, i]));
    v
}

#[test]
fn radix_sort_verilog_matches_the_model_in_verilator() {
    verilator_sort::<KEY, ENTRY>(250, 20, 7);
    verilator_sort::<WIDE, WIDE_ENTRY>(100, 63, 8);
}

/// `n` random keys of `key_bits` bits sorted by the emitted Verilog of the K-bit sort.
fn verilator_sort<const K: usize, const E: usize>(n: usize, key_bits: u32, digit: u32) {
    use obb_rtl::flow::verilator::Port;
    use obb_rtl::radix::VAL;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let keys: Vec<u64> =
        proptest::collection::vec(prop_oneof![0..(1u64 << key_bits), 0..4u64], n..=n)
            .new_tree(&mut runner)
            .unwrap()
            .current();
    let (want, clocks) = model_sort(&keys, key_bits, digit);
    let v = vectors(&keys, clocks);
    let mut u = Sorter::<K, E>::new(key_bits, digit);
    let verilog = obb_rtl::flow::emit::verilog(&mut u, "radix_sort").unwrap();
    let inputs = [
        Port::new("start", 1),
        Port::new("in_valid", 1),
        Port::new("in_key", K),
        Port::new("in_val", VAL),
        Port::new("go", 1),
        Port::new("rd_addr", A),
    ];
    let outputs = [
        Port::new("done", 1),
        Port::new("rd_key", K),
        Port::new("rd_val", VAL),
    ];
    let out = common::run_verilator(&verilog, "radix_sort", &inputs, &outputs, &v);
    // `done` rises on the clock of the last `wait` vector, `clocks` after `go`.
    let go = 1 + n;
    let first_done = out.iter().position(|o| o[0] == 1).expect("done rises");
    assert_eq!(
        first_done as u64,
        go as u64 + clocks - 1,
        "done, {K}-bit keys"
    );
    let reads = &out[out.len() - n..];
    let got: Vec<(u64, u64)> = reads.iter().map(|o| (o[1], o[2])).collect();
    assert_eq!(got, want, "{K}-bit keys");
}
