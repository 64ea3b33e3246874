//! A fixed scene of large boxes over small ones, for the grid's slow path (its tests in the
//! model and in the hardware): 40 small boxes in two groups on a plane, two slabs across them
//! (groups 2 and 3; the first among the small boxes' indices) and a large box far away.

use crate::scene::{Obb, Scene};

/// The scene: 43 boxes, boxes 5, 41 and 42 the large ones at 2 mm cells.
pub fn slabs() -> Scene {
    let mut obbs: Vec<Obb> = (0..40)
        .map(|k| {
            Obb::aligned(
                [f64::from(k % 8) * 0.9, f64::from(k / 8) * 0.9, 0.0],
                [0.4; 3],
                k % 2,
            )
        })
        .collect();
    obbs.insert(5, Obb::aligned([3.0, 2.0, 0.0], [4.0, 0.3, 0.3], 2));
    obbs.push(Obb::aligned([3.0, 2.0, 0.5], [0.3, 3.0, 0.3], 3));
    obbs.push(Obb::aligned([90.0, 0.0, 0.0], [5.0; 3], 3));
    Scene { obbs }
}
