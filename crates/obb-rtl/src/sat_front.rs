//! The SAT's first stage: for a pair (A, B) per clock, the exact products `t_i = T·a_i`,
//! `u_j = T·b_j` and `R_ij = a_i·b_j` with `T = c_B - c_A`, bit for bit as
//! `obb_model::fixed::sat::sat_products`. 45 multiplies, one DSP48E1 each.
//!
//! | clock | stage |
//! | --- | --- |
//! | 1 | `T = c_B - c_A` (offset centers, so the offsets cancel); the axes registered alongside |
//! | 2-6 | 15 three-term dot products (`SDot3`, `DOT_LATENCY` clocks): 3 for t, 3 for u, 9 for R |

use crate::leaf::{Diff, SDot3, DOT_LATENCY};
use crate::pipe::Pipe;
use crate::projection::{CENTER, ROT};
use rust_hdl::prelude::*;

/// Width of `T`.
pub const T_WORLD: usize = CENTER + 1;
/// Width of `t` and `u`: an 18 x 24-bit product summed three times.
pub const TU: usize = ROT + T_WORLD + 2;
/// Width of `R`.
pub const RR: usize = 2 * ROT + 2;
/// Clocks from a pair on the inputs to its products on the outputs.
pub const LATENCY: u64 = 1 + DOT_LATENCY;

#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SatFront {
    pub clock: Signal<In, Clock>,
    pub valid_in: Signal<In, Bit>,
    pub center_a: [Signal<In, Bits<CENTER>>; 3],
    pub center_b: [Signal<In, Bits<CENTER>>; 3],
    /// `axes_a[3i + x]`: entry x of A's axis i.
    pub axes_a: [Signal<In, Signed<ROT>>; 9],
    pub axes_b: [Signal<In, Signed<ROT>>; 9],
    pub valid_out: Signal<Out, Bit>,
    pub t: [Signal<Out, Signed<TU>>; 3],
    pub u: [Signal<Out, Signed<TU>>; 3],
    /// `r[3i + j]` = `R_ij`.
    pub r: [Signal<Out, Signed<RR>>; 9],
    /// `valid_in`, `LATENCY` clocks later.
    valid: Pipe<Bit, { LATENCY as usize }>,
    world: [Diff<CENTER, T_WORLD>; 3],
    axes_a_r: [DFF<Signed<ROT>>; 9],
    axes_b_r: [DFF<Signed<ROT>>; 9],
    t_dot: [SDot3<ROT, T_WORLD, TU>; 3],
    u_dot: [SDot3<ROT, T_WORLD, TU>; 3],
    r_dot: [SDot3<ROT, ROT, RR>; 9],
}

impl Logic for SatFront {
    #[hdl_gen]
    fn update(&mut self) {
        self.valid.clock.next = self.clock.val();
        for i in 0..3 {
            self.world[i].clock.next = self.clock.val();
            self.t_dot[i].clock.next = self.clock.val();
            self.u_dot[i].clock.next = self.clock.val();
        }
        for i in 0..9 {
            self.axes_a_r[i].clock.next = self.clock.val();
            self.axes_b_r[i].clock.next = self.clock.val();
            self.r_dot[i].clock.next = self.clock.val();
        }
        // Clock 1.
        self.valid.d.next = self.valid_in.val();
        for x in 0..3 {
            self.world[x].a.next = self.center_a[x].val();
            self.world[x].b.next = self.center_b[x].val();
        }
        for i in 0..9 {
            self.axes_a_r[i].d.next = self.axes_a[i].val();
            self.axes_b_r[i].d.next = self.axes_b[i].val();
        }
        // Clocks 2-6.
        for i in 0..3 {
            self.t_dot[i].a0.next = self.axes_a_r[i * 3].q.val();
            self.t_dot[i].a1.next = self.axes_a_r[i * 3 + 1].q.val();
            self.t_dot[i].a2.next = self.axes_a_r[i * 3 + 2].q.val();
            self.t_dot[i].b0.next = self.world[0].d.val();
            self.t_dot[i].b1.next = self.world[1].d.val();
            self.t_dot[i].b2.next = self.world[2].d.val();
            self.u_dot[i].a0.next = self.axes_b_r[i * 3].q.val();
            self.u_dot[i].a1.next = self.axes_b_r[i * 3 + 1].q.val();
            self.u_dot[i].a2.next = self.axes_b_r[i * 3 + 2].q.val();
            self.u_dot[i].b0.next = self.world[0].d.val();
            self.u_dot[i].b1.next = self.world[1].d.val();
            self.u_dot[i].b2.next = self.world[2].d.val();
            self.t[i].next = self.t_dot[i].p.val();
            self.u[i].next = self.u_dot[i].p.val();
        }
        for i in 0..3 {
            for j in 0..3 {
                self.r_dot[i * 3 + j].a0.next = self.axes_a_r[i * 3].q.val();
                self.r_dot[i * 3 + j].a1.next = self.axes_a_r[i * 3 + 1].q.val();
                self.r_dot[i * 3 + j].a2.next = self.axes_a_r[i * 3 + 2].q.val();
                self.r_dot[i * 3 + j].b0.next = self.axes_b_r[j * 3].q.val();
                self.r_dot[i * 3 + j].b1.next = self.axes_b_r[j * 3 + 1].q.val();
                self.r_dot[i * 3 + j].b2.next = self.axes_b_r[j * 3 + 2].q.val();
                self.r[i * 3 + j].next = self.r_dot[i * 3 + j].p.val();
            }
        }
        self.valid_out.next = self.valid.q.val();
    }
}
