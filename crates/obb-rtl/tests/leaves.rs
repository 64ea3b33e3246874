//! Each arithmetic leaf, delay line, memory and the pair FIFO: its Rust model (the rust-hdl
//! simulation) against its own Verilog in Verilator, clock by clock, on random operands
//! including the extremes; and the latencies the model's cycle count assumes. (The SAT back
//! end's leaves: `sat_leaves.rs`.)

use crate::common;

use common::in_verilator;
use obb_rtl::bin_table::BinTable;
use obb_rtl::dist_ram::DistRam;
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::{sbits, sval, uval, AbsTwice, UMul};
use obb_rtl::pair_fifo::{self, PairFifo};
use obb_rtl::pipe::Pipe;
use obb_rtl::table_ram::TableRam;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use rust_hdl::prelude::*;
use std::collections::VecDeque;

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

/// A memory's write port, the first three fields of `memory_traffic`'s vectors.
fn write_ports(address_bits: usize, data_bits: usize) -> Vec<Port> {
    vec![
        Port::new("write_enable", 1),
        Port::new("write_address", address_bits),
        Port::new("write_data", data_bits),
    ]
}

/// 400 clocks of memory traffic, [write enable, write address, write data, read addresses..]
/// on `address_bits`-bit addresses: small, so that reads meet writes often.
fn memory_traffic(address_bits: usize, data_bits: usize, reads: usize) -> Vec<Vec<u64>> {
    let address = 0..(1u64 << address_bits);
    let traffic = (
        prop_oneof![Just(0u64), Just(1u64)],
        address.clone(),
        0..(1u64 << data_bits),
        proptest::collection::vec(address, reads),
    )
        .prop_map(|(we, wa, wd, ra)| [vec![we, wa, wd], ra].concat());
    vectors(traffic, 400)
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
    let out = in_verilator(
        &mut UMul::<A, B, { A + B }>::default(),
        "umul",
        &[Port::new("a", A), Port::new("b", B)],
        &[Port::new("p", A + B)],
        &v,
    );
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
    let out = in_verilator(
        &mut AbsTwice::<N, M>::default(),
        "abs2",
        &[Port::new("r", N)],
        &[Port::new("t", M)],
        &v,
    );
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
    let v = memory_traffic(A, D, 2);
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
    let mut inputs = write_ports(A, D);
    inputs.push(Port::new("read_address_a", A));
    inputs.push(Port::new("read_address_b", A));
    let outputs = [Port::new("read_data_a", D), Port::new("read_data_b", D)];
    let out = in_verilator(
        &mut TableRam::<Bits<D>, A>::default(),
        "table_ram",
        &inputs,
        &outputs,
        &v,
    );
    assert_eq!(out, model);
}

/// A delay line gives its input `D` clocks later, in rust-hdl and in Verilog, at one clock
/// (nothing between its input and its only register) and at a length past `derive(Default)`'s
/// 32; signed values come out with their sign.
#[test]
fn pipe_delays_by_its_length() {
    fn check<T: Synth, const D: usize>(
        bits: usize,
        value: impl Fn(u64) -> T,
        read: impl Fn(T) -> u64,
    ) {
        let v = vectors(proptest::collection::vec(0..(1u64 << bits), 1), 120);
        let mut uut: Pipe<T, D> = Default::default();
        uut.connect_all();
        let mut got = Vec::new();
        for x in &v {
            uut.d.next = value(x[0]);
            tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
            got.push(vec![read(uut.q.val())]);
        }
        // Before the first value is through, the registers' reset value, 0.
        let want: Vec<Vec<u64>> = (0..v.len())
            .map(|k| vec![if k + 1 >= D { v[k + 1 - D][0] } else { 0 }])
            .collect();
        assert_eq!(got, want, "rust-hdl, D = {D}");
        let name = format!("pipe_{D}");
        let out = in_verilator(
            &mut Pipe::<T, D>::default(),
            &name,
            &[Port::new("d", bits)],
            &[Port::new("q", bits)],
            &v,
        );
        assert_eq!(out, want, "Verilog, D = {D}");
    }
    check::<Bit, 1>(1, |x| x == 1, u64::from);
    check::<Bits<7>, 5>(7, |x| x.into(), uval);
    // Signed: in by sign extension of the raw bits, out as raw bits again.
    check::<Signed<9>, 40>(
        9,
        |x| sbits::<9>(((x << 55) as i64) >> 55),
        |s| sval(s) as u64 & 0x1ff,
    );
}

/// The distributed RAM, and its flip-flop form: its model against a plain array (the read port
/// shows the memory at once, a write of the edge just past included), and its Verilog against
/// its model.
#[test]
fn dist_ram_matches_its_verilog() {
    const A: usize = 4;
    const D: usize = 9;
    let make: [fn() -> DistRam<Bits<D>, A>; 2] = [DistRam::default, DistRam::registers];
    for (make, name) in make.into_iter().zip(["dist_ram", "dist_ram_registers"]) {
        let v = memory_traffic(A, D, 1);
        let mut uut = make();
        uut.connect_all();
        let mut mem = [0u64; 1 << A];
        let mut model = Vec::new();
        for x in &v {
            uut.write_enable.next = x[0] == 1;
            uut.write_address.next = x[1].into();
            uut.write_data.next = x[2].into();
            uut.read_address.next = x[3].into();
            tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
            if x[0] == 1 {
                mem[x[1] as usize] = x[2];
            }
            let got = uval(uut.read_data.val());
            assert_eq!(got, mem[x[3] as usize], "{name} model, {x:?}");
            model.push(vec![got]);
        }
        let mut inputs = write_ports(A, D);
        inputs.push(Port::new("read_address", A));
        let out = in_verilator(&mut make(), name, &inputs, &[Port::new("read_data", D)], &v);
        assert_eq!(out, model, "{name}: Verilog against its model");
    }
}

/// The pair FIFO's specification, clock by clock: entries stored in order; the output register
/// loads the oldest when it is empty or taken; `almost_full` counts the stored entries; a
/// write with `depth` entries stored and none leaving is lost and sets `overflow` until `clear`
/// (a write on the clock of `clear` wins).
struct FifoSpec {
    stored: VecDeque<u64>,
    out: Option<u64>,
    stall_at: usize,
    depth: usize,
    overflow: bool,
}

impl FifoSpec {
    /// One clock edge with inputs `write`, `data`, `ready`, `clear`; returns the outputs after
    /// it: valid, data_out, empty, almost_full, overflow.
    fn clock(&mut self, write: bool, data: u64, ready: bool, clear: bool) -> Vec<u64> {
        let full = self.stored.len() == self.depth;
        let leaves = !self.stored.is_empty() && (self.out.is_none() || ready);
        if leaves {
            self.out = self.stored.pop_front();
        } else if ready {
            self.out = None;
        }
        self.overflow &= !clear;
        if write && full && !leaves {
            self.overflow = true;
        } else if write {
            self.stored.push_back(data);
        }
        vec![
            u64::from(self.out.is_some()),
            self.out.unwrap_or(0),
            u64::from(self.stored.is_empty() && self.out.is_none()),
            u64::from(self.stored.len() >= self.stall_at),
            u64::from(self.overflow),
        ]
    }
}

/// The pair FIFO against its specification, in rust-hdl and in Verilator: phases that fill it
/// to its depth with the receiver mostly away, stream with the receiver mostly ready, and
/// drain it; data_out is compared only while valid (it holds the last entry otherwise, as the
/// specification does not say). Every entry written leaves once, in order, and a steady stream
/// leaves one per clock. Then a phase writes past the depth with the receiver away: `overflow`
/// rises and stays up until `clear` (from the lost write on, only `overflow` is compared).
#[test]
fn pair_fifo_matches_its_specification_and_its_verilog() {
    const W: usize = 12;
    let stall_at = 32;
    let depth = pair_fifo::DEPTH as usize;
    // (write, data, ready) per clock; no write into a full FIFO (the core never does one).
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut spec = FifoSpec {
        stored: VecDeque::new(),
        out: None,
        stall_at,
        depth,
        overflow: false,
    };
    let mut v = Vec::new();
    let mut expected = Vec::new();
    for (clocks, write_in_4, ready_in_4) in [(300, 3, 1), (300, 2, 3), (150, 0, 4), (100, 4, 4)] {
        for _ in 0..clocks {
            let (w, d, r) = (0..4u32, 0..(1u64 << W), 0..4u32)
                .new_tree(&mut runner)
                .unwrap()
                .current();
            let write = w < write_in_4 && spec.stored.len() < depth;
            let ready = r < ready_in_4;
            v.push(vec![u64::from(write), d, u64::from(ready), 0]);
            expected.push(spec.clock(write, d, ready, false));
        }
    }
    // The overflow phase: writes every clock, the receiver away, then idle, a clear, idle.
    let whole = v.len();
    for k in 0..depth + 12 {
        let (write, clear) = (k < depth + 4, k == depth + 8);
        v.push(vec![u64::from(write), k as u64, 0, u64::from(clear)]);
        expected.push(spec.clock(write, k as u64, false, clear));
    }
    let lost = expected.iter().position(|o| o[4] == 1).unwrap();
    assert!(lost > whole && expected.last().unwrap()[4] == 0);
    assert!(
        expected.iter().any(|o| o[3] == 1),
        "the traffic reaches the stall threshold"
    );
    let mut uut = PairFifo::<W>::new(stall_at as u64);
    uut.connect_all();
    let mut got = Vec::new();
    for x in &v {
        uut.write.next = x[0] == 1;
        uut.data_in.next = x[1].into();
        uut.ready.next = x[2] == 1;
        uut.clear.next = x[3] == 1;
        tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
        got.push(vec![
            u64::from(uut.valid.val()),
            uval(uut.data_out.val()),
            u64::from(uut.empty.val()),
            u64::from(uut.almost_full.val()),
            u64::from(uut.overflow.val()),
        ]);
    }
    let masked = |o: &[Vec<u64>]| -> Vec<Vec<u64>> {
        o.iter()
            .enumerate()
            .map(|(k, o)| match k < lost {
                true => vec![o[0], o[1] * o[0], o[2], o[3], o[4]],
                false => vec![o[4]],
            })
            .collect()
    };
    assert_eq!(masked(&got), masked(&expected), "rust-hdl");
    // Order and loss: what is taken (valid and ready on a clock) is what was written.
    let written: Vec<u64> = v[..whole]
        .iter()
        .filter(|x| x[0] == 1)
        .map(|x| x[1])
        .collect();
    let mut taken = Vec::new();
    for (k, x) in v[..whole].iter().enumerate().skip(1) {
        if x[2] == 1 && got[k - 1][0] == 1 {
            taken.push(got[k - 1][1]);
        }
    }
    assert_eq!(taken[..], written[..taken.len()]);
    assert!(taken.len() + depth + 1 >= written.len());
    // A steady stream: a write every clock into an empty FIFO, the receiver always ready:
    // each entry is on the output two clocks after its write clock, one per clock.
    let mut uut = PairFifo::<W>::new(stall_at as u64);
    uut.connect_all();
    for k in 0..20u64 {
        uut.write.next = k < 10;
        uut.data_in.next = (100 + k).into();
        uut.ready.next = true;
        tick(&mut uut, |u, c| u.clock.next = Clock::from(c));
        let want = (2..12).contains(&(k + 1)).then_some(100 + k - 1);
        let have = uut.valid.val().then(|| uval(uut.data_out.val()));
        assert_eq!(have, want, "clock {k}");
    }
    let inputs = [
        Port::new("write", 1),
        Port::new("data_in", W),
        Port::new("ready", 1),
        Port::new("clear", 1),
    ];
    let outputs = [
        Port::new("valid", 1),
        Port::new("data_out", W),
        Port::new("empty", 1),
        Port::new("almost_full", 1),
        Port::new("overflow", 1),
    ];
    let out = in_verilator(
        &mut PairFifo::<W>::new(stall_at as u64),
        "pair_fifo",
        &inputs,
        &outputs,
        &v,
    );
    assert_eq!(out, got, "Verilator against rust-hdl");
}

/// The latencies the model's cycle count assumes are the blocks' own.
#[test]
fn model_latencies_are_the_hardware_latencies() {
    assert_eq!(
        obb_rtl::projection::LATENCY,
        obb_model::fixed::cycles::LAT_PROJECT
    );
    assert_eq!(
        (obb_rtl::radix::PASS, obb_rtl::radix::START),
        (
            obb_model::fixed::cycles::LAT_SORT_PASS,
            obb_model::fixed::cycles::LAT_SORT_START
        )
    );
}

/// One clock of the bin table's inputs: clear, count_valid, count_bin, step, take_valid,
/// take_bin.
fn bin_table_clock(u: &mut BinTable<BT_C>, x: &[u64]) -> u64 {
    u.clear.next = x[0] == 1;
    u.count_valid.next = x[1] == 1;
    u.count_bin.next = x[2].into();
    u.step.next = x[3] == 1;
    u.take_valid.next = x[4] == 1;
    u.take_bin.next = x[5].into();
    tick(u, |u, c| u.clock.next = Clock::from(c));
    uval(u.take_ptr.val())
}

const BT_C: usize = 9;

/// The bin table against what a radix pass needs of it, on rounds of count, prefix steps and
/// takes: each take of digit x gets the number of counted digits below x plus the number of
/// earlier takes of x, `TAKE_LATENCY` clocks later. The rounds run without a clear between them
/// (the steps must leave the counts at zero), and one round is cut short by a clear. Then its
/// Verilog against its model, clock by clock, on random traffic, for one group of bins (3-bit
/// digits) and for 8 groups of 16 (7-bit digits).
#[test]
fn bin_table_matches_a_radix_pass_and_its_verilog() {
    use obb_rtl::bin_table::{COUNT_LATENCY, TAKE_LATENCY};
    for d in [3u32, 7] {
        let bins = 1u64 << d;
        let mut runner = proptest::test_runner::TestRunner::deterministic();
        let mut u = BinTable::<BT_C>::new(d);
        u.connect_all();
        let idle = [0u64; 6];
        let mut clocks: Vec<Vec<u64>> = Vec::new();
        let mut run = |u: &mut BinTable<BT_C>, x: Vec<u64>| {
            clocks.push(x.clone());
            bin_table_clock(u, &x)
        };
        for round in 0..4 {
            let xs =
                proptest::collection::vec(prop_oneof![0..bins, Just(bins - 1), Just(0)], 0..60)
                    .new_tree(&mut runner)
                    .unwrap()
                    .current();
            if round == 2 {
                // Counts of a frame cut short, then cleared.
                for &x in &xs {
                    run(&mut u, vec![0, 1, x, 0, 0, 0]);
                }
                run(&mut u, vec![1, 0, 0, 0, 0, 0]);
            }
            for &x in &xs {
                run(&mut u, vec![0, 1, x, 0, 0, 0]);
            }
            for _ in 0..COUNT_LATENCY {
                run(&mut u, idle.to_vec());
            }
            for _ in 0..bins {
                run(&mut u, vec![0, 0, 0, 1, 0, 0]);
            }
            let mut got = Vec::new();
            for k in 0..xs.len() as u64 + TAKE_LATENCY {
                let take = xs
                    .get(k as usize)
                    .map_or(idle.to_vec(), |&x| vec![0, 0, 0, 0, 1, x]);
                let p = run(&mut u, take);
                if k + 1 >= TAKE_LATENCY {
                    got.push(p);
                }
            }
            let want: Vec<u64> = xs
                .iter()
                .enumerate()
                .map(|(k, &x)| {
                    (xs.iter().filter(|&&y| y < x).count()
                        + xs[..k].iter().filter(|&&y| y == x).count()) as u64
                })
                .collect();
            assert_eq!(got[..xs.len()], want[..], "{d}-bit digits, round {round}");
        }
        // Random traffic, every input at once at times.
        let bit = prop_oneof![3 => Just(0u64), 1 => Just(1u64)];
        let traffic = (
            bit.clone(),
            bit.clone(),
            0..256u64,
            bit.clone(),
            bit,
            0..256u64,
        )
            .prop_map(|(a, b, c, s, e, f)| vec![a, b, c, s, e, f]);
        clocks.extend(vectors(traffic, 300));
        let mut u = BinTable::<BT_C>::new(d);
        u.connect_all();
        let model: Vec<Vec<u64>> = clocks
            .iter()
            .map(|x| vec![bin_table_clock(&mut u, x)])
            .collect();
        let inputs = [
            Port::new("clear", 1),
            Port::new("count_valid", 1),
            Port::new("count_bin", 8),
            Port::new("step", 1),
            Port::new("take_valid", 1),
            Port::new("take_bin", 8),
        ];
        let out = in_verilator(
            &mut BinTable::<BT_C>::new(d),
            "bin_table",
            &inputs,
            &[Port::new("take_ptr", BT_C)],
            &clocks,
        );
        assert_eq!(out, model, "{d}-bit digits");
    }
}
