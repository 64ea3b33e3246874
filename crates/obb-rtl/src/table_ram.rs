//! A per-box table: one memory with a write port and two read ports, as one true dual-port
//! block RAM (RAMB36E1 in TDP mode) rather than two copies of a simple dual-port `RAM` written
//! together, which is all rust-hdl's `RAM` can say and which doubled the core's block RAM.
//! Port A writes or reads (the write wins its address), port B reads. The core never reads a
//! table while it writes it (boxes are loaded and projected before the broad phase reads them),
//! so sharing port A costs nothing but a 2:1 multiplexer on its address.
//!
//! Reads take one clock and see the memory before the same clock's write ("read first", the
//! RAMB36E1's READ_FIRST mode, which yosys maps with no bypass logic). A Rust simulation model
//! plus hand-written Verilog, co-simulated in `tests/leaves.rs`. `with_depth` makes a table of
//! fewer entries than the address reaches (the grid's per-lane banks: the caller never
//! addresses beyond them).

use rust_hdl::prelude::*;
use std::collections::BTreeMap;

#[derive(LogicBlock)]
pub struct TableRam<D: Synth, const A: usize> {
    pub clock: Signal<In, Clock>,
    pub write_enable: Signal<In, Bit>,
    pub write_address: Signal<In, Bits<A>>,
    pub write_data: Signal<In, D>,
    // Scalar ports: rust-hdl emits invalid Verilog for array ports of blocks kept in arrays.
    pub read_address_a: Signal<In, Bits<A>>,
    pub read_address_b: Signal<In, Bits<A>>,
    pub read_data_a: Signal<Out, D>,
    pub read_data_b: Signal<Out, D>,
    /// The simulation model's memory (not a port: rust-hdl skips fields named with `_`).
    _mem: BTreeMap<Bits<A>, D>,
    /// Entries held.
    _depth: u64,
}

impl<D: Synth, const A: usize> Default for TableRam<D, A> {
    fn default() -> Self {
        Self::with_depth(1 << A)
    }
}

impl<D: Synth, const A: usize> TableRam<D, A> {
    /// A table of `depth` entries, at most `2^A`.
    pub fn with_depth(depth: u64) -> Self {
        assert!(
            depth <= 1 << A,
            "{depth} entries need more than {A} address bits"
        );
        TableRam {
            clock: Default::default(),
            write_enable: Default::default(),
            write_address: Default::default(),
            write_data: Default::default(),
            read_address_a: Default::default(),
            read_address_b: Default::default(),
            read_data_a: Default::default(),
            read_data_b: Default::default(),
            _mem: BTreeMap::new(),
            _depth: depth,
        }
    }
}

impl<D: Synth, const A: usize> Logic for TableRam<D, A> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let we = self.write_enable.val();
            let address_a = if we {
                self.write_address.val()
            } else {
                self.read_address_a.val()
            };
            let read = |a: Bits<A>| self._mem.get(&a).copied().unwrap_or_default();
            self.read_data_a.next = read(address_a);
            self.read_data_b.next = read(self.read_address_b.val());
            if we {
                self._mem.insert(address_a, self.write_data.val());
            }
        }
    }
    fn connect(&mut self) {
        self.read_data_a.connect();
        self.read_data_b.connect();
    }
    fn hdl(&self) -> Verilog {
        // Port A's read and write share its address; both reads are nonblocking, so they see
        // the memory before the write (READ_FIRST).
        Verilog::Custom(format!(
            "\
reg [{d}:0] mem [0:{last}];
wire [{a}:0] address_a = write_enable ? write_address : read_address_a;
{init}always @(posedge clock) begin
   if (write_enable) begin
      mem[address_a] <= write_data;
   end
   read_data_a <= mem[address_a];
end
always @(posedge clock) begin
   read_data_b <= mem[read_address_b];
end
",
            init = crate::leaf::zeroed(["read_data_a", "read_data_b"]),
            d = D::BITS - 1,
            a = A - 1,
            last = self._depth - 1,
        ))
    }
}
