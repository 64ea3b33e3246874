//! The SAT after its first stage, clock by clock against the model's 15-axis test, in rust-hdl
//! and in Verilator: one pair per clock, the verdict `LATENCY` clocks later. The pairs are those
//! a broad phase sends to the SAT on a surgical and a dense scene (hits and near misses), under
//! two configurations.

mod common;

use common::{check, pairs, ports, raw, run_rust_hdl, run_verilator, signed};
use obb_model::fixed::sat::{sat_products, MINOR_PAIRS};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::generate::{surgical, uniform};
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::sbits;
use obb_rtl::sat_back::{SatBack, HALF_S, LATENCY, PAIR_MARGIN};
use obb_rtl::sat_front::{RR, TU};
use rust_hdl::prelude::*;

/// Inputs: valid, t (3), u (3), R (9), halves of A (3) and B (3), the pair margin.
fn input(m: &ModelFrame, i: usize, j: usize) -> Vec<u64> {
    let (a, b) = (&m.obbs[i], &m.obbs[j]);
    let p = sat_products(a, b);
    let mut v = vec![1];
    v.extend(p.t.map(|x| raw(x, TU)));
    v.extend(p.u.map(|x| raw(x, TU)));
    v.extend((0..9).map(|k| raw(p.r[k / 3][k % 3], RR)));
    v.extend(a.half.map(|h| h as u64));
    v.extend(b.half.map(|h| h as u64));
    v.push((m.projected[i].margin + m.projected[j].margin) as u64);
    v
}

fn run(m: &ModelFrame, pairs: &[(usize, usize)]) {
    let cfg = &m.cfg;
    let mut vectors: Vec<Vec<u64>> = pairs.iter().map(|&(i, j)| input(m, i, j)).collect();
    let width = vectors[0].len();
    vectors.extend(std::iter::repeat_n(vec![0; width], LATENCY as usize + 1));
    let mut want = vec![vec![0, 0]; vectors.len()];
    for (k, &(i, j)) in pairs.iter().enumerate() {
        want[k + LATENCY as usize - 1] = vec![1, u64::from(m.sat(i, j))];
    }
    let hits = want.iter().filter(|w| w[0] == 1 && w[1] == 1).count();
    assert!(
        hits > 0 && hits < pairs.len(),
        "both verdicts occur: {hits} of {}",
        pairs.len()
    );

    let apply = |u: &mut SatBack, v: &[u64]| {
        u.valid_in.next = v[0] == 1;
        for i in 0..3 {
            u.t[i].next = sbits(signed(v[1 + i], TU));
            u.u[i].next = sbits(signed(v[4 + i], TU));
            u.half_a[i].next = sbits(v[16 + i] as i64);
            u.half_b[i].next = sbits(v[19 + i] as i64);
        }
        for k in 0..9 {
            u.r[k].next = sbits(signed(v[7 + k], RR));
        }
        u.pair_margin.next = v[22].into();
    };
    let read = |u: &SatBack| vec![u64::from(u.valid_out.val()), u64::from(u.hit.val())];
    let clock = |u: &mut SatBack, c: bool| u.clock.next = Clock::from(c);
    let got = run_rust_hdl(&mut SatBack::new(cfg), &vectors, apply, clock, read);
    check(&got, &want, "rust-hdl");

    let verilog = obb_rtl::flow::emit::verilog(&mut SatBack::new(cfg), "sat_back").unwrap();
    let mut inputs = vec![Port::new("valid_in", 1)];
    inputs.extend(ports("t", 3, TU));
    inputs.extend(ports("u", 3, TU));
    inputs.extend(ports("r", 9, RR));
    inputs.extend(ports("half_a", 3, HALF_S));
    inputs.extend(ports("half_b", 3, HALF_S));
    inputs.push(Port::new("pair_margin", PAIR_MARGIN));
    let outputs = [Port::new("valid_out", 1), Port::new("hit", 1)];
    let got = run_verilator(&verilog, "sat_back", &inputs, &outputs, &vectors);
    check(&got, &want, "verilator");
}

#[test]
fn sat_back_matches_the_model_in_rust_hdl_and_verilator() {
    // The wiring of the minors follows the model's order of the pairs {j, l}.
    assert_eq!(MINOR_PAIRS, [(0, 1), (0, 2), (1, 2)]);
    let scene = surgical(600, 5).unwrap();
    let cfg = HwConfig::default().fitted(&scene);
    let m = ModelFrame::new(&scene, &cfg).unwrap();
    run(&m, &pairs(&m, 400));
    let dense = uniform(120, 8, 1.5).unwrap();
    let narrow = HwConfig {
        center_bits: 16,
        key_bits: 16,
        rot_bits: 12,
        half_bits: 15,
        sat_bits: 24,
        ..HwConfig::default()
    }
    .fitted(&dense);
    let m = ModelFrame::new(&dense, &narrow).unwrap();
    run(&m, &pairs(&m, 400));
}
