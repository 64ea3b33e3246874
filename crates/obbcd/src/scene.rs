//! `obbcd scene`: generate a scene, or make one from meshes.

use crate::builtin::DEFAULT_SEED;
use crate::mesh_io::{obj_text, read_obj, read_stl};
use anyhow::{bail, Context, Result};
use clap::{ArgMatches, Args, ValueEnum};
use obb_model::generate::{
    surgical, surgical_meshes, uniform, SURGICAL_DEFAULT_N, UNIFORM_DEFAULT_DENSITY,
};
use obb_model::mesh::mesh_boxes;
use obb_model::Scene;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, PartialEq, ValueEnum)]
pub enum Kind {
    /// Tissue surface and two laparoscopic grippers (the paper's scenario).
    Surgical,
    /// Randomly rotated boxes in a cube.
    Uniform,
    /// One thin box per face of OBJ and STL meshes (--obj, --stl).
    Mesh,
}

#[derive(Args)]
pub struct SceneArgs {
    kind: Kind,
    /// Number of boxes (surgical: 17,500; uniform: 10,000).
    #[arg(long)]
    n: Option<usize>,
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
    /// uniform: total box volume over cube volume.
    #[arg(long, default_value_t = UNIFORM_DEFAULT_DENSITY)]
    density: f64,
    /// mesh: an OBJ file (triangles and quads); --thickness and --group after it apply to it.
    #[arg(long, value_name = "FILE")]
    obj: Vec<PathBuf>,
    /// mesh: an STL file (binary or ASCII), as --obj.
    #[arg(long, value_name = "FILE")]
    stl: Vec<PathBuf>,
    /// mesh: the thickness of the boxes of the mesh before it, in mm (default: the previous
    /// mesh's; the first mesh needs one).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    thickness: Vec<f64>,
    /// mesh: the group of the boxes of the mesh before it (default 0).
    #[arg(long, value_name = "G")]
    group: Vec<u32>,
    /// surgical: also write the scene's surfaces as OBJ files into this folder (group0.obj,
    /// group1.obj, ...) and print the `scene mesh` command that makes the scene from them.
    #[arg(long, value_name = "DIR")]
    obj_out: Option<PathBuf>,
    /// Output JSON file.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
}

pub fn run(a: SceneArgs, matches: &ArgMatches) -> Result<()> {
    let meshes_given = !(a.obj.is_empty() && a.stl.is_empty());
    if a.kind != Kind::Mesh && (meshes_given || !a.thickness.is_empty() || !a.group.is_empty()) {
        bail!("--obj, --stl, --thickness and --group are for `scene mesh`");
    }
    if a.kind != Kind::Surgical && a.obj_out.is_some() {
        bail!("--obj-out is for `scene surgical`");
    }
    let scene = match a.kind {
        Kind::Surgical => {
            let n = a.n.unwrap_or(SURGICAL_DEFAULT_N);
            if let Some(dir) = &a.obj_out {
                write_surfaces(dir, n, a.seed, &a.output)?;
            }
            surgical(n, a.seed)?
        }
        Kind::Uniform => uniform(a.n.unwrap_or(10_000), a.seed, a.density)?,
        Kind::Mesh => {
            if a.n.is_some() {
                bail!("--n is not for `scene mesh`: the meshes' faces set the number of boxes");
            }
            from_meshes(&mesh_specs(matches)?)?
        }
    };
    scene.validate()?;
    scene.save(&a.output)?;
    eprintln!("wrote {} obbs to {}", scene.obbs.len(), a.output.display());
    Ok(())
}

/// One mesh of `scene mesh` with the options given after it.
#[derive(Debug, PartialEq)]
pub struct MeshSpec {
    pub path: PathBuf,
    pub stl: bool,
    pub thickness: f64,
    pub group: u32,
}

/// The meshes in the order given, each with the --thickness and --group between it and the
/// next mesh (clap's derive keeps each option's values but not their order among options, so
/// the order comes from the matches' indices).
fn mesh_specs(m: &ArgMatches) -> Result<Vec<MeshSpec>> {
    enum Item {
        Obj(PathBuf),
        Stl(PathBuf),
        Thickness(f64),
        Group(u32),
    }
    fn indexed<T: Clone + Send + Sync + 'static>(
        m: &ArgMatches,
        id: &str,
        item: fn(T) -> Item,
    ) -> Vec<(usize, Item)> {
        match (m.indices_of(id), m.get_many::<T>(id)) {
            (Some(at), Some(values)) => at.zip(values.cloned().map(item)).collect(),
            _ => Vec::new(),
        }
    }
    let mut items = indexed(m, "obj", Item::Obj);
    items.extend(indexed(m, "stl", Item::Stl));
    items.extend(indexed(m, "thickness", Item::Thickness));
    items.extend(indexed(m, "group", Item::Group));
    items.sort_by_key(|(at, _)| *at);
    let mut given: Vec<Given> = Vec::new();
    for (_, item) in items {
        match item {
            Item::Obj(path) => given.push(Given::new(path, false)),
            Item::Stl(path) => given.push(Given::new(path, true)),
            Item::Thickness(t) => {
                let g = mesh_before(&mut given, "--thickness", t)?;
                if g.thickness.replace(t).is_some() {
                    bail!("{} has two --thickness", g.path.display());
                }
            }
            Item::Group(n) => {
                let g = mesh_before(&mut given, "--group", n)?;
                if g.group.replace(n).is_some() {
                    bail!("{} has two --group", g.path.display());
                }
            }
        }
    }
    if given.is_empty() {
        bail!("`scene mesh` needs at least one --obj or --stl file");
    }
    let mut thickness = None;
    given
        .into_iter()
        .map(|g| {
            thickness = g.thickness.or(thickness);
            let Some(thickness) = thickness else {
                bail!("{} needs a --thickness after it", g.path.display());
            };
            Ok(MeshSpec {
                path: g.path,
                stl: g.stl,
                thickness,
                group: g.group.unwrap_or(0),
            })
        })
        .collect()
}

/// A mesh as given: its file and the options after it.
struct Given {
    path: PathBuf,
    stl: bool,
    thickness: Option<f64>,
    group: Option<u32>,
}

impl Given {
    fn new(path: PathBuf, stl: bool) -> Given {
        Given {
            path,
            stl,
            thickness: None,
            group: None,
        }
    }
}

/// The mesh an option given after it applies to.
fn mesh_before<'a>(
    given: &'a mut [Given],
    flag: &str,
    value: impl std::fmt::Display,
) -> Result<&'a mut Given> {
    given.last_mut().ok_or_else(|| {
        anyhow::anyhow!(
            "{flag} {value} comes before any --obj or --stl: it applies to the mesh before it"
        )
    })
}

/// The boxes of every mesh, in the order given.
fn from_meshes(specs: &[MeshSpec]) -> Result<Scene> {
    let mut obbs = Vec::new();
    for s in specs {
        let mesh = if s.stl {
            read_stl(&s.path)?
        } else {
            read_obj(&s.path)?
        };
        let boxes = mesh_boxes(&mesh, s.thickness, s.group)
            .with_context(|| format!("mesh {}", s.path.display()))?;
        eprintln!(
            "{}: {} faces, {} boxes (group {}, thickness {} mm)",
            s.path.display(),
            mesh.faces.len(),
            boxes.len(),
            s.group,
            s.thickness
        );
        obbs.extend(boxes);
    }
    Ok(Scene { obbs })
}

/// The surgical scene's surfaces as `dir/group<G>.obj`, and the command that makes the scene
/// (`output`) from them.
fn write_surfaces(dir: &Path, n: usize, seed: u64, output: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut command = String::from("obbcd scene mesh");
    for s in surgical_meshes(n, seed)? {
        let path = dir.join(format!("group{}.obj", s.group));
        std::fs::write(&path, obj_text(&s.mesh, &format!("group{}", s.group)))
            .with_context(|| format!("cannot write {}", path.display()))?;
        command += &format!(
            " --obj {} --thickness {} --group {}",
            path.display(),
            s.thickness,
            s.group
        );
    }
    eprintln!(
        "wrote the surfaces to {}; the same scene from them: {command} -o {}",
        dir.display(),
        output.display()
    );
    Ok(())
}
