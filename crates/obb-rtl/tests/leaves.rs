//! Each arithmetic leaf: its Rust model (the rust-hdl simulation) against its own Verilog in
//! Verilator, clock by clock, on random operands including the extremes; and the latencies the
//! model's cycle count assumes.

use obb_rtl::leaf::{sbits, uval, AbsTwice, UMul};
use obb_rtl::table_ram::TableRam;
use obb_rtl::verilator::{self, Port};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use rust_hdl::prelude::*;

/// One clock: apply the inputs, rising edge, read the outputs.
fn tick<B: Block>(uut: &mut B, clock: impl Fn(&mut B, bool)) {
    clock(uut, false);
    assert!(simulate(uut, 1000));
    clock(uut, true);
    assert!(simulate(uut, 1000));
}

fn vectors(strategy: impl Strategy<Value = Vec<u64>>, n: usize) -> Vec<Vec<u64>> {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    (0..n)
        .map(|_| strategy.new_tree(&mut runner).unwrap().current())
        .collect()
}

#[test]
fn unsigned_multiplier_matches_its_verilog() {
    const A: usize = 19;
    const B: usize = 17;
    let edge = prop_oneof![Just(0u64), Just((1 << A) - 1), 0..(1u64 << A)];
    let edge_b = prop_oneof![Just(0u64), Just((1 << B) - 1), 0..(1u64 << B)];
    let mut v = vectors((edge, edge_b).prop_map(|(a, b)| vec![a, b]), 300);
    v.extend(std::iter::repeat_n(vec![0, 0], 3));
    let mut uut: UMul<A, B, { A + B }> = Default::default();
    uut.connect_all();
    let mut model = Vec::new();
    for x in &v {
        uut.a.next = x[0].into();
        uut.b.next = x[1].into();
        tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
        model.push(uval(uut.p.val()));
    }
    // The product of clock k's operands appears after clock k + LATENCY - 1.
    let lat = UMul::<A, B, { A + B }>::LATENCY as usize;
    for k in 0..v.len() - lat {
        assert_eq!(model[k + lat - 1], v[k][0] * v[k][1], "clock {k}");
    }
    let verilog = obb_rtl::emit::verilog(&mut UMul::<A, B, { A + B }>::default(), "umul").unwrap();
    let dir = verilator::scratch_dir("umul").unwrap();
    verilator::lint(&dir, &verilog, "umul").unwrap();
    let inputs = [Port::new("a", A), Port::new("b", B)];
    let out = verilator::simulate(
        &dir,
        &verilog,
        "umul",
        "clock",
        &inputs,
        &[Port::new("p", A + B)],
        &v,
    )
    .unwrap();
    // From the first product on, the Verilog equals the model clock for clock.
    for k in lat - 1..v.len() {
        assert_eq!(out[k][0], model[k], "clock {k}");
    }
}

#[test]
fn abs_twice_plus_one_matches_its_verilog() {
    const N: usize = 18;
    const M: usize = 19;
    let lo = -(1i64 << (N - 1));
    let hi = (1i64 << (N - 1)) - 1;
    let r = prop_oneof![Just(lo), Just(hi), Just(0i64), Just(-1i64), lo..=hi];
    let v: Vec<Vec<u64>> = vectors(r.prop_map(|r| vec![r as u64 & ((1 << N) - 1)]), 300);
    let mut uut: AbsTwice<N, M> = Default::default();
    uut.connect_all();
    let mut model = Vec::new();
    for x in &v {
        let r = ((x[0] << (64 - N)) as i64) >> (64 - N);
        uut.r.next = sbits(r);
        tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
        assert_eq!(uval(uut.t.val()), 2 * r.unsigned_abs() + 1, "r = {r}");
        model.push(uval(uut.t.val()));
    }
    let verilog = obb_rtl::emit::verilog(&mut AbsTwice::<N, M>::default(), "abs2").unwrap();
    let dir = verilator::scratch_dir("abs2").unwrap();
    verilator::lint(&dir, &verilog, "abs2").unwrap();
    let out = verilator::simulate(
        &dir,
        &verilog,
        "abs2",
        "clock",
        &[Port::new("r", N)],
        &[Port::new("t", M)],
        &v,
    )
    .unwrap();
    for (k, o) in out.iter().enumerate() {
        assert_eq!(o[0], model[k], "clock {k}");
    }
}

/// The table RAM: its model against a plain array (read first: a read sees the memory before the
/// same clock's write, on both ports; port A reads the write address while writing), and its
/// Verilog against its model, on random traffic that writes and reads the same addresses often.
#[test]
fn table_ram_matches_its_verilog() {
    const A: usize = 4;
    const D: usize = 9;
    let address = 0..(1u64 << A);
    let traffic = (
        prop_oneof![Just(0u64), Just(1u64)],
        address.clone(),
        0..(1u64 << D),
        address.clone(),
        address,
    )
        .prop_map(|(we, wa, wd, ra, rb)| vec![we, wa, wd, ra, rb]);
    let v = vectors(traffic, 400);
    let mut uut: TableRam<Bits<D>, A> = Default::default();
    uut.connect_all();
    let mut mem = [0u64; 1 << A];
    let mut model = Vec::new();
    for x in &v {
        uut.write_enable.next = x[0] == 1;
        uut.write_address.next = x[1].into();
        uut.write_data.next = x[2].into();
        uut.read_address_a.next = x[3].into();
        uut.read_address_b.next = x[4].into();
        tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
        let got = [uval(uut.read_data_a.val()), uval(uut.read_data_b.val())];
        let a = if x[0] == 1 { x[1] } else { x[3] };
        assert_eq!(got, [mem[a as usize], mem[x[4] as usize]], "model, {x:?}");
        if x[0] == 1 {
            mem[x[1] as usize] = x[2];
        }
        model.push(got.to_vec());
    }
    let verilog =
        obb_rtl::emit::verilog(&mut TableRam::<Bits<D>, A>::default(), "table_ram").unwrap();
    let dir = verilator::scratch_dir("table_ram").unwrap();
    verilator::lint(&dir, &verilog, "table_ram").unwrap();
    let inputs = [
        Port::new("write_enable", 1),
        Port::new("write_address", A),
        Port::new("write_data", D),
        Port::new("read_address_a", A),
        Port::new("read_address_b", A),
    ];
    let outputs = [Port::new("read_data_a", D), Port::new("read_data_b", D)];
    let out =
        verilator::simulate(&dir, &verilog, "table_ram", "clock", &inputs, &outputs, &v).unwrap();
    assert_eq!(out, model);
}

#[test]
fn model_latencies_are_the_hardware_latencies() {
    assert_eq!(
        obb_rtl::projection::LATENCY,
        obb_model::fixed::cycles::LAT_PROJECT
    );
}
