//! What a broad phase did on a frame, and the grid's clocks: the plain records the broad
//! phases fill (`broad.rs`, `grid_clocks.rs`) and the cycle model reads (`cycles.rs`).

/// The work of one broad phase on one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BroadWork {
    /// Grid: boxes larger than a cell, met on the slow path after the load.
    pub large: u64,
    /// Grid: a large box's window was too wide for the slow path (`grid::MAX_WINDOW`): the
    /// frame's pairs are incomplete, and the core flags it.
    pub incomplete: bool,
    /// Radix passes, summed over the sorts.
    pub passes: u64,
    /// Keys moved by the radix passes: each sort's length times its passes, summed.
    pub moves: u64,
    /// Clocks of the sorts (`cycles::sort_cycles`), summed.
    pub sort_cycles: u64,
    /// Index pairs the broad phase visits (one per clock per lane).
    pub visits: u64,
    /// Clocks of the walk (`walk_cycles`).
    pub walk: u64,
    /// Pairs sent to the SAT stage.
    pub sat_tests: u64,
    /// Grid: the load and the walk, which overlap (`grid_clocks`).
    pub grid: Option<GridClocks>,
}

/// The grid's clocks, from the first load clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridClocks {
    /// Until the last keys are in the key table.
    pub load: u64,
    /// After the load, until every box has retired and the slow path is done.
    pub walk: u64,
    /// The rest: the clear of the list heads, the last verdicts.
    pub drain: u64,
}
