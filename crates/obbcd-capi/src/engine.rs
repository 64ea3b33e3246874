//! The engine behind the C ABI, in safe Rust: boxes kept by group, the static groups resident in
//! their own grid (rebuilt only when one of them is set), the moving groups placed by their
//! poses and tested each frame as the rigid bodies of `RigidResident`, and the pairs and
//! contacts in buffers that are reused from frame to frame.

use crate::types::{ObbcdBox, ObbcdContact, ObbcdPair};
use crate::workers::Workers;
use obb_model::contact::contact;
use obb_model::engines::{on_this_thread, Pair, RigidResident};
use obb_model::pose::Pose;
use obb_model::scene::{COORD_LIMIT, MAX_OBBS, ORTHO_TOL};
use obb_model::{GroupMask, Obb};

/// The most worker threads an engine starts: far above any machine's use for one frame, and
/// low enough that a mistaken count fails at once instead of starting threads by the thousand.
pub const MAX_THREADS: usize = 256;

/// Where one group's boxes lie: in `statics` or `moving`, from `start`, `len` of them; the
/// pose that places them in the world (the identity for static groups).
#[derive(Clone, Copy, Debug)]
struct Slot {
    group: u32,
    start: usize,
    len: usize,
    pose: Pose,
    /// Per axis, the largest |coordinate| of the boxes' centers: a pose keeps every placed
    /// center within `COORD_LIMIT` if `|t| + |R| reach` does.
    reach: [f64; 3],
}

/// One side (static or moving): its boxes, by group ascending, and the groups' slots.
#[derive(Default)]
struct Side {
    boxes: Vec<Obb>,
    slots: Vec<Slot>,
}

impl Side {
    /// Replaces `group`'s boxes with `new` (its pose kept; a new group's is the identity): in
    /// place when the count is kept (no allocation), else the side is laid out again. The
    /// group's slot, and whether the side was laid out again.
    fn set(
        &mut self,
        group: u32,
        new: impl ExactSizeIterator<Item = Obb>,
        reach: [f64; 3],
    ) -> (usize, bool) {
        let (k, relaid) = match self.slots.binary_search_by_key(&group, |s| s.group) {
            Ok(k) if self.slots[k].len == new.len() => {
                let s = self.slots[k];
                for (dst, b) in self.boxes[s.start..s.start + s.len].iter_mut().zip(new) {
                    *dst = b;
                }
                (k, false)
            }
            Ok(k) => {
                let s = self.slots[k];
                let len = new.len();
                self.boxes.splice(s.start..s.start + s.len, new);
                self.slots[k].len = len;
                self.restart();
                (k, true)
            }
            Err(k) => {
                let start = self.slots.get(k).map_or(self.boxes.len(), |s| s.start);
                let len = new.len();
                self.boxes.splice(start..start, new);
                let slot = Slot {
                    group,
                    start,
                    len,
                    pose: Pose::IDENTITY,
                    reach: [0.0; 3],
                };
                self.slots.insert(k, slot);
                self.restart();
                (k, true)
            }
        };
        self.slots[k].reach = reach;
        (k, relaid)
    }

    /// The boxes of slot `k`.
    fn boxes_of(&self, k: usize) -> &[Obb] {
        let s = &self.slots[k];
        &self.boxes[s.start..s.start + s.len]
    }

    /// The pose of `group`, if it has boxes here.
    fn pose(&self, group: u32) -> Option<Pose> {
        self.slots
            .binary_search_by_key(&group, |s| s.group)
            .ok()
            .map(|k| self.slots[k].pose)
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

    /// The slot of box `k` of this side.
    fn slot_of(&self, k: usize) -> &Slot {
        &self.slots[self.slots.partition_point(|s| s.start + s.len <= k)]
    }

    /// The group of box `k` of this side and its index inside the group.
    fn locate(&self, k: usize) -> (u32, u32) {
        let s = self.slot_of(k);
        (s.group, (k - s.start) as u32)
    }

    /// Box `k` of this side placed in the world by its group's pose.
    fn placed(&self, k: usize) -> Obb {
        self.slot_of(k).pose.apply(&self.boxes[k])
    }
}

/// Per axis, the largest |coordinate| of the boxes' centers.
fn reach(boxes: &[ObbcdBox]) -> [f64; 3] {
    boxes.iter().fold([0.0; 3], |r, b| {
        std::array::from_fn(|x| r[x].max(b.center[x].abs()))
    })
}

/// Refuses a pose the engine cannot honour: an entry not finite, a rotation not orthonormal
/// within `ORTHO_TOL` (as a box's axes), or one that places a box's center (as the engine
/// computes it) beyond `COORD_LIMIT`. `reach` is the boxes' (see [`Slot`]).
fn check_pose(
    group: u32,
    pose: &Pose,
    boxes: impl Iterator<Item = Obb>,
    reach: [f64; 3],
) -> Result<(), String> {
    let entries = pose.rotation.iter().flatten().chain(&pose.translation);
    if let Some(v) = entries.clone().find(|v| !v.is_finite()) {
        return Err(format!(
            "group {group}: the pose has {v}, not a finite number"
        ));
    }
    if let Some(v) = entries.clone().find(|v| v.abs() > COORD_LIMIT) {
        return Err(format!(
            "group {group}: the pose has {v}, beyond ±{COORD_LIMIT:e}"
        ));
    }
    let rotation = Obb {
        center: [0.0; 3],
        axes: pose.rotation,
        half: [0.0; 3],
        group,
    };
    let err = rotation.ortho_error();
    if err > ORTHO_TOL {
        return Err(format!(
            "group {group}: the pose's rotation is not orthonormal: an entry of R·Rᵀ - I is \
             {err:.3e}, the limit is {ORTHO_TOL:e}"
        ));
    }
    // |R c + t| <= |t| + |R| reach, widened for the rounding of the computed center; only a
    // pose near the limit has its boxes placed one by one.
    let within = (0..3).all(|x| {
        let bound = pose.translation[x].abs()
            + (0..3)
                .map(|j| pose.rotation[x][j].abs() * reach[j])
                .sum::<f64>();
        bound * (1.0 + 16.0 * f64::EPSILON) <= COORD_LIMIT
    });
    if within {
        return Ok(());
    }
    for (i, b) in boxes.enumerate() {
        let c = pose.apply(&b).center;
        if c.iter().any(|v| v.abs() > COORD_LIMIT) {
            return Err(format!(
                "group {group}: the pose places box {i}'s center at {c:?}, beyond ±{COORD_LIMIT:e}"
            ));
        }
    }
    Ok(())
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
    /// The static boxes resident, the moving groups its bodies (one per slot of `moving`).
    rigid: RigidResident,
    /// The moving groups' poses, gathered for a detection.
    poses: Vec<Pose>,
    /// The workers of a static group's rebuild, when there are two or more.
    pool: Option<Workers>,
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
        // One thread needs no pool: every detection then runs on the calling thread.
        let pool = match threads {
            1 => None,
            _ => Workers::new(threads)
                .map(|w| (w.pool().current_num_threads() > 1).then_some(w))
                .map_err(|e| Refusal::Argument(format!("cannot start {threads} threads: {e}")))?,
        };
        let mut static_groups = static_groups.to_vec();
        static_groups.sort_unstable();
        static_groups.dedup();
        let mut rigid = RigidResident::default();
        rigid.update_static(&[], &mask);
        Ok(Engine {
            mask,
            static_groups,
            statics: Side::default(),
            moving: Side::default(),
            statics_changed: false,
            rigid,
            poses: Vec::new(),
            pool,
            raw: Vec::new(),
            pairs: Vec::new(),
            contacts: Vec::new(),
            contacts_ready: false,
        })
    }

    /// Replaces the boxes of `group` (in the group's frame: its pose, kept, places them).
    /// Every box is checked first, and placed by the group's pose: on a refusal nothing
    /// changes. Otherwise the last detection's pairs and contacts are dropped (their indices
    /// may no longer name the same boxes).
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
        let reach = reach(boxes);
        if let Some(pose) = side.pose(group) {
            check_pose(group, &pose, boxes.iter().map(obb), reach).map_err(Refusal::Box)?;
        }
        let (k, relaid) = side.set(group, boxes.iter().map(obb), reach);
        match (is_static, relaid) {
            (true, _) => self.statics_changed = true,
            (false, true) => {
                let bodies: Vec<&[Obb]> = (0..self.moving.slots.len())
                    .map(|k| self.moving.boxes_of(k))
                    .collect();
                self.rigid.set_bodies(&bodies);
            }
            (false, false) => self.rigid.set_body(k, self.moving.boxes_of(k)),
        }
        self.drop_results();
        Ok(())
    }

    /// Places the boxes of the moving group `group` by `pose` from the next detection on
    /// (`x_world = R x + t`). Refused, changing nothing, for a static group, a group never
    /// set, or a pose `check_pose` refuses. The last detection's pairs and contacts are
    /// dropped.
    pub fn set_pose(&mut self, group: u32, pose: Pose) -> Result<(), Refusal> {
        if self.static_groups.binary_search(&group).is_ok() {
            return Err(Refusal::Argument(format!(
                "group {group} is static: its boxes are set, not posed"
            )));
        }
        let Ok(k) = self.moving.slots.binary_search_by_key(&group, |s| s.group) else {
            return Err(Refusal::Argument(format!(
                "group {group} has no boxes: set them before its pose"
            )));
        };
        let reach = self.moving.slots[k].reach;
        check_pose(group, &pose, self.moving.boxes_of(k).iter().cloned(), reach)
            .map_err(Refusal::Argument)?;
        self.moving.slots[k].pose = pose;
        self.drop_results();
        Ok(())
    }

    /// Forgets the last detection's pairs and contacts.
    fn drop_results(&mut self) {
        self.raw.clear();
        self.pairs.clear();
        self.contacts.clear();
        self.contacts_ready = true;
    }

    /// Finds the colliding pairs of the boxes set so far, each moving group placed by its pose.
    pub fn detect(&mut self) -> &[ObbcdPair] {
        let Engine {
            mask,
            statics,
            moving,
            statics_changed,
            rigid,
            poses,
            pool,
            raw,
            ..
        } = self;
        // A static group's rebuild (the tissue's, some milliseconds) is shared on the pool; any
        // other detection runs on the calling thread: handed to the pool and back, a haptic
        // frame of 0.02 ms took 0.1 to 0.24 ms (median over the frames) on one thread, the
        // two wake-ups of a halted CPU of this project's virtual machines.
        let rebuild = *statics_changed;
        let frame = || {
            if rebuild {
                rigid.update_static(&statics.boxes, mask);
                *statics_changed = false;
            }
            poses.clear();
            poses.extend(moving.slots.iter().map(|s| s.pose));
            rigid.detect(poses, raw);
        };
        match pool {
            Some(workers) if rebuild => workers.pool().install(frame),
            _ => on_this_thread(frame),
        }
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
                side.placed(i)
            };
            self.contacts.clear();
            self.contacts.extend(self.raw.iter().map(|&[i, j]| {
                let c = contact(&obb(i), &obb(j));
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
