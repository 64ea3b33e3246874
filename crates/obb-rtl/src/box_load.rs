//! The core's load stage: which box on the OBB stream is taken, at which index it is stored,
//! and when the load ends. A frame begins with `frame_start`; from the next clock a box on the
//! stream is taken when the core is ready, the grid (if any) has a record free for it, and the
//! tables have room; it is stored at `index` (the count of boxes before it). The load ends with
//! the last box taken, or with `obb_last` alone. A box after the tables are full is taken and
//! dropped, and the frame refused (incomplete).
//!
//! A `frame_start` while a frame is under way (`live`) aborts it: the load ends at once (no box
//! is taken on that clock or after), and the core begins the new frame when the old one has run
//! out (`restart_go`, with the `frame_update` given at the abort, `restart_update`). `frame_begin`,
//! `update` and `frame_abort` say so to the rest of the core, so that one place decides them.
//!
//! Resident groups (`resident_groups`): an update frame (`frame_start` with `frame_update`)
//! loads the resident groups' boxes first and keeps their count; a haptic frame (without)
//! streams only the other groups' boxes, whose indices follow the resident ones. A resident box
//! in a haptic frame, or after a streamed box, refuses the frame (the resident lists would be
//! unsure: the next frame must be an update). So does every haptic frame until an update frame
//! has loaded whole (`res_ok`): none yet, or the last one refused or aborted.

use obb_model::fixed::config::GROUP_BITS;
use obb_model::fixed::HwConfig;
use rust_hdl::prelude::*;

const GROUP: usize = GROUP_BITS as usize;

#[derive(LogicBlock)]
pub struct BoxLoad<const A: usize, const C: usize> {
    pub clock: Signal<In, Clock>,
    /// Pulse: a frame begins (boxes are taken from the next clock).
    pub frame_start: Signal<In, Bit>,
    /// With `frame_start`: an update frame (resident groups only).
    pub frame_update: Signal<In, Bit>,
    /// The core's frame is under way (registered): a `frame_start` now aborts it.
    pub live: Signal<In, Bit>,
    /// Pulse (registered): an aborted frame has run out; the new frame begins.
    pub restart_go: Signal<In, Bit>,
    /// The `frame_update` given with the abort (registered).
    pub restart_update: Signal<In, Bit>,
    /// A box is on the stream.
    pub obb_valid: Signal<In, Bit>,
    /// The box on the stream is the frame's last (or, alone, the frame has no more).
    pub obb_last: Signal<In, Bit>,
    /// The box's group.
    pub obb_group: Signal<In, Bits<GROUP>>,
    /// The broad phase can take a box (the grid: a record is free; always, without it).
    pub credit: Signal<In, Bit>,
    /// The stream's ready: the load is on and a box would be taken (or dropped, the tables
    /// full).
    pub obb_ready: Signal<Out, Bit>,
    /// A box is taken and stored this clock, at `index`.
    pub accept: Signal<Out, Bit>,
    /// The table address of the box taken.
    pub index: Signal<Out, Bits<A>>,
    /// Boxes in the tables (the resident ones included).
    pub loaded: Signal<Out, Bits<C>>,
    /// The load is on (from the clock after `frame_start` until the load ends).
    pub loading: Signal<Out, Bit>,
    /// The load ends this clock.
    pub ended: Signal<Out, Bit>,
    /// The frame is incomplete from this clock: a box beyond the capacity, or a resident box
    /// out of place.
    pub refused: Signal<Out, Bit>,
    /// A frame begins this clock: a `frame_start` with no frame under way, or `restart_go`.
    pub frame_begin: Signal<Out, Bit>,
    /// With `frame_begin`: the frame is an update frame.
    pub update: Signal<Out, Bit>,
    /// A `frame_start` aborts the frame under way this clock.
    pub frame_abort: Signal<Out, Bit>,
    /// With `frame_begin`: the index of the frame's first box (after the resident ones, in a
    /// haptic frame; else 0).
    pub first: Signal<Out, Bits<C>>,
    // Configuration: the last index a box may take (`capacity - 1`); the resident groups, bit
    // g for group g, and whether there are any.
    last_slot: Constant<Bits<C>>,
    resident_set: Constant<Bits<8>>,
    has_resident: Constant<Bit>,
    // Registered rather than decoded, so that taking a box (the write enable and address of
    // the 15 box tables) is one LUT from registers: the load is on (`ready`), the tables have
    // room (`room`, `loaded != capacity`).
    ready: DFF<Bit>,
    room: DFF<Bit>,
    count: DFF<Bits<C>>,
    // The resident boxes the last update frame loaded, and whether the tables had room after
    // them; a haptic frame; a box of a streamed group came.
    res_loaded: DFF<Bits<C>>,
    res_room: DFF<Bit>,
    haptic: DFF<Bit>,
    streamed_seen: DFF<Bit>,
    // An update frame has loaded whole since the last one began; a resident box was refused
    // in this frame.
    res_ok: DFF<Bit>,
    spoiled: DFF<Bit>,
    // The resident set shifted to the arriving box's group; the box is of a resident group.
    // (rust-hdl writes a bit of an expression as Verilog cannot read: a local first.)
    res_row: Signal<Local, Bits<8>>,
    obb_res: Signal<Local, Bit>,
}

impl<const A: usize, const C: usize> BoxLoad<A, C> {
    /// The load for `cfg`'s capacity and resident groups.
    pub fn new(cfg: &HwConfig) -> BoxLoad<A, C> {
        let resident_set: u64 = cfg.resident_groups.iter().map(|&g| 1u64 << g).sum();
        BoxLoad {
            clock: Default::default(),
            frame_start: Default::default(),
            frame_update: Default::default(),
            live: Default::default(),
            restart_go: Default::default(),
            restart_update: Default::default(),
            obb_valid: Default::default(),
            obb_last: Default::default(),
            obb_group: Default::default(),
            credit: Default::default(),
            obb_ready: Default::default(),
            accept: Default::default(),
            index: Default::default(),
            loaded: Default::default(),
            loading: Default::default(),
            ended: Default::default(),
            refused: Default::default(),
            first: Default::default(),
            last_slot: Constant::new(u64::from(cfg.capacity - 1).into()),
            resident_set: Constant::new(resident_set.into()),
            has_resident: Constant::new(resident_set != 0),
            ready: Default::default(),
            room: Default::default(),
            count: Default::default(),
            res_loaded: Default::default(),
            res_room: Default::default(),
            haptic: Default::default(),
            streamed_seen: Default::default(),
            res_ok: Default::default(),
            spoiled: Default::default(),
            frame_begin: Default::default(),
            update: Default::default(),
            frame_abort: Default::default(),
            res_row: Default::default(),
            obb_res: Default::default(),
        }
    }
}

impl<const A: usize, const C: usize> Logic for BoxLoad<A, C> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            ready,
            room,
            count,
            res_loaded,
            res_room,
            haptic,
            streamed_seen,
            res_ok,
            spoiled
        );
        self.frame_begin.next = (self.frame_start.val() & !self.live.val()) | self.restart_go.val();
        self.frame_abort.next = self.frame_start.val() & self.live.val() & !self.restart_go.val();
        // A frame_start with restart_go is the later word.
        self.update.next = self.restart_update.val();
        if self.frame_start.val() {
            self.update.next = self.frame_update.val();
        }
        // A box over capacity is taken (and dropped) whatever the credit says; nothing is taken
        // on the clock of an abort.
        self.obb_ready.next =
            self.ready.q.val() & !self.frame_start.val() & (self.credit.val() | !self.room.q.val());
        self.accept.next = self.obb_ready.val() & self.obb_valid.val() & self.room.q.val();
        self.index.next = bit_cast::<A, C>(self.count.q.val());
        self.loaded.next = self.count.q.val();
        self.loading.next = self.ready.q.val();
        if self.accept.val() {
            self.count.d.next = self.count.q.val() + 1;
            if self.count.q.val() == self.last_slot.val() {
                self.room.d.next = false;
            }
        }
        self.res_row.next = self.resident_set.val() >> bit_cast::<8, GROUP>(self.obb_group.val());
        self.obb_res.next = self.has_resident.val() & self.res_row.val().get_bit(0);
        self.refused.next = self.ready.q.val()
            & ((self.obb_valid.val() & !self.room.q.val())
                | (self.haptic.q.val() & !self.res_ok.q.val()));
        if self.accept.val() {
            if self.obb_res.val() {
                if self.haptic.q.val() | self.streamed_seen.q.val() {
                    self.refused.next = true;
                } else {
                    self.res_loaded.d.next = self.count.q.val() + 1;
                    self.res_room.d.next = self.count.q.val() != self.last_slot.val();
                }
            } else {
                self.streamed_seen.d.next = true;
            }
        }
        // A resident box refused leaves the resident lists unsure: no haptic frame until the
        // next update frame has loaded whole.
        if self.refused.val() & self.obb_res.val() {
            self.spoiled.d.next = true;
            self.res_ok.d.next = false;
        }
        // The last box taken, or the end marker alone.
        self.ended.next = self.ready.q.val()
            & !self.frame_start.val()
            & self.obb_last.val()
            & (self.obb_ready.val() | !self.obb_valid.val());
        if self.ended.val() {
            self.ready.d.next = false;
            // An update frame loaded whole: haptic frames may follow.
            if !self.haptic.q.val()
                & !self.spoiled.q.val()
                & !(self.refused.val() & self.obb_res.val())
            {
                self.res_ok.d.next = true;
            }
        }
        if self.frame_abort.val() {
            self.ready.d.next = false;
        }
        self.first.next = 0.into();
        if self.has_resident.val() & !self.update.val() {
            self.first.next = self.res_loaded.q.val();
        }
        if self.frame_begin.val() {
            self.ready.d.next = true;
            self.room.d.next = true;
            self.count.d.next = 0.into();
            self.streamed_seen.d.next = false;
            self.spoiled.d.next = false;
            self.haptic.d.next = self.has_resident.val() & !self.update.val();
            if self.has_resident.val() {
                if self.update.val() {
                    self.res_loaded.d.next = 0.into();
                    self.res_room.d.next = true;
                    self.res_ok.d.next = false;
                } else {
                    // A haptic frame's boxes follow the resident ones.
                    self.count.d.next = self.res_loaded.q.val();
                    self.room.d.next = self.res_room.q.val();
                }
            }
        }
    }
}
