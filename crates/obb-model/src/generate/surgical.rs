//! `surgical`: the paper's scenario (its section 3.2). A tissue surface, a dome with gentle
//! ripples over about 100 x 80 mm, tessellated into quads with one thin OBB each, and two
//! laparoscopic grippers (a 150 mm shaft of 4 mm radius and two jaws), each tessellated into
//! small OBBs, at different angles, their jaw tips slightly entering the tissue.
//!
//! Of `n` boxes, 4/7 are tissue and the rest is split between the grippers (17,500 gives the
//! paper's 10,000 + 3,750 + 3,750). Within a gripper a tenth goes to each jaw and the rest to
//! the shaft.

use super::{check_n, obb, rng, GenerateError};
use crate::scene::{Obb, Scene};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

pub const SURGICAL_DEFAULT_N: usize = 17_500;

const TISSUE_X: f64 = 100.0;
const TISSUE_Y: f64 = 80.0;
const TISSUE_HALF_THICKNESS: f64 = 0.125;
const SHAFT_RADIUS: f64 = 4.0;
const SHAFT_LENGTH: f64 = 150.0;
const JAW_LENGTH: f64 = 15.0;
const JAW_WIDTH: f64 = 3.0;
const JAW_THICKNESS: f64 = 1.5;
const SKIN_HALF_THICKNESS: f64 = 0.2;
/// How far the lowest jaw box dips below the tissue surface.
const PENETRATION: f64 = 0.3;

/// The tissue height field: a dome with gentle ripples whose phase comes from the seed.
struct Surface {
    phase: [f64; 2],
}

impl Surface {
    fn height(&self, x: f64, y: f64) -> f64 {
        12.0 * (-(x * x / (2.0 * 30.0 * 30.0) + y * y / (2.0 * 25.0 * 25.0))).exp()
            + 0.6 * (x / 7.0 + self.phase[0]).sin() * (y / 6.0 + self.phase[1]).cos()
    }

    fn point(&self, x: f64, y: f64) -> Vector3<f64> {
        Vector3::new(x, y, self.height(x, y))
    }
}

/// Columns and rows of a grid of `count` cells close to the aspect ratio `wide` : 1, filled
/// row by row (the last row may be partial).
fn grid_shape(count: usize, wide: f64) -> (usize, usize) {
    let cols = ((count as f64 * wide).sqrt().round() as usize).clamp(1, count.max(1));
    (cols, count.div_ceil(cols))
}

fn tissue(surface: &Surface, count: usize, out: &mut Vec<Obb>) {
    let (cols, rows) = grid_shape(count, TISSUE_X / TISSUE_Y);
    let (dx, dy) = (TISSUE_X / cols as f64, TISSUE_Y / rows as f64);
    for k in 0..count {
        let (ix, iy) = (k % cols, k / cols);
        let x0 = -TISSUE_X / 2.0 + ix as f64 * dx;
        let y0 = -TISSUE_Y / 2.0 + iy as f64 * dy;
        let p = [
            surface.point(x0, y0),
            surface.point(x0 + dx, y0),
            surface.point(x0, y0 + dy),
            surface.point(x0 + dx, y0 + dy),
        ];
        let u = ((p[1] - p[0]) + (p[3] - p[2])).normalize();
        let w = (p[2] - p[0]) + (p[3] - p[1]);
        let n = u.cross(&w).normalize();
        let v = n.cross(&u);
        let center = (p[0] + p[1] + p[2] + p[3]) / 4.0;
        // Half-lengths that cover the quad's corners; its warp goes into the thickness.
        let reach = |axis: &Vector3<f64>| {
            p.iter()
                .map(|q| (q - center).dot(axis).abs())
                .fold(0.0, f64::max)
        };
        let rot = Matrix3::from_columns(&[u, v, n]);
        out.push(obb(
            center,
            &rot,
            [reach(&u), reach(&v), TISSUE_HALF_THICKNESS + reach(&n)],
            0,
        ));
    }
}

/// A gripper in its own frame: the hinge at the origin, the shaft along +z, the jaws opening in
/// the x-z plane towards -z.
fn gripper_local(count: usize, open: f64, group: u32) -> Vec<Obb> {
    let mut out = Vec::with_capacity(count);
    let jaw = count / 10;
    let shaft = count - 2 * jaw;
    // Shaft: `segs` boxes around, rings along.
    let (segs, rings) = grid_shape(shaft, 1.0 / 7.5);
    let ring_len = SHAFT_LENGTH / rings as f64;
    for k in 0..shaft {
        let (s, m) = (k % segs, k / segs);
        let theta = 2.0 * PI * (s as f64 + 0.5) / segs as f64;
        let radial = Vector3::new(theta.cos(), theta.sin(), 0.0);
        let tangent = Vector3::new(-theta.sin(), theta.cos(), 0.0);
        let center = radial * SHAFT_RADIUS + Vector3::z() * ((m as f64 + 0.5) * ring_len);
        let rot = Matrix3::from_columns(&[radial, tangent, Vector3::z()]);
        let half_tangent = SHAFT_RADIUS * PI / segs as f64 * 1.05;
        out.push(obb(
            center,
            &rot,
            [SKIN_HALF_THICKNESS, half_tangent, ring_len / 2.0 * 1.02],
            group,
        ));
    }
    // Jaws: boxes around the rectangular cross-section's perimeter, rows along the jaw.
    let perimeter = 2.0 * (JAW_WIDTH + JAW_THICKNESS);
    let (around, along) = grid_shape(jaw, perimeter / JAW_LENGTH * 4.0);
    for side in [-1.0, 1.0] {
        let dir = Vector3::new(side * open.sin(), 0.0, -open.cos());
        let width = Vector3::y();
        let thick = dir.cross(&width);
        for k in 0..jaw {
            let (a, l) = (k % around, k / around);
            let seg_len = perimeter / around as f64;
            let (offset, tangent, normal) =
                perimeter_point((a as f64 + 0.5) * seg_len, &width, &thick);
            let center = dir * ((l as f64 + 0.5) * JAW_LENGTH / along as f64) + offset;
            let rot = Matrix3::from_columns(&[dir, tangent, normal]);
            let half = [
                JAW_LENGTH / along as f64 / 2.0 * 1.02,
                seg_len / 2.0 * 1.05,
                SKIN_HALF_THICKNESS,
            ];
            out.push(obb(center, &rot, half, group));
        }
    }
    out
}

/// The point at arc length `s` around a JAW_WIDTH x JAW_THICKNESS rectangle spanned by `w` and
/// `t`, with the perimeter's tangent and outward normal there.
fn perimeter_point(
    s: f64,
    w: &Vector3<f64>,
    t: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let (hw, ht) = (JAW_WIDTH / 2.0, JAW_THICKNESS / 2.0);
    if s < JAW_WIDTH {
        (w * (s - hw) + t * ht, *w, *t)
    } else if s < JAW_WIDTH + JAW_THICKNESS {
        (w * hw + t * (ht - (s - JAW_WIDTH)), -t, *w)
    } else if s < 2.0 * JAW_WIDTH + JAW_THICKNESS {
        (w * (hw - (s - JAW_WIDTH - JAW_THICKNESS)) - t * ht, -w, -t)
    } else {
        (
            -w * hw + t * (s - 2.0 * JAW_WIDTH - JAW_THICKNESS - ht),
            *t,
            -w,
        )
    }
}

/// Rotates and moves a gripper so that its shaft points along `up` (rolled by `roll`) and its
/// lowest jaw box dips PENETRATION below the tissue under the tip at (`tx`, `ty`).
fn place(
    mut boxes: Vec<Obb>,
    surface: &Surface,
    up: Vector3<f64>,
    roll: f64,
    tx: f64,
    ty: f64,
    jaw_from: usize,
) -> Vec<Obb> {
    let tilt = Rotation3::rotation_between(&Vector3::z(), &up).unwrap_or_else(Rotation3::identity);
    let rot = tilt * Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::z()), roll);
    for b in boxes.iter_mut() {
        let c = rot * Vector3::from(b.center);
        b.center = [c.x + tx, c.y + ty, c.z];
        for a in b.axes.iter_mut() {
            let v = rot * Vector3::from(*a);
            *a = [v.x, v.y, v.z];
        }
    }
    // Lowest point of each jaw box relative to the surface below its center.
    let dip = boxes[jaw_from..]
        .iter()
        .map(|b| {
            let reach: f64 = (0..3).map(|k| b.half[k] * b.axes[k][2].abs()).sum();
            b.center[2] - reach - surface.height(b.center[0], b.center[1])
        })
        .fold(f64::INFINITY, f64::min);
    let lift = if dip.is_finite() {
        -PENETRATION - dip
    } else {
        surface.height(tx, ty)
    };
    for b in boxes.iter_mut() {
        b.center[2] += lift;
    }
    boxes
}

fn jitter(r: &mut ChaCha8Rng, scale: f64) -> f64 {
    r.random_range(-scale..=scale)
}

/// The surgical scene with `n` boxes (default 17,500), deterministic from `seed`.
pub fn surgical(n: usize, seed: u64) -> Result<Scene, GenerateError> {
    check_n(n)?;
    let mut r = rng(seed);
    let surface = Surface {
        phase: [jitter(&mut r, PI), jitter(&mut r, PI)],
    };
    let n_tissue = ((n as f64 * 4.0 / 7.0).round() as usize).max(1);
    let n_left = (n - n_tissue) / 2;
    let n_right = n - n_tissue - n_left;
    let mut obbs = Vec::with_capacity(n);
    tissue(&surface, n_tissue, &mut obbs);
    // Left gripper comes in from -x, right from +x, at different angles; tips near the dome.
    let grippers = [
        (n_left, 1, -0.70, 0.25, -12.0, 5.0),
        (n_right, 2, 0.60, -0.35, 15.0, -8.0),
    ];
    for (count, group, lean_x, lean_y, tx, ty) in grippers {
        if count == 0 {
            continue;
        }
        let up = Vector3::new(
            lean_x + jitter(&mut r, 0.05),
            lean_y + jitter(&mut r, 0.05),
            1.0,
        )
        .normalize();
        let open = 0.25 + jitter(&mut r, 0.05);
        let roll = jitter(&mut r, PI);
        let local = gripper_local(count, open, group);
        let jaw_from = count - 2 * (count / 10);
        obbs.extend(place(
            local,
            &surface,
            up,
            roll,
            tx + jitter(&mut r, 1.0),
            ty + jitter(&mut r, 1.0),
            jaw_from,
        ));
    }
    Ok(Scene { obbs })
}
