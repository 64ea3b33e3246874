//! Mesh files: OBJ read with `tobj` (in f64, polygons kept as given) and STL with `stl_io`; OBJ
//! written for `scene surgical --obj-out`.

use anyhow::{bail, Context, Result};
use obb_model::mesh::Mesh;
use std::fmt::Write as _;
use std::path::Path;

/// All objects of an OBJ file as one mesh, faces in file order.
pub fn read_obj(path: &Path) -> Result<Mesh> {
    let options = tobj::LoadOptions {
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj(path, &options)
        .with_context(|| format!("cannot read OBJ file {}", path.display()))?;
    let mut mesh = Mesh::default();
    for model in models {
        let m = model.mesh;
        let base = mesh.vertices.len();
        mesh.vertices
            .extend(m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        let index = |i: &u32| base + *i as usize;
        if m.face_arities.is_empty() {
            mesh.faces.extend(
                m.indices
                    .chunks_exact(3)
                    .map(|f| f.iter().map(index).collect()),
            );
        } else {
            let mut at = 0;
            for &arity in &m.face_arities {
                let end = at + arity as usize;
                let Some(f) = m.indices.get(at..end) else {
                    bail!(
                        "OBJ file {}: a face's indices run past the end",
                        path.display()
                    );
                };
                mesh.faces.push(f.iter().map(index).collect());
                at = end;
            }
        }
    }
    Ok(mesh)
}

/// An STL file (binary or ASCII) as a mesh, identical vertices merged.
pub fn read_stl(path: &Path) -> Result<Mesh> {
    let mut file = std::fs::File::open(path)
        .with_context(|| format!("cannot read STL file {}", path.display()))?;
    let stl = stl_io::read_stl(&mut file)
        .with_context(|| format!("STL file {} is not a valid STL", path.display()))?;
    Ok(Mesh {
        vertices: stl.vertices.iter().map(|v| v.0.map(f64::from)).collect(),
        faces: stl.faces.iter().map(|f| f.vertices.to_vec()).collect(),
    })
}

/// `mesh` as OBJ text: every vertex (Rust prints the shortest decimal that reads back as the
/// same f64, so the file loses nothing), then the faces (OBJ counts vertices from 1).
pub fn obj_text(mesh: &Mesh, name: &str) -> String {
    let mut s = format!("# obbcd scene surgical --obj-out\no {name}\n");
    for v in &mesh.vertices {
        let _ = writeln!(s, "v {} {} {}", v[0], v[1], v[2]);
    }
    for f in &mesh.faces {
        s.push('f');
        for i in f {
            let _ = write!(s, " {}", i + 1);
        }
        s.push('\n');
    }
    s
}
