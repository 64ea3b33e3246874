//! The scenes the core's tests share: touching cases, the stiff and extreme suite, the dense
//! worst case, buckets shared by two cells in every list copy of the default grid.

use obb_model::fixed::grid::{GridShape, BANKS};
use obb_model::fixed::HwConfig;
use obb_model::generate::uniform;
use obb_model::{Obb, Scene};
use std::collections::{HashMap, HashSet};

/// Faces, edges and corners just touching, a zero-thickness box, a rotated one, a far one.
pub fn touching_pairs() -> Scene {
    let mut obbs = vec![
        Obb::aligned([0.0; 3], [1.0; 3], 0),
        Obb::aligned([2.0, 0.0, 0.0], [1.0; 3], 1),
        Obb::aligned([2.0, 2.0, 0.0], [1.0; 3], 2),
        Obb::aligned([-2.0, -2.0, -2.0], [1.0; 3], 1),
        Obb::aligned([0.0, 0.0, 3.0], [2.0, 2.0, 0.0], 1),
        Obb::aligned([50.0, 0.0, 0.0], [1.0; 3], 1),
    ];
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut r = Obb::aligned([0.0, 2.0 + std::f64::consts::SQRT_2, 0.0], [1.0; 3], 1);
    r.axes = [[s, s, 0.0], [-s, s, 0.0], [0.0, 0.0, 1.0]];
    obbs.push(r);
    Scene { obbs }
}

/// The boxes of `scene` but the tissue's (group 0): a surgical scene's instruments, which a
/// haptic frame streams when the tissue is resident.
pub fn instruments(scene: &Scene) -> Scene {
    boxes_where(scene, |o| o.group != 0)
}

/// The tissue's boxes (group 0) of `scene`: what an update frame leaves resident.
pub fn tissue(scene: &Scene) -> Scene {
    boxes_where(scene, |o| o.group == 0)
}

/// The boxes of `scene` that `keep` keeps, in scene order.
fn boxes_where(scene: &Scene, keep: impl Fn(&Obb) -> bool) -> Scene {
    Scene {
        obbs: scene.obbs.iter().filter(|o| keep(o)).cloned().collect(),
    }
}

/// The first `n` boxes of `scene`.
pub fn first(scene: Scene, n: usize) -> Scene {
    Scene {
        obbs: scene.obbs[..n].to_vec(),
    }
}

/// The dense worst case: `n` boxes packed into a small cube, in all eight groups.
pub fn dense(n: usize) -> Scene {
    let mut s = uniform(n, 3, 4.0).unwrap();
    for (i, o) in s.obbs.iter_mut().enumerate() {
        o.group = (i % 8) as u32;
    }
    s
}

/// `scene` with its groups folded into the grid's default three.
pub fn three_groups(mut scene: Scene) -> Scene {
    for o in &mut scene.obbs {
        o.group %= 3;
    }
    scene
}

/// The stiff and extreme cases: boxes at both ends of the coordinate range, the longest
/// half-lengths, a near-parallel pair 1e-9 rad apart, axes rounded to f32, a zero-thickness
/// plate touching a box, coincident boxes.
pub fn stiff() -> Scene {
    let rot = |angle: f64| {
        let (s, c) = angle.sin_cos();
        [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
    };
    let mut obbs = vec![
        Obb::aligned([-500.0, -500.0, -500.0], [1.0; 3], 0),
        Obb::aligned([-498.0, -500.0, -500.0], [1.0; 3], 1),
        Obb::aligned([499.0, 499.0, 499.0], [1.0; 3], 2),
        Obb::aligned([0.0, 0.0, 0.0], [120.0, 1.0, 1.0], 0),
        Obb::aligned([0.0, 2.0, 0.0], [120.0, 1.0, 1.0], 1),
        Obb::aligned([50.0, 50.0, 50.0], [2.0, 2.0, 0.0], 0),
        Obb::aligned([50.0, 50.0, 51.0], [1.0; 3], 1),
        Obb::aligned([-50.0, 0.0, 0.0], [3.0; 3], 2),
        Obb::aligned([-50.0, 0.0, 0.0], [3.0; 3], 1),
    ];
    let mut a = Obb::aligned([200.0, 0.0, 0.0], [10.0, 1.0, 1.0], 0);
    a.axes = rot(0.3);
    let mut b = Obb::aligned([200.0, 0.0, 0.0], [10.0, 1.0, 1.0], 1);
    b.axes = rot(0.3 + 1e-9);
    b.center = [200.0 - 2.0 * 0.3f64.sin(), 2.0 * 0.3f64.cos(), 0.0];
    let mut f = Obb::aligned([-200.0, 0.0, 0.0], [4.0, 2.0, 1.0], 2);
    f.axes = rot(0.7).map(|r| r.map(|v| v as f32 as f64));
    let g = Obb::aligned([-200.0, 0.0, 2.0], [1.0; 3], 0);
    obbs.extend([a, b, f, g]);
    Scene { obbs }
}

/// The `n` boxes of the full surgical scene nearest the lowest instrument box (a jaw tip
/// dipping into the tissue), in scene order: tissue and jaws where they touch, at the
/// tessellation the default configuration's 2 mm cells are sized for (a smaller `surgical`
/// scene has coarser, larger boxes).
pub fn surgical_contact(n: usize) -> Scene {
    let full = obb_model::generate::surgical(obb_model::generate::SURGICAL_DEFAULT_N, 1).unwrap();
    let tip = full
        .obbs
        .iter()
        .filter(|o| o.group != 0)
        .min_by(|a, b| a.center[2].total_cmp(&b.center[2]))
        .unwrap()
        .center;
    let dist = |o: &Obb| (0..3).map(|i| (o.center[i] - tip[i]).powi(2)).sum::<f64>();
    let mut order: Vec<usize> = (0..full.obbs.len()).collect();
    order.sort_by(|&a, &b| dist(&full.obbs[a]).total_cmp(&dist(&full.obbs[b])));
    order.truncate(n);
    order.sort_unstable();
    Scene {
        obbs: order.into_iter().map(|i| full.obbs[i].clone()).collect(),
    }
}

/// Cell pairs of the default grid, per bank (cell coordinates mod 3) `per_bank` of them, each
/// two cells of that bank in one bucket with different fingerprints; every cell chosen at least
/// three cells from every other on some axis, so that no box's window (two cells per axis)
/// reaches another's cell, and no two pairs of a bank in one bucket.
fn bucket_pairs(per_bank: usize) -> Vec<Vec<([u64; 3], [u64; 3])>> {
    let shape = GridShape::new(&HwConfig::default());
    let mut taken: Vec<[u64; 3]> = Vec::new();
    let free = |taken: &[[u64; 3]], c: &[u64; 3]| {
        taken
            .iter()
            .all(|t| (0..3).any(|x| t[x].abs_diff(c[x]) >= 3))
    };
    (0..BANKS)
        .map(|b| {
            let want = [b % 3, b / 3 % 3, b / 9].map(|r| r as u64);
            let mut seen: HashMap<usize, [u64; 3]> = HashMap::new();
            let mut used = HashSet::new();
            let mut pairs = Vec::new();
            // Cells of the bank around the middle of the coordinate range, z slowest.
            let along = |r: u64| (150..360).filter(move |c| c % 3 == r);
            'search: for z in along(want[2]) {
                for y in along(want[1]) {
                    for x in along(want[0]) {
                        let c = [x, y, z];
                        let bucket = shape.bucket(&c);
                        if used.contains(&bucket) || !free(&taken, &c) {
                            continue;
                        }
                        match seen.get(&bucket) {
                            Some(o)
                                if shape.fingerprint(o) != shape.fingerprint(&c)
                                    && free(&taken, o) =>
                            {
                                pairs.push((*o, c));
                                taken.extend([*o, c]);
                                used.insert(bucket);
                                if pairs.len() == per_bank {
                                    break 'search;
                                }
                            }
                            Some(_) => {}
                            None => {
                                seen.insert(bucket, c);
                            }
                        }
                    }
                }
            }
            assert_eq!(pairs.len(), per_bank, "bank {b}: too few shared buckets");
            pairs
        })
        .collect()
}

/// For the default grid (2 mm cells, 1,024 buckets a bank, three lists a bucket, cross-group),
/// in every one of its 81 list copies (27 banks x 3 groups), lists of buckets that two cells
/// share (`bucket_pairs`), in four phases over all copies: (1) a list entered by two boxes of
/// its first cell and, on the next clock, one of its second cell (the entries forwarded, the
/// list mixed by the forwarded fingerprint), then probed from its second cell by a box of
/// another group beside the second cell's box (the head forwarded, the list walked, no pair:
/// no SAT test in this phase, so that the load never waits); another list entered by two boxes of
/// its first cell, then probed from its second cell (pure: skipped without a visit); (2) that
/// list probed again from its second cell (its head read from the table, skipped); (3) a box
/// of the second cell enters it (mixed by a stored entry); (4) boxes of another group probe
/// both mixed lists from the other cells (walked: from the first cell, the pairs are found
/// only if the list is mixed). Boxes of 0.6 mm at cells' middles, each probe overlapping the
/// boxes of the other group in its cell.
pub fn shared_buckets() -> Scene {
    let cfg = HwConfig::default();
    // A cell's middle in mm: key (c - 1) edge + edge / 2, less the keys' offset.
    let edge = 1u64 << cfg.grid_cell_bits();
    let unit = cfg.lsb_mm * f64::from(1u32 << cfg.key_shift());
    let offset = cfg.lsb_mm * f64::from(1u32 << (cfg.center_bits - 1));
    let cell_mm = edge as f64 * unit;
    let shift = 0.05 * cell_mm;
    let box_at = |c: [u64; 3], dx: f64, group| {
        let mut at = c.map(|k| ((k - 1) * edge + edge / 2) as f64 * unit - offset);
        at[0] += dx;
        Obb::aligned(at, [0.15 * cell_mm; 3], group)
    };
    let pairs = bucket_pairs(6);
    // Per copy (bank b, group g): the first list's cells, the second's, the probes' group.
    let copies = || {
        pairs.iter().flat_map(|p| {
            (0..3u32).map(move |g| (p[2 * g as usize], p[2 * g as usize + 1], g, (g + 1) % 3))
        })
    };
    let mut obbs = Vec::new();
    for ((c1, c2), (c3, c4), g, other) in copies() {
        obbs.extend([
            box_at(c1, 0.0, g),
            box_at(c1, shift, g),
            box_at(c2, 0.0, g),
            box_at(c2, 6.5 * shift, other),
            box_at(c3, 0.0, g),
            box_at(c3, shift, g),
            box_at(c4, 0.0, other),
        ]);
    }
    obbs.extend(copies().map(|(_, (_, c4), _, other)| box_at(c4, -0.5 * shift, other)));
    obbs.extend(copies().map(|(_, (_, c4), g, _)| box_at(c4, shift, g)));
    for ((c1, _), (c3, c4), _, other) in copies() {
        obbs.extend([
            box_at(c1, -shift, other),
            box_at(c4, -shift, other),
            box_at(c3, -shift, other),
        ]);
    }
    Scene { obbs }
}
