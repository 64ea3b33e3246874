//! `surgical`: the paper's scenario (its section 3.2). A tissue surface, a dome with gentle
//! ripples over about 100 x 80 mm, tessellated into quads with one thin OBB each, and two
//! laparoscopic grippers (a 150 mm shaft of 4 mm radius and two jaws), each tessellated into
//! small OBBs, at different angles, their jaw tips slightly entering the tissue.
//!
//! Of `n` boxes, 4/7 are tissue and the rest is split between the grippers (17,500 gives the
//! paper's 10,000 + 3,750 + 3,750). Within a gripper a tenth goes to each jaw and the rest to
//! the shaft.

use super::{check_n, obb, rng, GenerateError};
use crate::mesh::{quad_box, Mesh};
use crate::scene::{Obb, Scene};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

pub const SURGICAL_DEFAULT_N: usize = 17_500;

const TISSUE_X: f64 = 100.0;
const TISSUE_Y: f64 = 80.0;
pub(super) const TISSUE_HALF_THICKNESS: f64 = 0.125;
const SHAFT_RADIUS: f64 = 4.0;
const SHAFT_LENGTH: f64 = 150.0;
const JAW_LENGTH: f64 = 15.0;
const JAW_WIDTH: f64 = 3.0;
const JAW_THICKNESS: f64 = 1.5;
const SKIN_HALF_THICKNESS: f64 = 0.2;
/// How far the lowest jaw box dips below the tissue surface.
const PENETRATION: f64 = 0.3;

/// The tissue height field: a dome with gentle ripples whose phase comes from the seed; `rise`
/// lifts the dome's top (0 in the still scene, breathing in `SurgicalMotion`).
#[derive(Clone, Copy)]
pub(super) struct Surface {
    pub(super) phase: [f64; 2],
    pub(super) rise: f64,
}

impl Surface {
    pub(super) fn height(&self, x: f64, y: f64) -> f64 {
        (12.0 + self.rise) * (-(x * x / (2.0 * 30.0 * 30.0) + y * y / (2.0 * 25.0 * 25.0))).exp()
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

/// The tissue's quads, corners in order around each: a grid of `count` cells over the surface.
pub(super) fn tissue(surface: &Surface, count: usize) -> Vec<[Vector3<f64>; 4]> {
    let (cols, rows) = grid_shape(count, TISSUE_X / TISSUE_Y);
    let (dx, dy) = (TISSUE_X / cols as f64, TISSUE_Y / rows as f64);
    (0..count)
        .map(|k| {
            let (ix, iy) = (k % cols, k / cols);
            let x0 = -TISSUE_X / 2.0 + ix as f64 * dx;
            let y0 = -TISSUE_Y / 2.0 + iy as f64 * dy;
            [
                surface.point(x0, y0),
                surface.point(x0 + dx, y0),
                surface.point(x0 + dx, y0 + dy),
                surface.point(x0, y0 + dy),
            ]
        })
        .collect()
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

/// The scene's parts: the tissue's quads and each gripper's boxes with the index of its first
/// jaw box (shaft boxes have their skin normal as axis 0, jaw boxes as axis 2).
pub(super) struct Parts {
    pub(super) surface: Surface,
    pub(super) tissue: Vec<[Vector3<f64>; 4]>,
    pub(super) grippers: Vec<(Vec<Obb>, usize)>,
}

pub(super) fn parts(n: usize, seed: u64) -> Result<Parts, GenerateError> {
    check_n(n)?;
    let mut r = rng(seed);
    let surface = Surface {
        phase: [jitter(&mut r, PI), jitter(&mut r, PI)],
        rise: 0.0,
    };
    let n_tissue = ((n as f64 * 4.0 / 7.0).round() as usize).max(1);
    let n_left = (n - n_tissue) / 2;
    let n_right = n - n_tissue - n_left;
    let tissue = tissue(&surface, n_tissue);
    // Left gripper comes in from -x, right from +x, at different angles; tips near the dome.
    let grippers = [
        (n_left, 1, -0.70, 0.25, -12.0, 5.0),
        (n_right, 2, 0.60, -0.35, 15.0, -8.0),
    ];
    let mut placed = Vec::with_capacity(2);
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
        let boxes = place(
            local,
            &surface,
            up,
            roll,
            tx + jitter(&mut r, 1.0),
            ty + jitter(&mut r, 1.0),
            jaw_from,
        );
        placed.push((boxes, jaw_from));
    }
    Ok(Parts {
        surface,
        tissue,
        grippers: placed,
    })
}

/// The surgical scene with `n` boxes (default 17,500), deterministic from `seed`.
pub fn surgical(n: usize, seed: u64) -> Result<Scene, GenerateError> {
    let parts = parts(n, seed)?;
    let mut obbs = Vec::with_capacity(n);
    // Half-lengths that cover the quad's corners; its warp goes into the thickness.
    obbs.extend(
        parts
            .tissue
            .iter()
            .map(|q| quad_box(q, TISSUE_HALF_THICKNESS, 0)),
    );
    for (boxes, _) in parts.grippers {
        obbs.extend(boxes);
    }
    Ok(Scene { obbs })
}

/// One surface of the surgical scene as a mesh: the group its boxes take and the thickness
/// `mesh_boxes` makes them again with.
pub struct SurfaceMesh {
    pub group: u32,
    pub thickness: f64,
    pub mesh: Mesh,
}

/// The surgical scene's surfaces as meshes (quads, four vertices each): the tissue's quads
/// (`mesh_boxes` gives back the scene's tissue boxes bit for bit) and each gripper's skin, one
/// quad per box at the middle of its skin (given back to rounding).
pub fn surgical_meshes(n: usize, seed: u64) -> Result<Vec<SurfaceMesh>, GenerateError> {
    let parts = parts(n, seed)?;
    let mut out = vec![SurfaceMesh {
        group: 0,
        thickness: 2.0 * TISSUE_HALF_THICKNESS,
        mesh: quads_mesh(parts.tissue),
    }];
    for (boxes, jaw_from) in parts.grippers {
        let group = boxes.first().map_or(0, |b| b.group);
        let quads = boxes
            .iter()
            .enumerate()
            .map(|(k, b)| mid_surface(b, if k < jaw_from { 0 } else { 2 }))
            .collect();
        out.push(SurfaceMesh {
            group,
            thickness: 2.0 * SKIN_HALF_THICKNESS,
            mesh: quads_mesh(quads),
        });
    }
    Ok(out)
}

fn quads_mesh(quads: Vec<[Vector3<f64>; 4]>) -> Mesh {
    Mesh {
        vertices: quads.iter().flatten().map(|p| [p.x, p.y, p.z]).collect(),
        faces: (0..quads.len())
            .map(|k| (4 * k..4 * k + 4).collect())
            .collect(),
    }
}

/// The rectangle through a box's center across its `normal` axis, corners in order around it.
fn mid_surface(b: &Obb, normal: usize) -> [Vector3<f64>; 4] {
    let (i, j) = ((normal + 1) % 3, (normal + 2) % 3);
    let c = Vector3::from(b.center);
    let a = Vector3::from(b.axes[i]) * b.half[i];
    let e = Vector3::from(b.axes[j]) * b.half[j];
    [c - a - e, c + a - e, c + a + e, c - a + e]
}
