//! The projection pipeline, cycle by cycle against the model: the rust-hdl simulation and the
//! emitted Verilog in Verilator, on the same vectors, must give the model's keys and margins
//! `LATENCY` clocks after each OBB, one OBB per clock, and nothing on the other clocks.

use obb_model::fixed::{keys, project, quantize, HwConfig, Margins, QObb};
use obb_model::generate::{surgical, uniform};
use obb_model::Scene;
use obb_rtl::leaf::{sbits, uval};
use obb_rtl::projection::{Projection, LATENCY};
use obb_rtl::verilator::{self, Port};
use rust_hdl::prelude::*;

/// What the pipeline must show after one clock: valid, min keys, max keys, margin.
type Out = (bool, [u64; 3], [u64; 3], u64);

/// One clock's inputs: valid, offset centers, half-lengths, the 9 rotation entries.
#[derive(Clone)]
struct In {
    valid: bool,
    center: [u64; 3],
    half: [u64; 3],
    axes: [i64; 9],
}

fn input(b: &QObb, cfg: &HwConfig) -> In {
    let offset = 1i64 << (cfg.center_bits - 1);
    In {
        valid: true,
        center: b.center.map(|c| (c + offset) as u64),
        half: b.half.map(|h| h as u64),
        axes: std::array::from_fn(|i| b.axes[i / 3][i % 3]),
    }
}

const IDLE: In = In {
    valid: false,
    center: [0; 3],
    half: [0; 3],
    axes: [0; 9],
};

/// The clocks: the boxes with a bubble after every seventh, then enough idle clocks to drain.
fn stream(boxes: &[QObb], cfg: &HwConfig) -> Vec<In> {
    let mut v = Vec::new();
    for (i, b) in boxes.iter().enumerate() {
        v.push(input(b, cfg));
        if i % 7 == 6 {
            v.push(IDLE);
        }
    }
    v.extend(std::iter::repeat_n(IDLE, LATENCY as usize + 2));
    v
}

/// The model's outputs clock by clock: each valid input appears `LATENCY - 1` clocks after the
/// clock it is applied on (outputs are read after the rising edge).
fn expected(stream: &[In], boxes: &[QObb], cfg: &HwConfig) -> Vec<Out> {
    let margins = Margins::new(cfg);
    let mut out = vec![(false, [0; 3], [0; 3], 0); stream.len()];
    let mut next = boxes.iter();
    for (k, s) in stream.iter().enumerate() {
        if s.valid {
            let b = next.next().unwrap();
            let p = project(b, cfg, &margins);
            let (lo, hi) = keys(&p, cfg);
            out[k + LATENCY as usize - 1] = (true, lo, hi, p.margin as u64);
        }
    }
    out
}

fn rust_hdl_run(cfg: &HwConfig, stream: &[In]) -> Vec<Out> {
    let mut uut = Projection::new(cfg);
    uut.connect_all();
    let mut out = Vec::with_capacity(stream.len());
    for s in stream {
        uut.valid_in.next = s.valid;
        for x in 0..3 {
            uut.center[x].next = s.center[x].into();
            uut.half[x].next = s.half[x].into();
        }
        for i in 0..9 {
            uut.axes[i].next = sbits(s.axes[i]);
        }
        uut.clock.next = Clock::from(false);
        assert!(simulate(&mut uut, 1000));
        uut.clock.next = Clock::from(true);
        assert!(simulate(&mut uut, 1000));
        out.push((
            uut.valid_out.val(),
            std::array::from_fn(|x| uval(uut.key_min[x].val())),
            std::array::from_fn(|x| uval(uut.key_max[x].val())),
            uval(uut.margin.val()),
        ));
    }
    out
}

fn ports() -> (Vec<Port>, Vec<Port>) {
    use obb_rtl::projection::{CENTER, HALF, MARGIN, ROT};
    let mut inputs = vec![Port::new("valid_in", 1)];
    inputs.extend((0..3).map(|x| Port::new(format!("center${x}"), CENTER)));
    inputs.extend((0..3).map(|x| Port::new(format!("half${x}"), HALF)));
    inputs.extend((0..9).map(|i| Port::new(format!("axes${i}"), ROT)));
    let mut outputs = vec![Port::new("valid_out", 1)];
    outputs.extend((0..3).map(|x| Port::new(format!("key_min${x}"), CENTER)));
    outputs.extend((0..3).map(|x| Port::new(format!("key_max${x}"), CENTER)));
    outputs.push(Port::new("margin", MARGIN));
    (inputs, outputs)
}

fn verilator_run(cfg: &HwConfig, stream: &[In], name: &str) -> Vec<Out> {
    let mut uut = Projection::new(cfg);
    let verilog = obb_rtl::emit::verilog(&mut uut, "projection").unwrap();
    let dir = verilator::scratch_dir(name).unwrap();
    verilator::lint(&dir, &verilog, "projection").unwrap();
    let (inputs, outputs) = ports();
    let rot_mask = (1u64 << obb_rtl::projection::ROT) - 1;
    let vectors: Vec<Vec<u64>> = stream
        .iter()
        .map(|s| {
            let mut v = vec![u64::from(s.valid)];
            v.extend(s.center);
            v.extend(s.half);
            v.extend(s.axes.map(|r| r as u64 & rot_mask));
            v
        })
        .collect();
    verilator::simulate(
        &dir,
        &verilog,
        "projection",
        "clock",
        &inputs,
        &outputs,
        &vectors,
    )
    .unwrap()
    .into_iter()
    .map(|o| (o[0] == 1, [o[1], o[2], o[3]], [o[4], o[5], o[6]], o[7]))
    .collect()
}

/// Compares the valid clocks value by value, and requires no valid output elsewhere.
fn check(got: &[Out], want: &[Out], what: &str) {
    assert_eq!(got.len(), want.len());
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        if w.0 || g.0 {
            assert_eq!(g, w, "{what}: clock {k}");
        }
    }
    assert!(want.iter().filter(|w| w.0).count() > 0);
}

fn scenes() -> Vec<(Scene, HwConfig)> {
    let cfg = HwConfig::default();
    let narrow = HwConfig {
        center_bits: 16,
        key_bits: 12,
        rot_bits: 10,
        half_bits: 15,
        ..HwConfig::default()
    };
    let mut stiff = uniform(60, 3, 2.0).unwrap();
    stiff.obbs[0].half = [0.0; 3];
    stiff.obbs[1].axes = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]];
    let wide = HwConfig {
        center_bits: 23,
        key_bits: 23,
        ..HwConfig::default()
    };
    vec![
        (surgical(300, 7).unwrap(), cfg.clone()),
        (uniform(200, 5, 0.5).unwrap(), narrow.clone()),
        (stiff.clone(), wide.clone()),
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
    for (n, (scene, cfg)) in scenes().into_iter().enumerate() {
        let boxes = quantize(&scene, &cfg).unwrap();
        let stream = stream(&boxes, &cfg);
        let want = expected(&stream, &boxes, &cfg);
        check(&rust_hdl_run(&cfg, &stream), &want, "rust-hdl");
        check(
            &verilator_run(&cfg, &stream, &format!("proj{n}")),
            &want,
            "verilator",
        );
    }
}
