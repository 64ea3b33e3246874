//! The scenes the core's tests share: touching cases, the stiff and extreme suite, the dense
//! worst case.

use obb_model::generate::uniform;
use obb_model::{Obb, Scene};

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
