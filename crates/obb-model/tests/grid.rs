//! The hardware grid's model (`fixed/grid.rs`, `fixed/grid_clocks.rs`): the window's cells fall
//! in 27 different banks, hash collisions cost visits and never a pair, large boxes take the
//! slow path, and the clock model follows its rules on frames worked out by hand.
//! (`tests/fixed.rs` checks on random scenes and configurations that the grid emits every pair
//! whose keys overlap, each once.)

use obb_model::fixed::cycles::{
    LAT_BROAD, LAT_GRID_CHECK, LAT_KEY_WRITE, LAT_PROBE, LAT_PROJECT, LAT_SAT,
};
use obb_model::fixed::grid::{GridShape, BANKS};
use obb_model::fixed::grid_clocks::grid_schedule;
use obb_model::fixed::{BroadPhase, HwConfig, ModelFrame};
use obb_model::generate::{slabs, surgical, SURGICAL_DEFAULT_N};
use obb_model::{GroupMask, Obb, Scene};
use proptest::prelude::*;

use crate::common;

fn grid(cfg: HwConfig) -> HwConfig {
    HwConfig {
        broad_phase: BroadPhase::Grid,
        ..cfg
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The 27 banks hold each cell of a small box's window exactly once, and nothing else.
    #[test]
    fn window_cells_fall_in_distinct_banks(
        g in 0u32..12, lo in proptest::array::uniform3(0u64..1 << 20), ext in proptest::array::uniform3(0u64..=4096),
    ) {
        let shape = GridShape { cell_bits: g, coord_bits: 20 - g + 1, hash_bits: 10, groups: 3 };
        let hi = [0, 1, 2].map(|x| (lo[x] + ext[x].min(1 << g)).min((1 << 20) - 1));
        prop_assert!(shape.is_small(&lo, &hi));
        let (first, last) = shape.window(&lo, &hi);
        let mut cells: Vec<[u64; 3]> =
            (0..BANKS).filter_map(|b| GridShape::cell_in_bank(b, &first, &last)).collect();
        for (b, c) in (0..BANKS).filter_map(|b| GridShape::cell_in_bank(b, &first, &last).map(|c| (b, c))) {
            prop_assert_eq!(GridShape::bank(&c), b);
        }
        let mut window = Vec::new();
        for z in first[2]..=last[2] {
            for y in first[1]..=last[1] {
                for x in first[0]..=last[0] {
                    window.push([x, y, z]);
                }
            }
        }
        prop_assert!((8..=27).contains(&window.len()));
        cells.sort_unstable();
        window.sort_unstable();
        prop_assert_eq!(cells, window);
        // The box's own home cell is in its window; a bucket fits its bits.
        let home = shape.home(&lo);
        prop_assert!((0..3).all(|x| first[x] <= home[x] && home[x] <= last[x]));
        prop_assert!(shape.bucket(&home) < 1 << 10);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Boxes spread over many cells, with few buckets (most lists mixed, some owned by another
    /// cell), small cells (some boxes large), a list per group or one for all, and every mask:
    /// the grid reports brute force's pairs, each once.
    #[test]
    fn spread_scenes_with_few_buckets(
        obbs in proptest::collection::vec(common::obb(40.0, 2.5, 3), 0..80),
        cell_exp in 0i32..=3,
        grid_hash_bits in 1u32..=4,
        lanes in prop::sample::select(vec![1u32, 2, 4, 8]),
        grid_group_lists in any::<bool>(),
        mask in common::mask(),
    ) {
        let scene = Scene { obbs };
        let cfg = grid(HwConfig {
            grid_cell_mm: 2f64.powi(cell_exp),
            grid_hash_bits,
            lanes,
            grid_group_lists,
            // One list needs a configured mask that pairs every group; the walk takes `mask`.
            groups: GroupMask::All,
            ..HwConfig::default()
        });
        let m = ModelFrame::new(&scene, &cfg).unwrap();
        let run = m.detect(BroadPhase::Grid, &mask);
        let brute = m.detect(BroadPhase::Brute, &mask);
        prop_assert_eq!(&run.pairs, &brute.pairs);
        prop_assert_eq!(run.reported(), brute.reported(), "each pair once");
        prop_assert_eq!(run.work.sat_tests, brute.work.sat_tests);
        lanes_keep_their_rules(&m, &mask)?;
    }
}

/// The schedule of `frame`'s grid walk under `mask` keeps the lanes' rules: a visit of box `j`
/// is made by lane `j % lanes` (box `j` is on that lane's lists and chain), each lane makes at
/// most one visit a clock and its visits in the walk's order, and at most one SAT test is
/// issued a clock, never on a clock that accepts a box; the SAT takes the SAT tests in the
/// order they are issued.
fn lanes_keep_their_rules(frame: &ModelFrame, mask: &GroupMask) -> Result<(), TestCaseError> {
    let walk = frame.grid_walk(mask);
    let s = grid_schedule(&walk);
    let lanes = walk.lanes;
    let mut last = vec![0u64; lanes];
    let mut per_clock = std::collections::HashSet::new();
    for (&(_, j), &t) in walk.pairs.iter().zip(&s.visits) {
        let lane = j as usize % lanes;
        prop_assert!(
            t > last[lane],
            "lane {} visits at {} after {}",
            lane,
            t,
            last[lane]
        );
        prop_assert!(per_clock.insert((lane, t)));
        last[lane] = t;
    }
    let mut issues = s.issues.clone();
    issues.sort_unstable();
    issues.dedup();
    prop_assert_eq!(issues.len(), s.issues.len(), "one issue a clock");
    prop_assert!(issues.iter().all(|t| s.accepts.binary_search(t).is_err()));
    let tests: Vec<(u32, u32)> = walk
        .pairs
        .iter()
        .zip(&walk.passes)
        .filter(|(_, &pass)| pass)
        .map(|(&p, _)| p)
        .collect();
    let mut by_issue: Vec<(u64, (u32, u32))> = s.issues.iter().copied().zip(tests).collect();
    by_issue.sort_unstable();
    let run = frame.detect(BroadPhase::Grid, mask);
    let sat: Vec<[u32; 2]> = by_issue
        .iter()
        .map(|&(_, (i, j))| [i.min(j), i.max(j)])
        .filter(|p| run.pairs.binary_search(p).is_ok())
        .collect();
    prop_assert_eq!(sat, run.stream);
    Ok(())
}

/// `n` boxes in the same place, all in group 0.
fn coincident(n: u64) -> Scene {
    Scene {
        obbs: (0..n)
            .map(|_| Obb::aligned([1.0; 3], [0.25; 3], 0))
            .collect(),
    }
}

/// Ten coincident boxes (all pairs): box k visits the k boxes before it. Worked out by hand from
/// the rules in `grid_clocks.rs`.
#[test]
fn clock_model_by_hand() {
    let n = 10u64;
    let scene = coincident(n);
    let cfg = grid(HwConfig::default());
    let frame = ModelFrame::new(&scene, &cfg).unwrap();
    let run = frame.detect(BroadPhase::Grid, &GroupMask::All);
    assert_eq!(run.work.visits, n * (n - 1) / 2);
    assert_eq!(run.pairs.len() as u64, n * (n - 1) / 2);
    // Box k is accepted at clock k + 1; its one list is the walker's LAT_PROJECT + LAT_PROBE
    // later (the record, then the enumerator's load, choice and write). Box 1's one visit comes
    // then. The enumerator takes three clocks a record (load, choose, write: it is free the
    // clock after its write), so the walker waits two clocks after box 1's one visit and one
    // after box 2's two; each later list (three visits or more) is queued before the walker is
    // free, so the other 42 visits run back to back. The last record retires the clock after
    // its last visit; the clock after that has nothing in flight, and the walk is over on the
    // next (the idle flag is a register). No box is accepted once the
    // SAT tests come out of their queue, so each issues LAT_GRID_CHECK after its visit.
    let first_visit = 2 + LAT_PROJECT + LAT_PROBE;
    let last_visit = first_visit + run.work.visits + 2;
    let walked = last_visit + 3;
    let schedule = grid_schedule(&frame.grid_walk(&GroupMask::All));
    let mut visits = vec![first_visit, first_visit + 3, first_visit + 4];
    visits.extend(first_visit + 6..=last_visit);
    assert_eq!(schedule.visits, visits);
    assert_eq!(
        schedule.issues,
        schedule
            .visits
            .iter()
            .map(|v| v + LAT_GRID_CHECK)
            .collect::<Vec<_>>()
    );
    assert_eq!(schedule.walked, walked);
    let load = n + LAT_PROJECT + LAT_KEY_WRITE;
    let clear = 1 << cfg.grid_hash_bits;
    let c = run.cycles;
    assert_eq!((c.load, c.sort, c.walk), (load, 0, walked - load));
    // The block sees the walk over on the clock after it and clears from the next.
    assert_eq!(c.total, walked + 1 + clear);

    // Three boxes, cross-group: 0 and 1 touch, 2 is far. Box 1 visits box 0 on the first clock
    // its list is the walker's; box 2 has no record and retires at K + 6 (its probe clock K + 5,
    // registered; before that visit); box 1 retires the clock after its visit, and the walk is
    // over two clocks later.
    let scene = Scene {
        obbs: vec![
            Obb::aligned([0.0; 3], [0.5; 3], 0),
            Obb::aligned([1.0, 0.0, 0.0], [0.5; 3], 1),
            Obb::aligned([40.0, 0.0, 0.0], [0.5; 3], 1),
        ],
    };
    let frame = ModelFrame::new(&scene, &cfg).unwrap();
    let run = frame.run();
    assert_eq!(run.pairs, vec![[0, 1]]);
    assert_eq!(run.work.visits, 1);
    let visit = 2 + LAT_PROJECT + LAT_PROBE;
    let schedule = grid_schedule(&frame.grid_walk(&cfg.groups));
    assert_eq!(schedule.visits, vec![visit]);
    assert_eq!(schedule.walked, visit + 3);
    assert_eq!(run.cycles.total, visit + 4 + clear);
}

/// Three coincident boxes on two lanes (all pairs), worked out by hand from the rules in
/// `grid_clocks.rs`: box 1 (lane 1) visits box 0 on lane 0; box 2 (lane 0) visits box 0 on lane
/// 0 and box 1 on lane 1, which is free and walks it first.
#[test]
fn clock_model_of_two_lanes_by_hand() {
    let cfg = grid(HwConfig {
        lanes: 2,
        ..HwConfig::default()
    });
    let frame = ModelFrame::new(&coincident(3), &cfg).unwrap();
    let walk = frame.grid_walk(&GroupMask::All);
    // The walk's order: record by record, lane by lane.
    assert_eq!(walk.pairs, vec![(1, 0), (2, 0), (2, 1)]);
    assert_eq!(walk.visits, vec![0, 0, 1, 0, 1, 1]);
    // Box k is accepted at clock k + 1. Box 1's list is lane 0's walker's LAT_PROJECT +
    // LAT_PROBE after its accept. Lane 0's enumerator writes box 1's list on the clock before
    // that visit and is free from the next: it loads box 2's record then, chooses on the next
    // clock and writes on the one after, and its walker visits the clock after that. Lane 1
    // loads box 2's record when it is ready (it has held none), so its visit comes LAT_PROBE
    // after box 2's keys.
    let first = 2 + LAT_PROJECT + LAT_PROBE;
    let s = grid_schedule(&walk);
    assert_eq!(s.accepts, vec![1, 2, 3]);
    assert_eq!(s.visits, vec![first, first + 3, first + 1]);
    // Each SAT test issues LAT_GRID_CHECK after its visit (no box is accepted then), so the
    // SAT takes lane 1's before lane 0's second.
    assert_eq!(
        s.issues,
        s.visits
            .iter()
            .map(|v| v + LAT_GRID_CHECK)
            .collect::<Vec<_>>()
    );
    let run = frame.detect(BroadPhase::Grid, &GroupMask::All);
    assert_eq!(run.stream, vec![[0, 1], [1, 2], [0, 2]]);
    // Lane 0 retires box 2 the clock after its last visit; the walk is over two clocks later
    // (the idle flag is a register).
    assert_eq!(s.walked, first + 6);
}

/// 200 coincident boxes: the walker falls behind, the boxes waiting for it use up the credits,
/// and the load waits (no record is lost: every pair is reported once).
#[test]
fn credits_hold_the_load_back() {
    let n = 200u64;
    let scene = coincident(n);
    let run = ModelFrame::new(&scene, &grid(HwConfig::default()))
        .unwrap()
        .detect(BroadPhase::Grid, &GroupMask::All);
    assert_eq!(run.reported(), n * (n - 1) / 2);
    assert!(
        run.cycles.load > n + LAT_PROJECT + LAT_KEY_WRITE + 1_000,
        "{:?}",
        run.cycles
    );
    // One visit per clock at most, and every SAT test waits for the load to leave port A free.
    assert!(run.cycles.total >= run.work.visits + LAT_PROJECT + LAT_PROBE + LAT_BROAD + LAT_SAT);
}

/// With two buckets per bank every list is mixed: more visits, the same pairs, each once.
#[test]
fn hash_collisions_cost_visits_not_pairs() {
    // 2,000 boxes tessellate the surgical surfaces coarsely: 8 mm cells hold them all.
    let scene = surgical(2_000, 3).unwrap();
    let mask = GroupMask::All;
    let run = |hash_bits| {
        let cfg = grid(HwConfig {
            grid_hash_bits: hash_bits,
            grid_cell_mm: 8.0,
            ..HwConfig::default()
        });
        ModelFrame::new(&scene, &cfg)
            .unwrap()
            .detect(BroadPhase::Grid, &mask)
    };
    let (fine, coarse) = (run(10), run(1));
    let brute = ModelFrame::new(&scene, &HwConfig::default())
        .unwrap()
        .detect(BroadPhase::Brute, &mask);
    assert_eq!(fine.work.large, 0);
    assert_eq!(fine.pairs, brute.pairs);
    assert_eq!(coarse.pairs, brute.pairs);
    assert_eq!(coarse.work.sat_tests, fine.work.sat_tests);
    assert_eq!(coarse.reported(), fine.reported(), "each pair once");
    assert!(
        coarse.work.visits > 2 * fine.work.visits,
        "{} vs {}",
        coarse.work.visits,
        fine.work.visits
    );
}

/// Boxes wider than a cell: the slow path meets every pair of them, with small boxes and with
/// each other, once; a window wider than `MAX_WINDOW` cells makes the frame incomplete, and
/// what it did report is true.
#[test]
fn large_boxes_take_the_slow_path() {
    let scene = slabs();
    // 2 mm cells: three large boxes, whose windows are read in rounds; 1/2 mm cells: every box
    // is large, every window within MAX_WINDOW; 1/64 mm cells: windows too wide.
    for (cell, large, whole) in [(2.0, 3, true), (0.5, 43, true), (1.0 / 64.0, 43, false)] {
        for (mask, hash_bits, lanes) in [
            (GroupMask::All, 1, 1),
            (GroupMask::All, 10, 1),
            (GroupMask::Cross, 10, 1),
            ("0-2,2-3".parse().unwrap(), 2, 1),
            (GroupMask::All, 2, 4),
            (GroupMask::Cross, 10, 8),
        ] {
            let cfg = grid(HwConfig {
                grid_cell_mm: cell,
                grid_groups: 4,
                grid_hash_bits: hash_bits,
                lanes,
                ..HwConfig::default()
            });
            let m = ModelFrame::new(&scene, &cfg).unwrap();
            let run = m.detect(BroadPhase::Grid, &mask);
            let brute = m.detect(BroadPhase::Brute, &mask);
            assert_eq!(run.work.large, large);
            assert_eq!(run.work.incomplete, !whole, "cells of {cell} mm");
            if whole {
                assert_eq!(run.pairs, brute.pairs, "{mask}");
                assert_eq!(run.reported(), brute.reported(), "{mask}: each pair once");
                assert!(run.pairs.iter().any(|p| p[0] == 5 || p[1] == 5));
                lanes_keep_their_rules(&m, &mask).unwrap();
            } else {
                assert!(run.pairs.iter().all(|p| brute.pairs.contains(p)));
            }
        }
    }
}

/// The surgical scene's cross-group frame fits the 25,000-clock budget (10 kHz at 4 ns) in the
/// model, which the core is to match clock for clock.
#[test]
fn surgical_cross_group_fits_the_budget() {
    let scene = surgical(SURGICAL_DEFAULT_N, 1).unwrap();
    let cfg = grid(HwConfig::default());
    let run = ModelFrame::new(&scene, &cfg).unwrap().run();
    assert_eq!(run.work.large, 0);
    assert!(
        run.cycles.total <= 25_000,
        "{:?} {:?}",
        run.cycles,
        run.work
    );
}

/// All pairs of the surgical scene fit the 125,000-clock budget (2 kHz at 4 ns) on eight lanes
/// with 2^7 buckets a lane (the list heads' size of one lane with 2^10), where one lane makes
/// one visit a clock and takes more than three times as long.
#[test]
fn surgical_all_pairs_fit_the_budget_on_eight_lanes() {
    let scene = surgical(SURGICAL_DEFAULT_N, 1).unwrap();
    let run = |lanes, grid_hash_bits| {
        let cfg = grid(HwConfig {
            groups: GroupMask::All,
            lanes,
            grid_hash_bits,
            ..HwConfig::default()
        });
        ModelFrame::new(&scene, &cfg).unwrap().run()
    };
    let (one, eight) = (run(1, 10), run(8, 7));
    assert_eq!(one.pairs, eight.pairs);
    assert!(eight.cycles.total <= 125_000, "{:?}", eight.cycles);
    assert!(
        one.cycles.total > 3 * eight.cycles.total,
        "{:?}",
        one.cycles
    );
}

#[test]
fn grid_keys_are_checked() {
    let bad = |text: &str| HwConfig::parse(text, "t").unwrap_err().to_string();
    assert!(bad("grid_groups = 0").contains("grid_groups"));
    assert!(bad("grid_groups = 9").contains("grid_groups"));
    // With the grid, a box's group must have lists; the other broad phases take groups 0..=7.
    let scene = Scene {
        obbs: vec![Obb::aligned([0.0; 3], [1.0; 3], 3)],
    };
    let e = ModelFrame::new(&scene, &grid(HwConfig::default())).unwrap_err();
    assert!(
        e.to_string().contains("obb 0: group 3") && e.to_string().contains("grid_groups"),
        "{e}"
    );
    let sweep = HwConfig {
        broad_phase: BroadPhase::Sweep,
        ..HwConfig::default()
    };
    assert!(ModelFrame::new(&scene, &sweep).is_ok());
    assert!(bad("grid_cell_mm = 3.0").contains("grid_cell_mm"));
    assert!(bad("grid_cell_mm = 0.0").contains("grid_cell_mm"));
    assert!(bad("grid_hash_bits = 0").contains("grid_hash_bits"));
    assert!(bad("grid_hash_bits = 13").contains("grid_hash_bits"));
    // One list for every group: only where the mask pairs every group, and none is resident.
    assert!(bad("grid_group_lists = false").contains("grid_group_lists"));
    let all = "groups = \"all\"\ngrid_group_lists = false";
    assert_eq!(HwConfig::parse(all, "t").unwrap().list_groups(), 1);
    assert!(bad(&format!("{all}\nresident_groups = [0]")).contains("grid_group_lists"));
    // 2 mm at 2^-10 mm and 20-bit keys: 2^11 key units; never finer than a key unit nor wider
    // than the key range.
    assert_eq!(HwConfig::default().grid_cell_bits(), 11);
    let tiny = HwConfig {
        grid_cell_mm: 2f64.powi(-20),
        ..HwConfig::default()
    };
    assert_eq!(tiny.grid_cell_bits(), 0);
    let huge = HwConfig {
        grid_cell_mm: 2f64.powi(30),
        ..HwConfig::default()
    };
    assert_eq!(huge.grid_cell_bits(), 20);
    let narrow = HwConfig {
        key_bits: 16,
        ..HwConfig::default()
    };
    assert_eq!(narrow.grid_cell_bits(), 7);
}
