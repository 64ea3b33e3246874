//! A small memory with one write port and an unregistered read port: distributed RAM
//! (RAM64M / RAM32M on the Virtex-6), which rust-hdl's `RAM` (registered read, block RAM) cannot
//! say (and its attribute `ram_style = "distributed"`, which XST and yosys both honour, keeps
//! it so where the read feeds only a register and block RAM would also do). Writes take effect
//! at the clock edge; `read_data` shows the memory at `read_address`
//! at once, including a write of the edge just past. `zeroed` makes a memory that holds zeros
//! from power-up (the LUTs' INIT; the simulation model's too) with fewer entries than the
//! address reaches (the caller never addresses beyond them). `registers` makes one of
//! flip-flops and a read multiplexer instead (written out register by register, so that every
//! tool maps it so): synthesis then sees the read as logic and counts its LUT level, where a
//! distributed RAM's read is a level its mapper (yosys' ABC) does not see, and may stack three
//! more behind. A Rust simulation model plus hand-written Verilog, co-simulated in
//! `tests/leaves.rs`.

use rust_hdl::prelude::*;
use std::collections::BTreeMap;

#[derive(LogicBlock)]
pub struct DistRam<D: Synth, const A: usize> {
    pub clock: Signal<In, Clock>,
    pub write_enable: Signal<In, Bit>,
    pub write_address: Signal<In, Bits<A>>,
    pub write_data: Signal<In, D>,
    pub read_address: Signal<In, Bits<A>>,
    pub read_data: Signal<Out, D>,
    /// The simulation model's memory (not a port: rust-hdl skips fields named with `_`).
    _mem: BTreeMap<Bits<A>, D>,
    /// Entries held, whether the Verilog states their zeros at power-up, whether they are
    /// flip-flops.
    _depth: u64,
    _zeroed: bool,
    _registers: bool,
}

impl<D: Synth, const A: usize> Default for DistRam<D, A> {
    fn default() -> Self {
        Self::new(1 << A, false)
    }
}

impl<D: Synth, const A: usize> DistRam<D, A> {
    /// A memory of `depth` entries, at most `2^A`, zero from power-up.
    pub fn zeroed(depth: u64) -> Self {
        Self::new(depth, true)
    }

    /// A memory of `2^A` flip-flop entries.
    pub fn registers() -> Self {
        DistRam {
            _registers: true,
            ..Self::new(1 << A, false)
        }
    }

    fn new(depth: u64, zeroed: bool) -> Self {
        assert!(
            depth >= 1 && depth <= 1 << A,
            "the depth is within the address"
        );
        DistRam {
            clock: Default::default(),
            write_enable: Default::default(),
            write_address: Default::default(),
            write_data: Default::default(),
            read_address: Default::default(),
            read_data: Default::default(),
            _mem: BTreeMap::new(),
            _depth: depth,
            _zeroed: zeroed,
            _registers: false,
        }
    }
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
        if self._registers {
            return Verilog::Custom(self.registers_verilog());
        }
        Verilog::Custom(format!(
            "\
(* ram_style = \"distributed\" *)
reg [{d}:0] mem [0:{last}];
{init}always @(posedge clock) begin
   if (write_enable) begin
      mem[write_address] <= write_data;
   end
end
always @(*) begin
   read_data = mem[read_address];
end
",
            d = D::BITS - 1,
            last = self._depth - 1,
            init = if self._zeroed {
                format!(
                    "integer k;\ninitial begin\n   for (k = 0; k < {}; k = k + 1) begin\n      \
                     mem[k] = 0;\n   end\nend\n",
                    self._depth
                )
            } else {
                String::new()
            },
        ))
    }
}

impl<D: Synth, const A: usize> DistRam<D, A> {
    /// The flip-flop memory: one register per entry, a `case` to write and one to read.
    fn registers_verilog(&self) -> String {
        let entries = 0..1u64 << A;
        let regs: String = entries
            .clone()
            .map(|k| format!("reg [{}:0] mem_{k};\n", D::BITS - 1))
            .collect();
        let writes: String = entries
            .clone()
            .map(|k| format!("         {k}: mem_{k} <= write_data;\n"))
            .collect();
        let reads: String = entries
            .map(|k| format!("      {k}: read_data = mem_{k};\n"))
            .collect();
        format!(
            "\
{regs}always @(posedge clock) begin
   if (write_enable) begin
      case (write_address)
{writes}      endcase
   end
end
always @(*) begin
   case (read_address)
{reads}   endcase
end
"
        )
    }
}
