//! The core's key check, for the sweep and the walkers (the grid checks its own keys): a
//! visit's keys, margins and groups as the key table gives them, registered (V+1); their
//! overlap on x, y and z and the group mask (V+2); the SAT test registered, lower index first
//! (V+3: the clock its geometry is read). Clocks as in `core.rs`'s table.

use crate::projection::{CENTER, MARGIN};
use obb_model::fixed::config::GROUP_BITS;
use rust_hdl::prelude::*;

const GROUP: usize = GROUP_BITS as usize;
/// The group mask: bit `8 g + h` says whether groups g and h are paired.
pub const MASK: usize = 1 << (2 * GROUP);

#[derive(Default, LogicBlock)]
pub struct KeyCheck<const A: usize> {
    pub clock: Signal<In, Clock>,
    /// A visit (i, j) this clock: its keys are read now, on the key table's ports A and B.
    pub visit: Signal<In, Bit>,
    /// The visit's box i (port A).
    pub i: Signal<In, Bits<A>>,
    /// The visit's box j (port B).
    pub j: Signal<In, Bits<A>>,
    /// Port A's min keys (box i's), the clock after the visit.
    pub min_a: [Signal<In, Bits<CENTER>>; 3],
    /// Port B's min keys (box j's), the clock after the visit.
    pub min_b: [Signal<In, Bits<CENTER>>; 3],
    /// Port A's max keys, the clock after the visit.
    pub max_a: [Signal<In, Bits<CENTER>>; 3],
    /// Port B's max keys, the clock after the visit.
    pub max_b: [Signal<In, Bits<CENTER>>; 3],
    /// Box i's projection margin, the clock after the visit.
    pub margin_a: Signal<In, Bits<MARGIN>>,
    /// Box j's projection margin, the clock after the visit.
    pub margin_b: Signal<In, Bits<MARGIN>>,
    /// Box i's group, the clock after the visit.
    pub group_a: Signal<In, Bits<GROUP>>,
    /// Box j's group, the clock after the visit.
    pub group_b: Signal<In, Bits<GROUP>>,
    /// The configured group mask.
    pub mask: Signal<In, Bits<MASK>>,
    /// Improved-sap: every visit the mask allows is a SAT test (the paper checks no keys).
    pub unchecked: Signal<In, Bit>,
    /// No SAT test comes from here (the grid sends its own).
    pub idle: Signal<In, Bit>,
    /// A visit's keys are registered this clock (the visit was a clock before): counted.
    pub visited: Signal<Out, Bit>,
    /// The registered keys overlap on all three axes (V+2), a SAT test or not.
    pub overlap: Signal<Out, Bit>,
    /// A SAT test (V+3): its boxes, lower index first, and their margins.
    pub test_valid: Signal<Out, Bit>,
    /// The SAT test's lower box index (box A of the SAT).
    pub test_a: Signal<Out, Bits<A>>,
    /// The SAT test's higher box index.
    pub test_b: Signal<Out, Bits<A>>,
    /// The margin of box `test_a`.
    pub test_ma: Signal<Out, Bits<MARGIN>>,
    /// The margin of box `test_b`.
    pub test_mb: Signal<Out, Bits<MARGIN>>,
    // The visit registered (V+1, `k_`), and again beside its keys (V+2, `r_`); the keys,
    // margins and groups as the key table gave them at V+1, registered.
    k_valid: DFF<Bit>,
    k_i: DFF<Bits<A>>,
    k_j: DFF<Bits<A>>,
    r_valid: DFF<Bit>,
    r_i: DFF<Bits<A>>,
    r_j: DFF<Bits<A>>,
    key_min_a: [DFF<Bits<CENTER>>; 3],
    key_min_b: [DFF<Bits<CENTER>>; 3],
    key_max_a: [DFF<Bits<CENTER>>; 3],
    key_max_b: [DFF<Bits<CENTER>>; 3],
    r_margin_a: DFF<Bits<MARGIN>>,
    r_margin_b: DFF<Bits<MARGIN>>,
    r_group_a: DFF<Bits<GROUP>>,
    r_group_b: DFF<Bits<GROUP>>,
    // V+2: the check.
    gidx: Signal<Local, Bits<MASK>>,
    shifted: Signal<Local, Bits<MASK>>,
    pass: Signal<Local, Bit>,
    swap: Signal<Local, Bit>,
    // V+3: the SAT test.
    c_valid: DFF<Bit>,
    c_a: DFF<Bits<A>>,
    c_b: DFF<Bits<A>>,
    c_ma: DFF<Bits<MARGIN>>,
    c_mb: DFF<Bits<MARGIN>>,
}

impl<const A: usize> Logic for KeyCheck<A> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, k_valid, k_i, k_j, r_valid, r_i, r_j, r_margin_a, r_margin_b, r_group_a,
            r_group_b, c_valid, c_a, c_b, c_ma, c_mb
        );
        // V+1: the keys, margins and groups of i and j arrive and are registered.
        self.k_valid.d.next = self.visit.val();
        self.k_i.d.next = self.i.val();
        self.k_j.d.next = self.j.val();
        self.r_valid.d.next = self.k_valid.q.val();
        self.r_i.d.next = self.k_i.q.val();
        self.r_j.d.next = self.k_j.q.val();
        for x in 0..3 {
            self.key_min_a[x].clock.next = self.clock.val();
            self.key_min_b[x].clock.next = self.clock.val();
            self.key_max_a[x].clock.next = self.clock.val();
            self.key_max_b[x].clock.next = self.clock.val();
            self.key_min_a[x].d.next = self.min_a[x].val();
            self.key_min_b[x].d.next = self.min_b[x].val();
            self.key_max_a[x].d.next = self.max_a[x].val();
            self.key_max_b[x].d.next = self.max_b[x].val();
        }
        self.r_margin_a.d.next = self.margin_a.val();
        self.r_margin_b.d.next = self.margin_b.val();
        self.r_group_a.d.next = self.group_a.val();
        self.r_group_b.d.next = self.group_b.val();
        self.visited.next = self.k_valid.q.val();

        // V+2: the keys of i and j overlap on all three axes, and the mask allows the groups.
        self.overlap.next = (self.key_min_a[0].q.val() <= self.key_max_b[0].q.val())
            & (self.key_min_b[0].q.val() <= self.key_max_a[0].q.val())
            & (self.key_min_a[1].q.val() <= self.key_max_b[1].q.val())
            & (self.key_min_b[1].q.val() <= self.key_max_a[1].q.val())
            & (self.key_min_a[2].q.val() <= self.key_max_b[2].q.val())
            & (self.key_min_b[2].q.val() <= self.key_max_a[2].q.val());
        self.gidx.next = (bit_cast::<MASK, GROUP>(self.r_group_a.q.val()) << 3_u64)
            | bit_cast::<MASK, GROUP>(self.r_group_b.q.val());
        self.shifted.next = self.mask.val() >> self.gidx.val();
        self.pass.next = self.r_valid.q.val()
            & (self.overlap.val() | self.unchecked.val())
            & self.shifted.val().get_bit(0)
            & !self.idle.val();
        // The lower index is box A of the SAT.
        self.swap.next = self.r_j.q.val() < self.r_i.q.val();
        self.c_valid.d.next = self.pass.val();
        self.c_a.d.next = self.r_i.q.val();
        self.c_b.d.next = self.r_j.q.val();
        self.c_ma.d.next = self.r_margin_a.q.val();
        self.c_mb.d.next = self.r_margin_b.q.val();
        if self.swap.val() {
            self.c_a.d.next = self.r_j.q.val();
            self.c_b.d.next = self.r_i.q.val();
            self.c_ma.d.next = self.r_margin_b.q.val();
            self.c_mb.d.next = self.r_margin_a.q.val();
        }
        self.test_valid.next = self.c_valid.q.val();
        self.test_a.next = self.c_a.q.val();
        self.test_b.next = self.c_b.q.val();
        self.test_ma.next = self.c_ma.q.val();
        self.test_mb.next = self.c_mb.q.val();
    }
}
