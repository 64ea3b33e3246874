//! The engine behind the C ABI, in safe Rust: boxes kept by group, the static groups resident in
//! their own grid (rebuilt only when one of them is set), the moving groups tested each frame,
//! and the pairs and contacts in buffers that are reused from frame to frame.

use crate::types::{ObbcdBox, ObbcdContact, ObbcdPair};
use obb_model::contact::contact;
use obb_model::engines::{Pair, Resident};
use obb_model::scene::MAX_OBBS;
use obb_model::{GroupMask, Obb};

/// The most worker threads an engine starts: far above any machine's use for one frame, and
/// low enough that a mistaken count fails at once instead of starting threads by the thousand.
pub const MAX_THREADS: usize = 256;

/// Where one group's boxes lie: in `statics` or `moving`, from `start`, `len` of them.
#[derive(Clone, Copy, Debug)]
struct Slot {
    group: u32,
    start: usize,
    len: usize,
}

/// One side (static or moving): its boxes, by group ascending, and the groups' slots.
#[derive(Default)]
struct Side {
    boxes: Vec<Obb>,
    slots: Vec<Slot>,
}

impl Side {
    /// Replaces `group`'s boxes with `new`: in place when the count is kept (no allocation),
    /// else the side is laid out again.
    fn set(&mut self, group: u32, new: impl ExactSizeIterator<Item = Obb>) {
        match self.slots.binary_search_by_key(&group, |s| s.group) {
            Ok(k) if self.slots[k].len == new.len() => {
                let s = self.slots[k];
                for (dst, b) in self.boxes[s.start..s.start + s.len].iter_mut().zip(new) {
                    *dst = b;
                }
            }
            Ok(k) => {
                let s = self.slots[k];
                let len = new.len();
                self.boxes.splice(s.start..s.start + s.len, new);
                self.slots[k].len = len;
                self.restart();
            }
            Err(k) => {
                let start = self.slots.get(k).map_or(self.boxes.len(), |s| s.start);
                let len = new.len();
                self.boxes.splice(start..start, new);
                self.slots.insert(k, Slot { group, start, len });
                self.restart();
            }
        }
    }

    /// How many boxes `group` has here (0 if none).
    fn count(&self, group: u32) -> usize {
        self.slots
            .binary_search_by_key(&group, |s| s.group)
            .map_or(0, |k| self.slots[k].len)
    }

    /// The slots' starts after a group changed its count.
    fn restart(&mut self) {
        let mut start = 0;
        for s in &mut self.slots {
            s.start = start;
            start += s.len;
        }
    }

    /// The group of box `k` of this side and its index inside the group.
    fn locate(&self, k: usize) -> (u32, u32) {
        let s = &self.slots[self.slots.partition_point(|s| s.start + s.len <= k)];
        (s.group, (k - s.start) as u32)
    }
}

/// The side holding `Resident`'s box `k` (the static boxes first, the moving ones after them)
/// and the box's index on that side.
fn side_of<'a>(statics: &'a Side, moving: &'a Side, k: u32) -> (&'a Side, usize) {
    let k = k as usize;
    match k.checked_sub(statics.boxes.len()) {
        None => (statics, k),
        Some(m) => (moving, m),
    }
}

/// Why a call was refused.
#[derive(Debug)]
pub enum Refusal {
    /// A parameter outside its domain (the message says which).
    Argument(String),
    /// A box that fails the scene's validation (the message names group, index and field).
    Box(String),
}

pub struct Engine {
    mask: GroupMask,
    /// The groups kept resident, sorted.
    static_groups: Vec<u32>,
    statics: Side,
    moving: Side,
    /// A static group changed since the last detection: the resident grid is rebuilt.
    statics_changed: bool,
    resident: Resident,
    pool: rayon::ThreadPool,
    raw: Vec<Pair>,
    pairs: Vec<ObbcdPair>,
    contacts: Vec<ObbcdContact>,
    /// `contacts` belongs to the current `pairs`.
    contacts_ready: bool,
}

impl Engine {
    /// An engine reporting the pairs `mask` allows; `static_groups` are kept resident; `threads`
    /// workers (0: one per core).
    pub fn new(mask: GroupMask, static_groups: &[u32], threads: usize) -> Result<Engine, Refusal> {
        if threads > MAX_THREADS {
            return Err(Refusal::Argument(format!(
                "threads is {threads}, more than the limit of {MAX_THREADS}"
            )));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|k| format!("obbcd-{k}"))
            .build()
            .map_err(|e| Refusal::Argument(format!("cannot start {threads} threads: {e}")))?;
        let mut static_groups = static_groups.to_vec();
        static_groups.sort_unstable();
        static_groups.dedup();
        let mut resident = Resident::default();
        resident.update_static(&[], &mask);
        Ok(Engine {
            mask,
            static_groups,
            statics: Side::default(),
            moving: Side::default(),
            statics_changed: false,
            resident,
            pool,
            raw: Vec::new(),
            pairs: Vec::new(),
            contacts: Vec::new(),
            contacts_ready: false,
        })
    }

    /// Replaces the boxes of `group`. Every box is checked first: on a refusal nothing changes.
    /// Otherwise the last detection's pairs and contacts are dropped (their indices may no
    /// longer name the same boxes).
    pub fn set_boxes(&mut self, group: u32, boxes: &[ObbcdBox]) -> Result<(), Refusal> {
        let obb = |b: &ObbcdBox| Obb {
            center: b.center,
            axes: b.axes,
            half: b.half,
            group,
        };
        for (i, b) in boxes.iter().enumerate() {
            obb(b)
                .validate(i)
                .map_err(|e| Refusal::Box(format!("group {group}: {e}")))?;
        }
        let is_static = self.static_groups.binary_search(&group).is_ok();
        let held = self.statics.boxes.len() + self.moving.boxes.len();
        let side = if is_static {
            &mut self.statics
        } else {
            &mut self.moving
        };
        let total = held - side.count(group) + boxes.len();
        if total > MAX_OBBS {
            return Err(Refusal::Argument(format!(
                "group {group}: {} boxes would make {total} in all, more than the limit of {MAX_OBBS}",
                boxes.len()
            )));
        }
        side.set(group, boxes.iter().map(obb));
        self.statics_changed |= is_static;
        self.raw.clear();
        self.pairs.clear();
        self.contacts.clear();
        self.contacts_ready = true;
        Ok(())
    }

    /// Finds the colliding pairs of the boxes set so far.
    pub fn detect(&mut self) -> &[ObbcdPair] {
        let Engine {
            mask,
            statics,
            moving,
            statics_changed,
            resident,
            pool,
            raw,
            ..
        } = self;
        pool.install(|| {
            if *statics_changed {
                resident.update_static(&statics.boxes, mask);
                *statics_changed = false;
            }
            resident.detect(&moving.boxes, raw);
        });
        let at = |k: u32| {
            let (side, i) = side_of(&self.statics, &self.moving, k);
            side.locate(i)
        };
        self.pairs.clear();
        self.pairs.extend(self.raw.iter().map(|&[i, j]| {
            let ((group_a, index_a), (group_b, index_b)) = (at(i), at(j));
            ObbcdPair {
                group_a,
                index_a,
                group_b,
                index_b,
            }
        }));
        self.contacts_ready = false;
        &self.pairs
    }

    /// The last detection's pairs (`&mut` as `contacts`, so that both are one kind of reader).
    pub fn pairs(&mut self) -> &[ObbcdPair] {
        &self.pairs
    }

    /// The contact of each of the last detection's pairs, computed on the first call after it.
    pub fn contacts(&mut self) -> &[ObbcdContact] {
        if !self.contacts_ready {
            let obb = |k: u32| {
                let (side, i) = side_of(&self.statics, &self.moving, k);
                &side.boxes[i]
            };
            self.contacts.clear();
            self.contacts.extend(self.raw.iter().map(|&[i, j]| {
                let c = contact(obb(i), obb(j));
                ObbcdContact {
                    normal: c.normal,
                    depth: c.depth,
                }
            }));
            self.contacts_ready = true;
        }
        &self.contacts
    }
}
