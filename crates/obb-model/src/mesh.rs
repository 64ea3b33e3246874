//! Scenes from surface meshes, as the paper tessellates tissue: one thin OBB per quad, or per
//! triangle where no neighbour makes a quad with it.
//!
//! A face's box has the face's plane as its middle: its two in-plane half-lengths cover the
//! face's vertices, its third is half the given thickness plus how far the vertices stand out
//! of that plane (a warped quad's warp). A box covers its vertices, hence their convex hull:
//! every point of the face whatever the diagonal it is split along, so the boxes are
//! conservative for any surface through those vertices.
//!
//! Faces are counted from 0 in the order the file gives them (over all its objects); errors
//! name the face.

use crate::scene::{Obb, COORD_LIMIT};
use nalgebra::{Matrix3, Vector3};
use thiserror::Error;

/// Smallest sine between two edges of a face (triangle) or between a quad's two mean edge
/// directions below which the face is degenerate: its plane, hence its box's thin axis, is not
/// defined by the vertices (rounding alone leaves a sine near 1e-16 on collinear vertices).
pub const MIN_FACE_SINE: f64 = 1.0e-9;

/// A polygon soup or an indexed mesh: vertex positions and faces, each the indices of its
/// three or four vertices in order around it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<[f64; 3]>,
    pub faces: Vec<Vec<usize>>,
}

#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("has no faces")]
    Empty,
    #[error("thickness must be a finite number >= 0, got {0}")]
    Thickness(f64),
    #[error("face {face}: {problem}")]
    Face { face: usize, problem: String },
}

/// The box of a quad given by its corners in order around it: the generator's tissue boxes are
/// made by this function, so a tissue exported as OBJ comes back bit for bit.
///
/// The first axis is the mean direction of the two edges q0-q1 and q3-q2, the third the normal
/// of that and the mean of the other two edges; the center is the corners' mean.
pub fn quad_box(q: &[Vector3<f64>; 4], half_thickness: f64, group: u32) -> Obb {
    let u = ((q[1] - q[0]) + (q[2] - q[3])).normalize();
    let w = (q[3] - q[0]) + (q[2] - q[1]);
    let n = u.cross(&w).normalize();
    let v = n.cross(&u);
    let center = (q[0] + q[1] + q[3] + q[2]) / 4.0;
    let reach = |axis: &Vector3<f64>| {
        q.iter()
            .map(|p| (p - center).dot(axis).abs())
            .fold(0.0, f64::max)
    };
    let rot = Matrix3::from_columns(&[u, v, n]);
    crate::generate::obb(
        center,
        &rot,
        [reach(&u), reach(&v), half_thickness + reach(&n)],
        group,
    )
}

/// The smallest box of a triangle with one axis along its longest edge: the other in-plane
/// axis spans the triangle's height, so the box's face is twice the triangle's area.
pub fn triangle_box(t: &[Vector3<f64>; 3], half_thickness: f64, group: u32) -> Obb {
    let edges = [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
    let longest = (0..3)
        .max_by(|&a, &b| edges[a].norm_squared().total_cmp(&edges[b].norm_squared()))
        .unwrap_or(0);
    let u = edges[longest].normalize();
    let n = u.cross(&edges[(longest + 1) % 3]).normalize();
    let v = n.cross(&u);
    // Extents from t[0] along each axis: the box is centered on them, not on the centroid.
    let mut center = t[0];
    let mut half = [0.0; 3];
    for (k, axis) in [u, v, n].iter().enumerate() {
        let (lo, hi) = t.iter().fold((0.0f64, 0.0f64), |(lo, hi), p| {
            let s = (p - t[0]).dot(axis);
            (lo.min(s), hi.max(s))
        });
        center += axis * ((lo + hi) / 2.0);
        half[k] = (hi - lo) / 2.0;
    }
    half[2] += half_thickness;
    crate::generate::obb(center, &Matrix3::from_columns(&[u, v, n]), half, group)
}

fn volume(b: &Obb) -> f64 {
    b.half.iter().product()
}

/// Sine of the angle between `a` and `b` (0 when either vanishes).
fn sine(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let scale = a.norm() * b.norm();
    if scale > 0.0 {
        a.cross(b).norm() / scale
    } else {
        0.0
    }
}

/// The face's corners, checked: three or four vertices, in range, finite, within the scene's
/// coordinate limit, not degenerate.
fn corners(mesh: &Mesh, face: usize) -> Result<Vec<Vector3<f64>>, MeshError> {
    let bad = |problem: String| MeshError::Face { face, problem };
    let f = &mesh.faces[face];
    if !(3..=4).contains(&f.len()) {
        return Err(bad(format!(
            "has {} vertices: a face must be a triangle or a quad",
            f.len()
        )));
    }
    let mut out = Vec::with_capacity(f.len());
    for &i in f {
        let p = mesh.vertices.get(i).ok_or_else(|| {
            bad(format!(
                "names vertex {i}, but the mesh has {} vertices",
                mesh.vertices.len()
            ))
        })?;
        // Named by position: a mesh reader may number the vertices differently from the file.
        if let Some(c) = p.iter().find(|c| !c.is_finite() || c.abs() > COORD_LIMIT) {
            return Err(bad(format!(
                "its vertex {p:?} has {c}, not a finite number within ±{COORD_LIMIT:e}"
            )));
        }
        out.push(Vector3::from(*p));
    }
    let s = if out.len() == 3 {
        sine(&(out[1] - out[0]), &(out[2] - out[0]))
    } else {
        sine(
            &((out[1] - out[0]) + (out[2] - out[3])),
            &((out[3] - out[0]) + (out[2] - out[1])),
        )
    };
    if s.is_nan() || s < MIN_FACE_SINE {
        return Err(bad(format!(
            "is degenerate: its vertices {f:?} are collinear or repeated (sine {s:.1e})"
        )));
    }
    Ok(out)
}

/// The two triangles as one quad, in order around it, when they share exactly one edge.
/// Vertices are compared by position, so a polygon soup (each face its own vertices, as many
/// OBJ exporters write) merges as an indexed mesh does.
fn shared_quad(mesh: &Mesh, a: &[usize], b: &[usize]) -> Option<[usize; 4]> {
    let at = |i: usize| mesh.vertices[i];
    let shared = |i: usize| b.iter().any(|&j| at(j) == at(i));
    if a.iter().filter(|&&i| shared(i)).count() != 2 {
        return None;
    }
    let other = *b.iter().find(|&&j| !a.iter().any(|&i| at(i) == at(j)))?;
    // The edge a[k]-a[k+1] is shared: the quad runs a[k+2], a[k], other, a[k+1].
    (0..3)
        .find(|&k| shared(a[k]) && shared(a[(k + 1) % 3]))
        .map(|k| [a[(k + 2) % 3], a[k], other, a[(k + 1) % 3]])
}

/// One box per face of `mesh`, `thickness` thick (plus any warp), in face order; two triangles
/// next to each other in that order that share an edge become one quad's box when that box is
/// no larger than the two triangles' boxes together (a flat mesh split from quads comes back
/// as its quads).
pub fn mesh_boxes(mesh: &Mesh, thickness: f64, group: u32) -> Result<Vec<Obb>, MeshError> {
    if !(thickness.is_finite() && thickness >= 0.0) {
        return Err(MeshError::Thickness(thickness));
    }
    if mesh.faces.is_empty() {
        return Err(MeshError::Empty);
    }
    let half = thickness / 2.0;
    let mut out = Vec::with_capacity(mesh.faces.len());
    let mut face = 0;
    while face < mesh.faces.len() {
        let p = corners(mesh, face)?;
        if let [a, b, c] = p[..] {
            let first = triangle_box(&[a, b, c], half, group);
            if let Some(merged) = merged_with_next(mesh, face, &first, half, group)? {
                out.push(merged);
                face += 2;
                continue;
            }
            out.push(first);
        } else {
            out.push(quad_box(&[p[0], p[1], p[2], p[3]], half, group));
        }
        face += 1;
    }
    Ok(out)
}

/// Triangle `face` (whose box is `first`) merged with the next face, if that is a triangle
/// sharing an edge with it and the quad's box is no larger than the two triangles' boxes.
fn merged_with_next(
    mesh: &Mesh,
    face: usize,
    first: &Obb,
    half: f64,
    group: u32,
) -> Result<Option<Obb>, MeshError> {
    let Some(next) = mesh.faces.get(face + 1).filter(|f| f.len() == 3) else {
        return Ok(None);
    };
    // Checked first: shared_quad reads its vertices.
    let p = corners(mesh, face + 1)?;
    let Some(quad) = shared_quad(mesh, &mesh.faces[face], next) else {
        return Ok(None);
    };
    let second = triangle_box(&[p[0], p[1], p[2]], half, group);
    let q = quad.map(|i| Vector3::from(mesh.vertices[i]));
    let merged = quad_box(&q, half, group);
    Ok((volume(&merged) <= volume(first) + volume(&second)).then_some(merged))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `p` is in `b`, `tol` outside its faces allowed.
    fn obb_contains(b: &Obb, p: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| {
            let d: f64 = (0..3).map(|i| (p[i] - b.center[i]) * b.axes[k][i]).sum();
            d.abs() <= b.half[k] + tol
        })
    }

    fn v(x: f64, y: f64, z: f64) -> [f64; 3] {
        [x, y, z]
    }

    #[test]
    fn a_square_split_in_two_triangles_is_one_box() {
        let mesh = Mesh {
            vertices: vec![v(0., 0., 0.), v(2., 0., 0.), v(2., 1., 0.), v(0., 1., 0.)],
            faces: vec![vec![0, 1, 2], vec![0, 2, 3]],
        };
        let boxes = mesh_boxes(&mesh, 0.5, 3).unwrap();
        assert_eq!(boxes.len(), 1);
        let b = &boxes[0];
        assert_eq!(b.group, 3);
        for (got, want) in b.center.iter().zip([1.0, 0.5, 0.0]) {
            assert!((got - want).abs() < 1e-15, "center {:?}", b.center);
        }
        let mut half = b.half;
        half.sort_by(f64::total_cmp);
        for (got, want) in half.iter().zip([0.25, 0.5, 1.0]) {
            assert!((got - want).abs() < 1e-15, "half {:?}", b.half);
        }
    }

    #[test]
    fn a_folded_pair_stays_two_triangles_and_each_box_covers_its_triangle() {
        // Folded 90 degrees along the shared edge: one box would be much thicker.
        let mesh = Mesh {
            vertices: vec![v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.), v(0., 0., 1.)],
            faces: vec![vec![0, 1, 2], vec![0, 3, 1]],
        };
        let boxes = mesh_boxes(&mesh, 0.0, 0).unwrap();
        assert_eq!(boxes.len(), 2);
        for (b, f) in boxes.iter().zip(&mesh.faces) {
            for &i in f {
                assert!(obb_contains(b, mesh.vertices[i], 1e-12), "{b:?} {i}");
            }
            // Tight: a triangle's box face is twice its area (here 0.5).
            let mut half = b.half;
            half.sort_by(f64::total_cmp);
            assert!((4.0 * half[1] * half[2] - 1.0).abs() < 1e-12, "{b:?}");
        }
    }

    #[test]
    fn bad_faces_are_named() {
        let mesh = |faces: Vec<Vec<usize>>| Mesh {
            vertices: vec![
                v(0., 0., 0.),
                v(1., 0., 0.),
                v(2., 0., 0.),
                v(0., 1., f64::NAN),
            ],
            faces,
        };
        let err = |faces| mesh_boxes(&mesh(faces), 0.25, 0).unwrap_err().to_string();
        assert!(err(vec![vec![0, 1, 2]]).starts_with("face 0: is degenerate"));
        assert!(err(vec![vec![0, 1, 1]]).starts_with("face 0: is degenerate"));
        assert!(err(vec![vec![0, 1, 3]]).starts_with("face 0: its vertex [0.0, 1.0, NaN] has NaN"));
        assert!(err(vec![vec![0, 1, 7]]).contains("names vertex 7"));
        assert!(err(vec![vec![0, 1]]).contains("has 2 vertices"));
        assert_eq!(
            mesh_boxes(&mesh(vec![]), 0.25, 0),
            Err(MeshError::Empty),
            "empty"
        );
        assert_eq!(
            mesh_boxes(&mesh(vec![vec![0, 1, 3]]), -1.0, 0),
            Err(MeshError::Thickness(-1.0))
        );
    }

    proptest::proptest! {
        /// Whatever four points (two triangles sharing an edge, merged or not, or one quad),
        /// every vertex lies in a box of its face: the boxes cover the surface.
        #[test]
        fn every_vertex_is_in_its_faces_box(
            p in proptest::array::uniform4(proptest::array::uniform3(-50.0f64..50.0)),
            thickness in 0.0f64..2.0,
        ) {
            for faces in [vec![vec![0, 1, 2], vec![2, 1, 3]], vec![vec![0, 1, 3, 2]]] {
                let mesh = Mesh { vertices: p.to_vec(), faces };
                // Random points may be near collinear: then the error is the answer.
                let Ok(boxes) = mesh_boxes(&mesh, thickness, 0) else { continue };
                let faces_of_box: Vec<Vec<usize>> = if boxes.len() == 1 {
                    vec![(0..4).collect()]
                } else {
                    mesh.faces.clone()
                };
                for (b, f) in boxes.iter().zip(&faces_of_box) {
                    proptest::prop_assert!((b.half[2] - thickness / 2.0) >= -1e-12);
                    for &i in f {
                        proptest::prop_assert!(obb_contains(b, p[i], 1e-9), "{:?} {:?}", b, p[i]);
                    }
                }
            }
        }
    }
}
