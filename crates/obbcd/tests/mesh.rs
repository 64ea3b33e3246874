//! `obbcd scene mesh`: scenes from OBJ and STL meshes, checked against the surgical generator's
//! own boxes, on triangle meshes, and on bad meshes.

mod common;

use common::{fails_with, ok, Scratch};
use obb_model::{Obb, Scene};
use std::path::Path;

fn load(path: &Path) -> Scene {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A box's eight corners, sorted: the same set of points whatever the order and signs of its axes.
fn corners(b: &Obb) -> Vec<[f64; 3]> {
    let mut out: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let t = [k & 1, k >> 1 & 1, k >> 2 & 1].map(|bit| if bit == 1 { 1.0 } else { -1.0 });
            std::array::from_fn(|i| {
                b.center[i] + (0..3).map(|a| t[a] * b.half[a] * b.axes[a][i]).sum::<f64>()
            })
        })
        .collect();
    out.sort_by(|p, q| p.partial_cmp(q).unwrap());
    out
}

/// The surgical scene's surfaces, written as OBJ by `scene surgical --obj-out` and made into a
/// scene by `scene mesh` with the printed thicknesses and groups, give the generator's scene:
/// the tissue bit for bit (its boxes are made from its quads by the same function), each
/// gripper box as the same set of points to 1e-9 mm; and `detect` finds the same pairs in both.
#[test]
fn surgical_surfaces_as_obj_make_the_surgical_scene_again() {
    let scratch = Scratch::new();
    let dir = scratch.file("surfaces");
    let (generated, imported) = (
        scratch.file("generated.json"),
        scratch.file("imported.json"),
    );
    let out = ok(&[
        "scene",
        "surgical",
        "--n",
        "1750",
        "--seed",
        "5",
        "--obj-out",
        s(&dir),
        "-o",
        s(&generated),
    ]);
    let said = String::from_utf8(out.stderr).unwrap();
    let command = said
        .split("the same scene from them: obbcd ")
        .nth(1)
        .and_then(|rest| rest.lines().next())
        .expect("the command is printed");
    let args: Vec<&str> = command.split_whitespace().collect();
    assert_eq!(args[args.len() - 1], s(&generated));
    let mut args = args[..args.len() - 1].to_vec();
    args.push(s(&imported));
    ok(&args);
    let (want, got) = (load(&generated), load(&imported));
    assert_eq!(got.obbs.len(), want.obbs.len());
    let tissue = want.obbs.iter().filter(|b| b.group == 0).count();
    assert_eq!(tissue, 1000);
    assert_eq!(got.obbs[..tissue], want.obbs[..tissue], "tissue");
    for (k, (g, w)) in got.obbs.iter().zip(&want.obbs).enumerate().skip(tissue) {
        assert_eq!(g.group, w.group, "box {k}");
        let worst = corners(g)
            .iter()
            .zip(corners(w))
            .flat_map(|(p, q)| (0..3).map(move |i| (p[i] - q[i]).abs()))
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-9,
            "box {k}: corners {worst:e} apart\n{g:?}\n{w:?}"
        );
    }
    let pairs = |scene: &Path, name: &str| {
        let file = scratch.file(name);
        ok(&["detect", "--scene", s(scene), "-o", s(&file)]);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        json["pairs"].clone()
    };
    let want_pairs = pairs(&generated, "generated-pairs.json");
    assert!(want_pairs.as_array().unwrap().len() > 1000);
    assert_eq!(pairs(&imported, "imported-pairs.json"), want_pairs);
}

/// A tilted 10 x 8 grid of 2 x 1.5 mm rectangles, each written to STL as two triangles (with
/// stl_io), comes back as one box per rectangle: its corners inside, 0.3 mm thick, no larger
/// than the rectangle (to f32's rounding). The same rectangles as a triangle soup in OBJ (each
/// triangle its own vertices) merge the same way; a fold does not merge.
#[test]
fn triangles_that_make_a_rectangle_become_one_box() {
    let scratch = Scratch::new();
    // Two orthonormal in-plane directions of a tilted plane.
    let unit = |v: [f64; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / n)
    };
    let e1 = unit([1.0, 0.0, 0.3]);
    let e2 = [0.0, 0.6f64.cos(), 0.6f64.sin()];
    let along: f64 = (0..3).map(|i| e1[i] * e2[i]).sum();
    let e2 = unit(std::array::from_fn(|i| e2[i] - along * e1[i]));
    let point = |x: f64, y: f64| -> [f64; 3] { std::array::from_fn(|i| x * e1[i] + y * e2[i]) };
    let mut rects = Vec::new();
    for i in 0..10 {
        for j in 0..8 {
            let (x, y) = (i as f64 * 2.0, j as f64 * 1.5);
            rects.push([
                point(x, y),
                point(x + 2.0, y),
                point(x + 2.0, y + 1.5),
                point(x, y + 1.5),
            ]);
        }
    }
    let triangles: Vec<[[f64; 3]; 3]> = rects
        .iter()
        .flat_map(|r| [[r[0], r[1], r[2]], [r[0], r[2], r[3]]])
        .collect();
    let stl = scratch.file("grid.stl");
    let mut file = std::fs::File::create(&stl).unwrap();
    let vertex = |p: [f64; 3]| stl_io::Vertex::new(p.map(|c| c as f32));
    let faces: Vec<stl_io::Triangle> = triangles
        .iter()
        .map(|t| stl_io::Triangle {
            normal: stl_io::Normal::new([0.0, 0.0, 1.0]),
            vertices: t.map(vertex),
        })
        .collect();
    stl_io::write_stl(&mut file, faces.iter()).unwrap();
    drop(file);
    let mut text = String::new();
    for t in &triangles {
        for p in t {
            text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
    }
    for k in 0..triangles.len() {
        text += &format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    let obj = scratch.write("grid.obj", text);
    let scene = scratch.file("grid.json");
    ok(&[
        "scene",
        "mesh",
        "--stl",
        s(&stl),
        "--thickness",
        "0.3",
        "--group",
        "2",
        "--obj",
        s(&obj),
        "-o",
        s(&scene),
    ]);
    let boxes = load(&scene).obbs;
    assert_eq!(
        boxes.len(),
        2 * rects.len(),
        "one box per rectangle, per file"
    );
    let area = 2.0 * 1.5;
    for (k, b) in boxes.iter().enumerate() {
        // The STL's boxes take --group 2; the OBJ after it the default 0 and the same thickness.
        assert_eq!(b.group, if k < rects.len() { 2 } else { 0 }, "box {k}");
        let mut half = b.half;
        half.sort_by(f64::total_cmp);
        assert!((half[0] - 0.15).abs() < 1e-5, "box {k}: {half:?}");
        assert!(
            4.0 * half[1] * half[2] <= area * (1.0 + 1e-5),
            "box {k}: {half:?}"
        );
        for p in rects[k % rects.len()] {
            let inside = (0..3).all(|a| {
                let d: f64 = (0..3).map(|i| (p[i] - b.center[i]) * b.axes[a][i]).sum();
                d.abs() <= b.half[a] + 1e-5
            });
            assert!(inside, "box {k}: corner {p:?} outside {b:?}");
        }
    }
}

/// Bad meshes and bad options fail with a message naming the file and the face.
#[test]
fn bad_meshes_are_named() {
    let scratch = Scratch::new();
    let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
    let nan = scratch.write("nan.obj", format!("{square}v nan 0 0\nf 1 2 5\n"));
    let line = scratch.write("line.obj", format!("{square}v 2 0 0\nf 1 2 5\n"));
    let pentagon = scratch.write("pentagon.obj", format!("{square}v 0.5 2 0\nf 1 2 3 5 4\n"));
    let empty = scratch.write("empty.obj", "# nothing\n");
    let good = scratch.write("good.obj", format!("{square}f 1 2 3 4\n"));
    let not_stl = scratch.write(
        "not.stl",
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
    );
    let out = s(&scratch.file("bad.json")).to_string();
    let mesh = |file: &Path, more: &[&'static str]| -> Vec<String> {
        let mut a = vec!["scene".into(), "mesh".into()];
        let kind = if file.extension().unwrap() == "stl" {
            "--stl"
        } else {
            "--obj"
        };
        a.extend([kind.to_string(), s(file).to_string()]);
        a.extend(more.iter().map(|m| m.to_string()));
        a.extend(["-o".to_string(), out.clone()]);
        a
    };
    let cases: Vec<(Vec<String>, String)> = vec![
        (
            mesh(&nan, &["--thickness", "1"]),
            format!(
                "mesh {}: face 0: its vertex [NaN, 0.0, 0.0] has NaN",
                s(&nan)
            ),
        ),
        (
            mesh(&line, &["--thickness", "1"]),
            format!("mesh {}: face 0: is degenerate", s(&line)),
        ),
        (
            mesh(&pentagon, &["--thickness", "1"]),
            "face 0: has 5 vertices".into(),
        ),
        (
            mesh(&empty, &["--thickness", "1"]),
            format!("mesh {}: has no faces", s(&empty)),
        ),
        (
            mesh(&not_stl, &["--thickness", "1"]),
            format!("STL file {} is not a valid STL", s(&not_stl)),
        ),
        (
            mesh(&good, &["--thickness", "-1"]),
            "thickness must be a finite number >= 0, got -1".into(),
        ),
        (
            mesh(&good, &[]),
            format!("{} needs a --thickness after it", s(&good)),
        ),
        (
            mesh(&good, &["--thickness", "1", "--group", "1", "--group", "2"]),
            "has two --group".into(),
        ),
        (
            mesh(&good, &["--thickness", "1", "--n", "5"]),
            "--n is not for `scene mesh`".into(),
        ),
        (
            vec!["scene".into(), "mesh".into(), "-o".into(), out.clone()],
            "needs at least one --obj or --stl".into(),
        ),
        (
            vec![
                "scene".into(),
                "mesh".into(),
                "--group".into(),
                "1".into(),
                "--obj".into(),
                s(&good).into(),
                "-o".into(),
                out.clone(),
            ],
            "--group 1 comes before any --obj or --stl".into(),
        ),
        (
            vec![
                "scene".into(),
                "uniform".into(),
                "--obj".into(),
                s(&good).into(),
                "-o".into(),
                out.clone(),
            ],
            "are for `scene mesh`".into(),
        ),
        (
            vec![
                "scene".into(),
                "uniform".into(),
                "--obj-out".into(),
                "d".into(),
                "-o".into(),
                out.clone(),
            ],
            "--obj-out is for `scene surgical`".into(),
        ),
    ];
    let cases: Vec<(Vec<&str>, &str)> = cases
        .iter()
        .map(|(a, w)| (a.iter().map(String::as_str).collect(), w.as_str()))
        .collect();
    let cases: Vec<(&[&str], &str)> = cases.iter().map(|(a, w)| (a.as_slice(), *w)).collect();
    fails_with(&cases);
}
