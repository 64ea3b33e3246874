//! Driving a block clock by clock: in rust-hdl's simulation and, as emitted Verilog, in
//! Verilator, on the same packed vectors, and comparing both with the model's expected outputs.

pub mod sat_sides;
pub mod scenes;
pub mod whole_sat;

use obb_model::fixed::broad;
use obb_model::fixed::{BroadPhase, ModelFrame};
use obb_model::GroupMask;
use obb_rtl::flow::verilator::{self, Port};
use rust_hdl::prelude::*;

/// Sign-extends the low `bits` of `v`.
pub fn signed(v: u64, bits: usize) -> i64 {
    ((v << (64 - bits)) as i64) >> (64 - bits)
}

/// `floor(x / 2^s)`, `ceil(x / 2^s)`, and `x / 2^s` to the nearest integer with ties up, by
/// Euclidean division (the leaves shift).
pub fn floor_div(x: i64, s: u32) -> i64 {
    x.div_euclid(1 << s)
}
pub fn ceil_div(x: i64, s: u32) -> i64 {
    -(-x).div_euclid(1 << s)
}
pub fn nearest(x: i64, s: u32) -> i64 {
    floor_div(2 * x + (1 << s), s + 1)
}

/// The low `bits` of a signed value, as a vector entry.
pub fn raw(v: i64, bits: usize) -> u64 {
    if bits == 64 {
        v as u64
    } else {
        v as u64 & ((1 << bits) - 1)
    }
}

/// Runs `uut` one vector per clock in rust-hdl: `apply` sets the inputs, a rising edge, then
/// `read` takes the outputs.
pub fn run_rust_hdl<B: Block>(
    uut: &mut B,
    vectors: &[Vec<u64>],
    apply: impl Fn(&mut B, &[u64]),
    clock: impl Fn(&mut B, bool),
    read: impl Fn(&B) -> Vec<u64>,
) -> Vec<Vec<u64>> {
    uut.connect_all();
    vectors
        .iter()
        .map(|v| {
            apply(uut, v);
            clock(uut, false);
            assert!(simulate(uut, 1000), "settles");
            clock(uut, true);
            assert!(simulate(uut, 1000), "settles");
            read(uut)
        })
        .collect()
}

/// Lints and runs `verilog` in Verilator on the vectors (its build is the lint,
/// `verilator::Warnings::Fatal`).
pub fn run_verilator(
    verilog: &str,
    top: &str,
    inputs: &[Port],
    outputs: &[Port],
    vectors: &[Vec<u64>],
) -> Vec<Vec<u64>> {
    let dir = verilator::scratch_dir(top).unwrap();
    let cache = cache();
    verilator::simulate(
        verilator::Simulator::Verilator,
        &dir,
        Some(&cache),
        verilog,
        top,
        "clock",
        inputs,
        outputs,
        vectors,
    )
    .unwrap()
}

/// The cache of Verilator and yosys builds, below cargo's scratch directory: a build is reused
/// by the tests (and the runs) that simulate the same Verilog.
pub fn cache() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cosim-cache")
}

/// `block`'s Verilog, top module `name`, linted and run in Verilator on `vectors` (one per
/// clock): the outputs after each rising edge.
pub fn in_verilator<B: Block>(
    block: &mut B,
    name: &str,
    inputs: &[Port],
    outputs: &[Port],
    vectors: &[Vec<u64>],
) -> Vec<Vec<u64>> {
    let verilog = obb_rtl::flow::emit::verilog(block, name).unwrap();
    run_verilator(&verilog, name, inputs, outputs, vectors)
}

/// The first clock where the model (`want`) or the block (`got`) has its first output (valid)
/// high and the two differ in any output.
pub fn disagreement(got: &[Vec<u64>], want: &[Vec<u64>]) -> Option<usize> {
    got.iter()
        .zip(want)
        .position(|(g, w)| (g[0] == 1 || w[0] == 1) && g != w)
}

/// Every clock where the model (`want`) or the block (`got`) has its first output (valid)
/// high must agree on every output; and some clock must be valid.
pub fn check(got: &[Vec<u64>], want: &[Vec<u64>], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: clocks");
    if let Some(k) = disagreement(got, want) {
        assert_eq!(got[k], want[k], "{what}: clock {k}");
    }
    assert!(want.iter().any(|w| w[0] == 1), "{what}: nothing valid");
}

/// Ports named `name$0..n`.
pub fn ports(name: &str, n: usize, bits: usize) -> Vec<Port> {
    (0..n)
        .map(|i| Port::new(format!("{name}${i}"), bits))
        .collect()
}

/// Pairs the brute-force broad phase sends to the SAT (keys overlap), ordered i < j: up to
/// `most` the SAT reports and as many it separates, interleaved, then pairs far apart.
pub fn pairs(m: &ModelFrame, most: usize) -> Vec<(usize, usize)> {
    let (mut hits, mut misses) = (Vec::new(), Vec::new());
    broad::run(m, BroadPhase::Brute, &GroupMask::All, |i, j| {
        let p = (i.min(j), i.max(j));
        if m.sat(p.0, p.1) {
            hits.push(p);
        } else {
            misses.push(p);
        }
    });
    let mut out: Vec<_> = hits
        .iter()
        .zip(&misses)
        .take(most)
        .flat_map(|(h, s)| [*h, *s])
        .collect();
    let n = m.obbs.len();
    out.extend((0..40).map(|k| (k, n - 1 - k)));
    out
}
