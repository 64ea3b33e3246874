//! The synthesis estimate's cache (`synth::period_ns`), on a small module in yosys: no period
//! before a synthesis, the analysis' period after it, the same from the cache without yosys
//! running again, and none for other Verilog.

use obb_rtl::flow::synth;

const ADDER: &str = "module tiny(input clock, input [7:0] a, input [7:0] b, output reg [7:0] q);
  reg [7:0] ra, rb;
  always @(posedge clock) begin ra <= a; rb <= b; q <= ra + rb; end
endmodule
";

#[test]
fn a_period_is_known_once_the_core_is_synthesized() {
    let cache = obb_rtl::flow::verilator::scratch_dir("period").unwrap();
    assert_eq!(
        synth::period_ns(ADDER, "tiny", &cache, false).unwrap(),
        None
    );
    let ns = synth::period_ns(ADDER, "tiny", &cache, true)
        .unwrap()
        .expect("synthesized");
    let (dir, cached) = synth::netlist(ADDER, "tiny", synth::Mapping::Report, &cache).unwrap();
    assert!(cached, "period_ns kept the netlist in the cache");
    let report = synth::analyze(&dir.join("net.json"), "tiny").unwrap();
    assert_eq!(ns, report.worst.delay_ns);
    assert!(ns > 0.0 && report.worst.carry4 > 0, "{:?}", report.worst);
    assert_eq!(
        synth::period_ns(ADDER, "tiny", &cache, false).unwrap(),
        Some(ns)
    );
    let other = ADDER.replace("ra + rb", "ra - rb");
    assert_eq!(
        synth::period_ns(&other, "tiny", &cache, false).unwrap(),
        None
    );
}
