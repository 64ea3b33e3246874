//! The projection pipeline, clock by clock against the model: the rust-hdl simulation and the
//! emitted Verilog in Verilator (and Icarus, which must agree), on the same vectors, must give
//! the model's keys and margins `LATENCY` clocks after each OBB, one OBB per clock, and nothing
//! on the other clocks.

use crate::common;

use common::{check, ports, raw, run_rust_hdl, run_verilator, signed};
use obb_model::fixed::{keys, project, quantize, HwConfig, Margins, QObb};
use obb_model::generate::{surgical, uniform};
use obb_model::Scene;
use obb_rtl::flow::verilator::{Port, Simulator};
use obb_rtl::leaf::{sbits, uval};
use obb_rtl::projection::{Projection, CENTER, HALF, LATENCY, MARGIN, ROT};
use rust_hdl::prelude::*;

/// One clock's inputs: valid, offset centers (3), half-lengths (3), rotation entries (9, raw).
fn input(b: &QObb, cfg: &HwConfig) -> Vec<u64> {
    let offset = 1i64 << (cfg.center_bits - 1);
    let mut v = vec![1];
    v.extend(b.center.map(|c| (c + offset) as u64));
    v.extend(b.half.map(|h| h as u64));
    v.extend((0..9).map(|i| raw(b.axes[i / 3][i % 3], ROT)));
    v
}

/// The boxes with a bubble after every seventh, then idle clocks to drain the pipeline.
fn stream(boxes: &[QObb], cfg: &HwConfig) -> Vec<Vec<u64>> {
    let idle = vec![0; 16];
    let mut v = Vec::new();
    for (i, b) in boxes.iter().enumerate() {
        v.push(input(b, cfg));
        if i % 7 == 6 {
            v.push(idle.clone());
        }
    }
    v.extend(std::iter::repeat_n(idle, LATENCY as usize + 2));
    v
}

/// The model's outputs clock by clock: valid, min keys, max keys, margin. A box applied on
/// clock k shows after the rising edge of clock k + LATENCY - 1.
fn expected(stream: &[Vec<u64>], boxes: &[QObb], cfg: &HwConfig) -> Vec<Vec<u64>> {
    let margins = Margins::new(cfg);
    let mut out = vec![vec![0; 8]; stream.len()];
    let mut next = boxes.iter();
    for (k, s) in stream.iter().enumerate() {
        if s[0] == 1 {
            let p = project(next.next().unwrap(), cfg, &margins);
            let (lo, hi) = keys(&p, cfg);
            let mut o = vec![1];
            o.extend(lo);
            o.extend(hi);
            o.push(p.margin as u64);
            out[k + LATENCY as usize - 1] = o;
        }
    }
    out
}

fn rust_hdl(cfg: &HwConfig, vectors: &[Vec<u64>]) -> Vec<Vec<u64>> {
    let apply = |u: &mut Projection, v: &[u64]| {
        u.valid_in.next = v[0] == 1;
        for x in 0..3 {
            u.center[x].next = v[1 + x].into();
            u.half[x].next = v[4 + x].into();
        }
        for i in 0..9 {
            u.axes[i].next = sbits(signed(v[7 + i], ROT));
        }
    };
    let read = |u: &Projection| {
        let mut o = vec![u64::from(u.valid_out.val())];
        o.extend((0..3).map(|x| uval(u.key_min[x].val())));
        o.extend((0..3).map(|x| uval(u.key_max[x].val())));
        o.push(uval(u.margin.val()));
        o
    };
    let clock = |u: &mut Projection, c: bool| u.clock.next = Clock::from(c);
    run_rust_hdl(&mut Projection::new(cfg), vectors, apply, clock, read)
}

/// The emitted Verilog in Verilator and in Icarus.
fn simulators(cfg: &HwConfig, vectors: &[Vec<u64>]) -> (Vec<Vec<u64>>, Vec<Vec<u64>>) {
    let verilog = obb_rtl::flow::emit::verilog(&mut Projection::new(cfg), "projection").unwrap();
    let mut inputs = vec![Port::new("valid_in", 1)];
    inputs.extend(ports("center", 3, CENTER));
    inputs.extend(ports("half", 3, HALF));
    inputs.extend(ports("axes", 9, ROT));
    let mut outputs = vec![Port::new("valid_out", 1)];
    outputs.extend(ports("key_min", 3, CENTER));
    outputs.extend(ports("key_max", 3, CENTER));
    outputs.push(Port::new("margin", MARGIN));
    let verilator = run_verilator(&verilog, "projection", &inputs, &outputs, vectors);
    // Icarus as a second opinion, on the same words.
    let dir = obb_rtl::flow::verilator::scratch_dir("projection-icarus").unwrap();
    let icarus = obb_rtl::flow::verilator::simulate(
        Simulator::Icarus,
        &dir,
        None,
        &verilog,
        "projection",
        "clock",
        &inputs,
        &outputs,
        vectors,
    )
    .unwrap();
    (verilator, icarus)
}

/// Scenes and configurations: the surgical scene (default formats), uniform boxes (narrow
/// formats), and degenerate boxes (widest formats).
fn cases() -> Vec<(Scene, HwConfig)> {
    let narrow = HwConfig {
        center_bits: 16,
        key_bits: 12,
        rot_bits: 10,
        half_bits: 15,
        ..HwConfig::default()
    };
    let wide = HwConfig {
        center_bits: 23,
        key_bits: 23,
        ..HwConfig::default()
    };
    let mut stiff = uniform(60, 3, 2.0).unwrap();
    stiff.obbs[0].half = [0.0; 3];
    stiff.obbs[1].axes = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]];
    vec![
        (surgical(300, 7).unwrap(), HwConfig::default()),
        (uniform(200, 5, 0.5).unwrap(), narrow),
        (stiff, wide),
    ]
    .into_iter()
    .map(|(s, c)| {
        let c = c.fitted(&s);
        (s, c)
    })
    .collect()
}

#[test]
fn projection_matches_the_model_in_rust_hdl_and_verilator() {
    for (scene, cfg) in cases() {
        let boxes = quantize(&scene, &cfg).unwrap();
        let vectors = stream(&boxes, &cfg);
        let want = expected(&vectors, &boxes, &cfg);
        check(&rust_hdl(&cfg, &vectors), &want, "rust-hdl");
        let (verilator, icarus) = simulators(&cfg, &vectors);
        check(&verilator, &want, "verilator");
        check(&icarus, &want, "icarus");
    }
}
