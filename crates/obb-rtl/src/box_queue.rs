//! `BoxQueue`: a box as the grid's queues carry it (index, keys, margin, record kind), one
//! distributed RAM per field, `2^A` entries, written at `write_address` when `write_enable`,
//! read at `read_address` at once (`DistRam`). The grid's record queue and its list queue are
//! two of them.

use crate::dist_ram::DistRam;
use crate::projection::{CENTER, MARGIN};
use rust_hdl::prelude::*;

/// What a record is: bit 0 a round of a large box's window, bit 1 the rest of the large boxes'
/// chain (neither: an arriving box).
pub const KIND: usize = 2;

#[derive(LogicBlock, Default)]
pub struct BoxQueue<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    pub write_enable: Signal<In, Bit>,
    pub write_address: Signal<In, Bits<A>>,
    pub read_address: Signal<In, Bits<A>>,
    // The ports come axis by axis, not as arrays: the grid keeps a queue per lane in a list,
    // and rust-hdl emits an array port of a listed block wrongly.
    /// The box written: its index (with the flag bit).
    pub in_index: Signal<In, Bits<C>>,
    /// The box written: its min key on x.
    pub in_min_x: Signal<In, Bits<CENTER>>,
    /// The box written: its min key on y.
    pub in_min_y: Signal<In, Bits<CENTER>>,
    /// The box written: its min key on z.
    pub in_min_z: Signal<In, Bits<CENTER>>,
    /// The box written: its max key on x.
    pub in_max_x: Signal<In, Bits<CENTER>>,
    /// The box written: its max key on y.
    pub in_max_y: Signal<In, Bits<CENTER>>,
    /// The box written: its max key on z.
    pub in_max_z: Signal<In, Bits<CENTER>>,
    /// The box written: its projection margin.
    pub in_margin: Signal<In, Bits<MARGIN>>,
    /// The box written: its record kind (`KIND`).
    pub in_kind: Signal<In, Bits<KIND>>,
    /// The box at `read_address`: its index (with the flag bit).
    pub index: Signal<Out, Bits<C>>,
    /// The box at `read_address`: its min key on x.
    pub min_x: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its min key on y.
    pub min_y: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its min key on z.
    pub min_z: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its max key on x.
    pub max_x: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its max key on y.
    pub max_y: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its max key on z.
    pub max_z: Signal<Out, Bits<CENTER>>,
    /// The box at `read_address`: its projection margin.
    pub margin: Signal<Out, Bits<MARGIN>>,
    /// The box at `read_address`: its record kind (`KIND`).
    pub kind: Signal<Out, Bits<KIND>>,
    index_ram: DistRam<Bits<C>, A>,
    min_ram: [DistRam<Bits<CENTER>, A>; 3],
    max_ram: [DistRam<Bits<CENTER>, A>; 3],
    margin_ram: DistRam<Bits<MARGIN>, A>,
    kind_ram: DistRam<Bits<KIND>, A>,
}

impl<const A: usize, const C: usize> Logic for BoxQueue<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        clock!(self, clock, index_ram, margin_ram, kind_ram);
        self.index_ram.write_enable.next = self.write_enable.val();
        self.index_ram.write_address.next = self.write_address.val();
        self.index_ram.write_data.next = self.in_index.val();
        self.index_ram.read_address.next = self.read_address.val();
        self.index.next = self.index_ram.read_data.val();
        self.margin_ram.write_enable.next = self.write_enable.val();
        self.margin_ram.write_address.next = self.write_address.val();
        self.margin_ram.write_data.next = self.in_margin.val();
        self.margin_ram.read_address.next = self.read_address.val();
        self.margin.next = self.margin_ram.read_data.val();
        self.kind_ram.write_enable.next = self.write_enable.val();
        self.kind_ram.write_address.next = self.write_address.val();
        self.kind_ram.write_data.next = self.in_kind.val();
        self.kind_ram.read_address.next = self.read_address.val();
        self.kind.next = self.kind_ram.read_data.val();
        for x in 0..3 {
            self.min_ram[x].clock.next = self.clock.val();
            self.min_ram[x].write_enable.next = self.write_enable.val();
            self.min_ram[x].write_address.next = self.write_address.val();
            self.min_ram[x].read_address.next = self.read_address.val();
            self.max_ram[x].clock.next = self.clock.val();
            self.max_ram[x].write_enable.next = self.write_enable.val();
            self.max_ram[x].write_address.next = self.write_address.val();
            self.max_ram[x].read_address.next = self.read_address.val();
        }
        self.min_ram[0].write_data.next = self.in_min_x.val();
        self.min_ram[1].write_data.next = self.in_min_y.val();
        self.min_ram[2].write_data.next = self.in_min_z.val();
        self.max_ram[0].write_data.next = self.in_max_x.val();
        self.max_ram[1].write_data.next = self.in_max_y.val();
        self.max_ram[2].write_data.next = self.in_max_z.val();
        self.min_x.next = self.min_ram[0].read_data.val();
        self.min_y.next = self.min_ram[1].read_data.val();
        self.min_z.next = self.min_ram[2].read_data.val();
        self.max_x.next = self.max_ram[0].read_data.val();
        self.max_y.next = self.max_ram[1].read_data.val();
        self.max_z.next = self.max_ram[2].read_data.val();
    }
}
