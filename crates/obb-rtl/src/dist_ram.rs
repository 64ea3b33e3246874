//! A small memory with one write port and an unregistered read port: distributed RAM
//! (RAM64M / RAM32M on the Virtex-6), which rust-hdl's `RAM` (registered read, block RAM) cannot
//! say. Writes take effect at the clock edge; `read_data` shows the memory at `read_address`
//! at once, including a write of the edge just past. A Rust simulation model plus hand-written
//! Verilog, co-simulated in `tests/leaves.rs`.

use rust_hdl::prelude::*;
use std::collections::BTreeMap;

#[derive(LogicBlock, Default)]
pub struct DistRam<D: Synth, const A: usize> {
    pub clock: Signal<In, Clock>,
    pub write_enable: Signal<In, Bit>,
    pub write_address: Signal<In, Bits<A>>,
    pub write_data: Signal<In, D>,
    pub read_address: Signal<In, Bits<A>>,
    pub read_data: Signal<Out, D>,
    /// The simulation model's memory (not a port: rust-hdl skips fields named with `_`).
    _mem: BTreeMap<Bits<A>, D>,
}

impl<D: Synth, const A: usize> Logic for DistRam<D, A> {
    fn update(&mut self) {
        if self.clock.pos_edge() && self.write_enable.val() {
            self._mem
                .insert(self.write_address.val(), self.write_data.val());
        }
        self.read_data.next = self
            ._mem
            .get(&self.read_address.val())
            .copied()
            .unwrap_or_default();
    }
    fn connect(&mut self) {
        self.read_data.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
reg [{d}:0] mem [0:{last}];
always @(posedge clock) begin
   if (write_enable) begin
      mem[write_address] <= write_data;
   end
end
always @(*) begin
   read_data = mem[read_address];
end
",
            d = D::BITS - 1,
            last = (1u64 << A) - 1,
        ))
    }
}
