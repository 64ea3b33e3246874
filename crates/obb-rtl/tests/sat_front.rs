//! The SAT's first stage, clock by clock against `obb_model::fixed::sat::sat_products`, in
//! rust-hdl and in Verilator: one pair per clock, the exact t, u and R `LATENCY` clocks later.

use crate::common;

use common::{check, ports, raw, run_rust_hdl, run_verilator, signed};
use obb_model::fixed::sat::sat_products;
use obb_model::fixed::{quantize, HwConfig, QObb};
use obb_model::generate::{surgical, uniform};
use obb_model::{Obb, Scene};
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::{sbits, sval};
use obb_rtl::projection::{CENTER, ROT};
use obb_rtl::sat_front::{SatFront, LATENCY, RR, TU};
use rust_hdl::prelude::*;

fn input(a: &QObb, b: &QObb, cfg: &HwConfig) -> Vec<u64> {
    let offset = 1i64 << (cfg.center_bits - 1);
    let mut v = vec![1];
    v.extend(a.center.map(|c| (c + offset) as u64));
    v.extend(b.center.map(|c| (c + offset) as u64));
    v.extend((0..9).map(|i| raw(a.axes[i / 3][i % 3], ROT)));
    v.extend((0..9).map(|i| raw(b.axes[i / 3][i % 3], ROT)));
    v
}

fn expected(pairs: &[(QObb, QObb)], len: usize) -> Vec<Vec<u64>> {
    let mut out = vec![vec![0; 16]; len];
    for (k, (a, b)) in pairs.iter().enumerate() {
        let p = sat_products(a, b);
        let mut o = vec![1];
        o.extend(p.t.map(|v| raw(v, TU)));
        o.extend(p.u.map(|v| raw(v, TU)));
        o.extend((0..9).map(|i| raw(p.r[i / 3][i % 3], RR)));
        out[k + LATENCY as usize - 1] = o;
    }
    out
}

/// Pairs from a surgical and a uniform scene, and two boxes at opposite corners of the widest
/// range (the largest T).
fn pairs() -> (Vec<(QObb, QObb)>, HwConfig) {
    let cfg = HwConfig {
        center_bits: 23,
        key_bits: 23,
        ..HwConfig::default()
    };
    let mut scene: Scene = surgical(160, 3).unwrap();
    scene.obbs.extend(uniform(80, 4, 1.0).unwrap().obbs);
    scene
        .obbs
        .push(Obb::aligned([-400.0, -400.0, -400.0], [1.0; 3], 0));
    scene
        .obbs
        .push(Obb::aligned([400.0, 400.0, 400.0], [1.0; 3], 0));
    let cfg = cfg.fitted(&Scene {
        obbs: vec![Obb::aligned([0.0; 3], [500.0; 3], 0)],
    });
    let q = quantize(&scene, &cfg).unwrap();
    let n = q.len();
    let mut pairs: Vec<(QObb, QObb)> = (0..n).map(|i| (q[i], q[(i * 7 + 3) % n])).collect();
    pairs.push((q[n - 2], q[n - 1]));
    pairs.push((q[n - 1], q[n - 2]));
    (pairs, cfg)
}

#[test]
fn sat_front_matches_the_model_in_rust_hdl_and_verilator() {
    let (pairs, cfg) = pairs();
    let mut vectors: Vec<Vec<u64>> = pairs.iter().map(|(a, b)| input(a, b, &cfg)).collect();
    vectors.extend(std::iter::repeat_n(vec![0; 25], LATENCY as usize + 1));
    let want = expected(&pairs, vectors.len());

    let apply = |u: &mut SatFront, v: &[u64]| {
        u.valid_in.next = v[0] == 1;
        for x in 0..3 {
            u.center_a[x].next = v[1 + x].into();
            u.center_b[x].next = v[4 + x].into();
        }
        for i in 0..9 {
            u.axes_a[i].next = sbits(signed(v[7 + i], ROT));
            u.axes_b[i].next = sbits(signed(v[16 + i], ROT));
        }
    };
    let read = |u: &SatFront| {
        let mut o = vec![u64::from(u.valid_out.val())];
        o.extend((0..3).map(|i| raw(sval(u.t[i].val()), TU)));
        o.extend((0..3).map(|i| raw(sval(u.u[i].val()), TU)));
        o.extend((0..9).map(|i| raw(sval(u.r[i].val()), RR)));
        o
    };
    let clock = |u: &mut SatFront, c: bool| u.clock.next = Clock::from(c);
    let got = run_rust_hdl(&mut SatFront::default(), &vectors, apply, clock, read);
    check(&got, &want, "rust-hdl");

    let verilog = obb_rtl::flow::emit::verilog(&mut SatFront::default(), "sat_front").unwrap();
    let mut inputs = vec![Port::new("valid_in", 1)];
    inputs.extend(ports("center_a", 3, CENTER));
    inputs.extend(ports("center_b", 3, CENTER));
    inputs.extend(ports("axes_a", 9, ROT));
    inputs.extend(ports("axes_b", 9, ROT));
    let mut outputs = vec![Port::new("valid_out", 1)];
    outputs.extend(ports("t", 3, TU));
    outputs.extend(ports("u", 3, TU));
    outputs.extend(ports("r", 9, RR));
    let got = run_verilator(&verilog, "sat_front", &inputs, &outputs, &vectors);
    check(&got, &want, "verilator");
}
