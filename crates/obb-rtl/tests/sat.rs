//! The whole SAT pipeline, clock by clock against the model's `collide` (via `ModelFrame::sat`),
//! in rust-hdl and in Verilator: one pair of boxes per clock, the verdict `LATENCY` clocks later;
//! and every axis' two sides where the decision reads them (`common::sat_sides`), against a
//! reference computed here from the boxes.

mod common;

use common::sat_sides::{self, Products};
use common::{check, pairs, ports, raw, run_rust_hdl, run_verilator, signed};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::generate::{surgical, uniform};
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::sbits;
use obb_rtl::projection::{CENTER, HALF, MARGIN, ROT};
use obb_rtl::sat::{Sat, LATENCY};
use obb_rtl::sat_back::R_B_DONE;
use obb_rtl::sat_front;
use rust_hdl::prelude::*;

/// Inputs: valid, then for A and for B: centers (3), halves (3), axes (9), margin.
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

fn run(m: &ModelFrame, pairs: &[(usize, usize)]) {
    let f = m.cfg.frac_bits();
    let want_sides: Vec<Vec<u64>> = pairs
        .iter()
        .map(|&(i, j)| sat_sides::sides(&products(m, i, j), f))
        .collect();
    // The sides reach the decision the back end's `R_B_DONE` clocks after the front's products.
    let at = (sat_front::LATENCY as usize) + R_B_DONE - 1;
    let mut vectors: Vec<Vec<u64>> = pairs.iter().map(|&(i, j)| input(m, i, j)).collect();
    vectors.extend(std::iter::repeat_n(vec![0; 33], LATENCY as usize + 1));
    let mut want = vec![vec![0, 0]; vectors.len()];
    for (k, &(i, j)) in pairs.iter().enumerate() {
        want[k + LATENCY as usize - 1] = vec![1, u64::from(m.sat(i, j))];
    }
    let apply = |u: &mut Sat, v: &[u64]| {
        u.valid_in.next = v[0] == 1;
        for x in 0..3 {
            u.center_a[x].next = v[1 + x].into();
            u.half_a[x].next = v[4 + x].into();
            u.center_b[x].next = v[17 + x].into();
            u.half_b[x].next = v[20 + x].into();
        }
        for x in 0..9 {
            u.axes_a[x].next = sbits(signed(v[7 + x], ROT));
            u.axes_b[x].next = sbits(signed(v[23 + x], ROT));
        }
        u.margin_a.next = v[16].into();
        u.margin_b.next = v[32].into();
    };
    let read = |u: &Sat| {
        let mut row = vec![u64::from(u.valid_out.val()), u64::from(u.hit.val())];
        row.extend(sat_sides::read(&u.back.decide));
        row
    };
    let clock = |u: &mut Sat, c: bool| u.clock.next = Clock::from(c);
    let got = run_rust_hdl(&mut Sat::new(&m.cfg), &vectors, apply, clock, read);
    check(&sat_sides::verdicts(&got), &want, "rust-hdl");
    assert_eq!(
        sat_sides::differ(&got, &want_sides, at, 2),
        None,
        "rust-hdl"
    );

    let verilog = obb_rtl::flow::emit::verilog(&mut Sat::new(&m.cfg), "sat").unwrap();
    let mut inputs = vec![Port::new("valid_in", 1)];
    for side in ["a", "b"] {
        inputs.extend(ports(&format!("center_{side}"), 3, CENTER));
        inputs.extend(ports(&format!("half_{side}"), 3, HALF));
        inputs.extend(ports(&format!("axes_{side}"), 9, ROT));
        inputs.push(Port::new(format!("margin_{side}"), MARGIN));
    }
    let mut outputs = vec![Port::new("valid_out", 1), Port::new("hit", 1)];
    outputs.extend(sat_sides::probes("dut.back.decide"));
    let got = run_verilator(&verilog, "sat", &inputs, &outputs, &vectors);
    check(&sat_sides::verdicts(&got), &want, "verilator");
    assert_eq!(
        sat_sides::differ(&got, &want_sides, at, 2),
        None,
        "verilator"
    );
}

#[test]
fn sat_matches_the_model_in_rust_hdl_and_verilator() {
    assert_eq!(LATENCY, obb_model::fixed::cycles::LAT_SAT);
    let scene = surgical(600, 9).unwrap();
    let cfg = HwConfig::default().fitted(&scene);
    let m = ModelFrame::new(&scene, &cfg).unwrap();
    run(&m, &pairs(&m, 300));
    let dense = uniform(150, 2, 1.5).unwrap();
    let coarse = HwConfig {
        center_bits: 14,
        key_bits: 10,
        rot_bits: 8,
        half_bits: 13,
        sat_bits: 20,
        ..HwConfig::default()
    }
    .fitted(&dense);
    let m = ModelFrame::new(&dense, &coarse).unwrap();
    run(&m, &pairs(&m, 300));
}
