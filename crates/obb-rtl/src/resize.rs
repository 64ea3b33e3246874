//! `Resize`: a value widened (zeros above) or cut to `O` bits. rust-hdl computes a
//! `bit_cast`'s width by evaluating its argument when it writes the Verilog, outside any loop,
//! so a loop-indexed signal (`self.x[k]`) cannot be cast in a loop; a block per element can.

use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct Resize<const O: usize, const I: usize> {
    pub value: Signal<In, Bits<I>>,
    pub resized: Signal<Out, Bits<O>>,
}

impl<const O: usize, const I: usize> Logic for Resize<O, I> {
    #[hdl_gen]
    fn update(&mut self) {
        self.resized.next = bit_cast::<O, I>(self.value.val());
    }
}
