//! A table with one write port and two read ports, as two copies of a `RAM` written together
//! (rust-hdl has no true dual-port memory). The core keeps its per-box tables in these: the
//! broad phase and the SAT read two boxes (A and B) every clock. Reads take one clock, like
//! `RAM`'s.

use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct TwoReadRam<D: Synth, const A: usize> {
    pub clock: Signal<In, Clock>,
    pub write_enable: Signal<In, Bit>,
    pub write_address: Signal<In, Bits<A>>,
    pub write_data: Signal<In, D>,
    // Scalar ports: rust-hdl emits invalid Verilog for array ports of blocks kept in arrays.
    pub read_address_a: Signal<In, Bits<A>>,
    pub read_address_b: Signal<In, Bits<A>>,
    pub read_data_a: Signal<Out, D>,
    pub read_data_b: Signal<Out, D>,
    copy_a: RAM<D, A>,
    copy_b: RAM<D, A>,
}

impl<D: Synth, const A: usize> Logic for TwoReadRam<D, A> {
    #[hdl_gen]
    fn update(&mut self) {
        self.copy_a.read_clock.next = self.clock.val();
        self.copy_a.write_clock.next = self.clock.val();
        self.copy_b.read_clock.next = self.clock.val();
        self.copy_b.write_clock.next = self.clock.val();
        self.copy_a.write_enable.next = self.write_enable.val();
        self.copy_b.write_enable.next = self.write_enable.val();
        self.copy_a.write_address.next = self.write_address.val();
        self.copy_b.write_address.next = self.write_address.val();
        self.copy_a.write_data.next = self.write_data.val();
        self.copy_b.write_data.next = self.write_data.val();
        self.copy_a.read_address.next = self.read_address_a.val();
        self.copy_b.read_address.next = self.read_address_b.val();
        self.read_data_a.next = self.copy_a.read_data.val();
        self.read_data_b.next = self.copy_b.read_data.val();
    }
}
