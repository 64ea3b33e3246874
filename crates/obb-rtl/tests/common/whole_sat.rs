//! The whole SAT (`Sat`, top module `sat`) driven one pair of boxes per clock: its input
//! vectors, the verdicts the model gives, and every axis' sides from the boxes' own products
//! (`sat_sides`); and its emitted Verilog run in Verilator with the sides probed.

use super::sat_sides::{self, Products, Stimulus};
use super::{ports, raw};
use obb_model::fixed::ModelFrame;
use obb_rtl::flow::verilator::{self, Port};
use obb_rtl::projection::{CENTER, HALF, MARGIN, ROT};
use obb_rtl::sat::LATENCY;
use obb_rtl::sat_back::R_B_DONE;
use obb_rtl::sat_front;
use std::path::Path;

/// The clock after a pair's inputs at which its sides reach the decision: the back end's
/// `R_B_DONE` clocks after the front's products.
pub const SIDES_AT: usize = sat_front::LATENCY as usize + R_B_DONE - 1;

/// Boxes i and j of `m` as an input vector.
fn input(m: &ModelFrame, i: usize, j: usize) -> Vec<u64> {
    let offset = 1i64 << (m.cfg.center_bits - 1);
    let mut v = vec![1];
    for k in [i, j] {
        let b = &m.obbs[k];
        v.extend(b.center.map(|c| (c + offset) as u64));
        v.extend(b.half.map(|h| h as u64));
        v.extend((0..9).map(|x| raw(b.axes[x / 3][x % 3], ROT)));
        v.push(m.projected[k].margin as u64);
    }
    v
}

/// The first stage's products of boxes i and j, from their quantized centers and axes.
fn products(m: &ModelFrame, i: usize, j: usize) -> Products {
    let (a, b) = (&m.obbs[i], &m.obbs[j]);
    let d: [i64; 3] = std::array::from_fn(|x| b.center[x] - a.center[x]);
    let dot = |p: &[i64; 3], q: &[i64; 3]| (0..3).map(|x| p[x] * q[x]).sum::<i64>();
    Products {
        t: std::array::from_fn(|k| dot(&a.axes[k], &d)),
        u: std::array::from_fn(|k| dot(&b.axes[k], &d)),
        r: std::array::from_fn(|k| std::array::from_fn(|l| dot(&a.axes[k], &b.axes[l]))),
        half_a: a.half,
        half_b: b.half,
    }
}

/// `pairs` of `m` into the whole SAT, one a clock (vectors: valid, then for A and for B:
/// centers (3), halves (3), axes (9), margin).
pub fn stimulus(m: &ModelFrame, pairs: &[(usize, usize)]) -> Stimulus {
    let vectors = pairs.iter().map(|&(i, j)| input(m, i, j)).collect();
    let first_stage = pairs.iter().map(|&(i, j)| products(m, i, j));
    Stimulus::new(m, pairs, LATENCY, vectors, first_stage)
}

/// `verilog` (the whole SAT's) in Verilator: the verdicts and the probed sides.
pub fn in_verilator(verilog: &str, vectors: &[Vec<u64>]) -> Vec<Vec<u64>> {
    let dir = verilator::scratch_dir("sat").unwrap();
    try_in_verilator(verilog, vectors, &dir, Some(&super::cache())).unwrap()
}

/// The same, linted and built in `dir` or taken from `cache` (the build is the lint); the
/// first line of what failed.
pub fn try_in_verilator(
    verilog: &str,
    vectors: &[Vec<u64>],
    dir: &Path,
    cache: Option<&Path>,
) -> Result<Vec<Vec<u64>>, String> {
    let mut inputs = vec![Port::new("valid_in", 1)];
    for side in ["a", "b"] {
        inputs.extend(ports(&format!("center_{side}"), 3, CENTER));
        inputs.extend(ports(&format!("half_{side}"), 3, HALF));
        inputs.extend(ports(&format!("axes_{side}"), 9, ROT));
        inputs.push(Port::new(format!("margin_{side}"), MARGIN));
    }
    let mut outputs = vec![Port::new("valid_out", 1), Port::new("hit", 1)];
    outputs.extend(sat_sides::probes("dut.back.decide"));
    verilator::simulate(
        verilator::Simulator::Verilator,
        dir,
        cache,
        verilog,
        "sat",
        "clock",
        &inputs,
        &outputs,
        vectors,
    )
    .map_err(|e| format!("{e:#}").lines().next().unwrap_or("").to_string())
}
