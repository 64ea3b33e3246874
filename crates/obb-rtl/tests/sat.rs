//! The whole SAT pipeline, clock by clock against the model's `collide` (via `ModelFrame::sat`),
//! in rust-hdl and in Verilator: one pair of boxes per clock, the verdict `LATENCY` clocks later;
//! and every axis' two sides where the decision reads them (`common::sat_sides`), against a
//! reference computed from the boxes (`common::whole_sat`).

use crate::common;

use common::sat_sides::{self, Stimulus};
use common::whole_sat::{self, SIDES_AT};
use common::{check, pairs, run_rust_hdl, signed};
use obb_model::fixed::{HwConfig, ModelFrame};
use obb_model::generate::{surgical, uniform};
use obb_rtl::leaf::sbits;
use obb_rtl::projection::ROT;
use obb_rtl::sat::{Sat, LATENCY};
use rust_hdl::prelude::*;

fn run(m: &ModelFrame, pairs: &[(usize, usize)]) {
    let Stimulus {
        vectors,
        want,
        want_sides,
    } = whole_sat::stimulus(m, pairs);
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
        sat_sides::differ(&got, &want_sides, SIDES_AT, 2),
        None,
        "rust-hdl"
    );

    let verilog = obb_rtl::flow::emit::verilog(&mut Sat::new(&m.cfg), "sat").unwrap();
    let got = whole_sat::in_verilator(&verilog, &vectors);
    check(&sat_sides::verdicts(&got), &want, "verilator");
    assert_eq!(
        sat_sides::differ(&got, &want_sides, SIDES_AT, 2),
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
