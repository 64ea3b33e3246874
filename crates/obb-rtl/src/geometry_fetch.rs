//! The core's geometry fetch: a SAT test's two boxes read from the geometry tables (V+3 in
//! `core.rs`'s table: the addresses go to the tables' ports A and B as the test arrives, and
//! the test is registered beside the read) and their centers, half-lengths and axes registered
//! as the tables give them (V+4), with the test: the SAT's inputs. Nothing follows a block
//! RAM's output in its clock.

use crate::projection::{CENTER, HALF, MARGIN, ROT};
use rust_hdl::prelude::*;

#[derive(Default, LogicBlock)]
pub struct GeometryFetch<const A: usize> {
    pub clock: Signal<In, Clock>,
    /// A SAT test this clock: its boxes (lower index first) and their margins.
    pub test_valid: Signal<In, Bit>,
    /// The test's lower box index.
    pub test_a: Signal<In, Bits<A>>,
    /// The test's higher box index.
    pub test_b: Signal<In, Bits<A>>,
    /// The margin of box `test_a`.
    pub test_ma: Signal<In, Bits<MARGIN>>,
    /// The margin of box `test_b`.
    pub test_mb: Signal<In, Bits<MARGIN>>,
    /// The geometry tables' port A address: box `test_a`.
    pub addr_a: Signal<Out, Bits<A>>,
    /// The geometry tables' port B address: box `test_b`.
    pub addr_b: Signal<Out, Bits<A>>,
    /// Port A's center (box a), the clock after its address.
    pub read_center_a: [Signal<In, Bits<CENTER>>; 3],
    /// Port B's center (box b), the clock after its address.
    pub read_center_b: [Signal<In, Bits<CENTER>>; 3],
    /// Port A's half-lengths, the clock after its address.
    pub read_half_a: [Signal<In, Bits<HALF>>; 3],
    /// Port B's half-lengths, the clock after its address.
    pub read_half_b: [Signal<In, Bits<HALF>>; 3],
    /// Port A's axes (row-major), the clock after its address.
    pub read_axes_a: [Signal<In, Signed<ROT>>; 9],
    /// Port B's axes (row-major), the clock after its address.
    pub read_axes_b: [Signal<In, Signed<ROT>>; 9],
    /// A test's geometry is being read (V+3 done): counted as a SAT test.
    pub fetching: Signal<Out, Bit>,
    /// The SAT's inputs (V+5): a test, its boxes, their margins and their geometry.
    pub valid: Signal<Out, Bit>,
    /// The SAT's box A (the lower index).
    pub a: Signal<Out, Bits<A>>,
    /// The SAT's box B.
    pub b: Signal<Out, Bits<A>>,
    /// Box A's margin.
    pub ma: Signal<Out, Bits<MARGIN>>,
    /// Box B's margin.
    pub mb: Signal<Out, Bits<MARGIN>>,
    /// Box A's center.
    pub center_a: [Signal<Out, Bits<CENTER>>; 3],
    /// Box B's center.
    pub center_b: [Signal<Out, Bits<CENTER>>; 3],
    /// Box A's half-lengths.
    pub half_a: [Signal<Out, Bits<HALF>>; 3],
    /// Box B's half-lengths.
    pub half_b: [Signal<Out, Bits<HALF>>; 3],
    /// Box A's axes.
    pub axes_a: [Signal<Out, Signed<ROT>>; 9],
    /// Box B's axes.
    pub axes_b: [Signal<Out, Signed<ROT>>; 9],
    // The test beside its read (`g_`, V+3), and beside its geometry (`h_`, V+4).
    g_valid: DFF<Bit>,
    g_a: DFF<Bits<A>>,
    g_b: DFF<Bits<A>>,
    g_ma: DFF<Bits<MARGIN>>,
    g_mb: DFF<Bits<MARGIN>>,
    h_valid: DFF<Bit>,
    h_a: DFF<Bits<A>>,
    h_b: DFF<Bits<A>>,
    h_ma: DFF<Bits<MARGIN>>,
    h_mb: DFF<Bits<MARGIN>>,
    // The geometry as read, registered.
    geo_center_a: [DFF<Bits<CENTER>>; 3],
    geo_center_b: [DFF<Bits<CENTER>>; 3],
    geo_half_a: [DFF<Bits<HALF>>; 3],
    geo_half_b: [DFF<Bits<HALF>>; 3],
    geo_axes_a: [DFF<Signed<ROT>>; 9],
    geo_axes_b: [DFF<Signed<ROT>>; 9],
}

impl<const A: usize> Logic for GeometryFetch<A> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, g_valid, g_a, g_b, g_ma, g_mb, h_valid, h_a, h_b, h_ma, h_mb);
        for x in 0..3 {
            self.geo_center_a[x].clock.next = self.clock.val();
            self.geo_center_b[x].clock.next = self.clock.val();
            self.geo_half_a[x].clock.next = self.clock.val();
            self.geo_half_b[x].clock.next = self.clock.val();
        }
        for k in 0..9 {
            self.geo_axes_a[k].clock.next = self.clock.val();
            self.geo_axes_b[k].clock.next = self.clock.val();
        }
        // V+3: the tables take the addresses at the edge that registers the test.
        self.addr_a.next = self.test_a.val();
        self.addr_b.next = self.test_b.val();
        self.g_valid.d.next = self.test_valid.val();
        self.g_a.d.next = self.test_a.val();
        self.g_b.d.next = self.test_b.val();
        self.g_ma.d.next = self.test_ma.val();
        self.g_mb.d.next = self.test_mb.val();
        self.fetching.next = self.g_valid.q.val();
        // V+4: the geometry arrives and is registered.
        for x in 0..3 {
            self.geo_center_a[x].d.next = self.read_center_a[x].val();
            self.geo_center_b[x].d.next = self.read_center_b[x].val();
            self.geo_half_a[x].d.next = self.read_half_a[x].val();
            self.geo_half_b[x].d.next = self.read_half_b[x].val();
        }
        for k in 0..9 {
            self.geo_axes_a[k].d.next = self.read_axes_a[k].val();
            self.geo_axes_b[k].d.next = self.read_axes_b[k].val();
        }
        self.h_valid.d.next = self.g_valid.q.val();
        self.h_a.d.next = self.g_a.q.val();
        self.h_b.d.next = self.g_b.q.val();
        self.h_ma.d.next = self.g_ma.q.val();
        self.h_mb.d.next = self.g_mb.q.val();
        // V+5: the SAT's inputs.
        self.valid.next = self.h_valid.q.val();
        self.a.next = self.h_a.q.val();
        self.b.next = self.h_b.q.val();
        self.ma.next = self.h_ma.q.val();
        self.mb.next = self.h_mb.q.val();
        for x in 0..3 {
            self.center_a[x].next = self.geo_center_a[x].q.val();
            self.center_b[x].next = self.geo_center_b[x].q.val();
            self.half_a[x].next = self.geo_half_a[x].q.val();
            self.half_b[x].next = self.geo_half_b[x].q.val();
        }
        for k in 0..9 {
            self.axes_a[k].next = self.geo_axes_a[k].q.val();
            self.axes_b[k].next = self.geo_axes_b[k].q.val();
        }
    }
}
