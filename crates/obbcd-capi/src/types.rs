//! The values that cross the C ABI, laid out as C lays them out.

/// An oriented box: its center, three orthonormal axes (one per row) and the half-lengths
/// along them. Lengths in the scene's unit (mm in the surgical scene); coordinates within
/// ±1e6, axes orthonormal to 1e-6.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ObbcdBox {
    pub center: [f64; 3],
    pub axes: [[f64; 3]; 3],
    pub half: [f64; 3],
}

/// A rigid pose: a moving group's boxes, given in the group's own frame, are placed in the
/// world as `x_world = rotation x + translation` (rotation by rows: a box's center `c` goes to
/// `rotation c + translation`, each of its axes `a` to `rotation a`). The rotation must be
/// orthonormal within 1e-5 (as a box's axes), every entry finite, the translation and every
/// placed center within ±1e6.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ObbcdPose {
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
}

/// A colliding pair: box `index_a` of group `group_a` and box `index_b` of group `group_b`
/// (indices in the order the group's boxes were last set). The first box is the one earlier
/// in the engine's order: static groups ascending, then the other groups ascending.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct ObbcdPair {
    pub group_a: u32,
    pub index_a: u32,
    pub group_b: u32,
    pub index_b: u32,
}

/// A pair's contact: the unit normal of the axis of least overlap, pointing from the pair's
/// first box to its second, and the penetration depth along it (0 for boxes that touch).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ObbcdContact {
    pub normal: [f64; 3],
    pub depth: f64,
}

/// What a call did. On anything but `OBBCD_STATUS_OK`, `obbcd_last_error` says why.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObbcdStatus {
    Ok = 0,
    /// A pointer argument that must not be NULL was NULL.
    NullArgument = 1,
    /// An argument outside its domain: a bad group mask, too many boxes, too many threads or
    /// threads that cannot start, a string that is not UTF-8, a pose refused.
    InvalidArgument = 2,
    /// A box with a NaN, an infinity, a coordinate beyond ±1e6 (also where its group's pose
    /// places it), a negative half-length or axes that are not orthonormal. Nothing was
    /// changed.
    InvalidBox = 3,
    /// A bug in obbcd, caught at the boundary (no panic crosses it). The engine must not be
    /// used again, only freed.
    Internal = 4,
}
