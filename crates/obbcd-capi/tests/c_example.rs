//! The C example, built with `cc` against the static library and run: every frame's pairs are
//! those of brute force on the boxes it set placed by the poses it set (read back from its
//! trace), each with its contact, and its bad box and bad pose are refused with a reason.

mod common;

use obb_model::contact::contact;
use obb_model::pose::Pose;
use obb_model::{GroupMask, Obb};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The static library cargo built beside this test (the crate's lib unit, all its types).
fn static_library() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable");
    let lib = exe.parent().expect("deps folder").join("libobbcd_c.a");
    assert!(lib.exists(), "{} was not built", lib.display());
    lib
}

/// Compiles the example `source` with `compiler` in standard `std`, linked with the static
/// library: the executable.
fn build(compiler: &str, std: &str, source: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join(source.replace('.', "_"));
    common::run(
        Command::new(compiler)
            .arg(format!("-std={std}"))
            .args(["-O2", "-Wall", "-Wextra", "-Werror", "-I"])
            .arg(dir.join("include"))
            .arg(dir.join("examples").join(source))
            .arg(static_library())
            .args(["-lpthread", "-ldl", "-lm", "-o"])
            .arg(&exe),
    );
    exe
}

fn numbers(fields: &[&str]) -> Vec<f64> {
    fields
        .iter()
        .map(|f| f.parse().expect("a number"))
        .collect()
}

#[test]
fn c_example_reports_brute_force_pairs_with_contacts() {
    let out = common::run(Command::new(build("cc", "c11", "haptic_loop.c")).arg("--trace"));
    let text = String::from_utf8(out.stdout).expect("UTF-8 output");
    let mut groups: BTreeMap<u32, Vec<Obb>> = BTreeMap::new();
    let mut poses: BTreeMap<u32, Pose> = BTreeMap::new();
    let mut listed: Vec<(u32, u32, u32, u32, [f64; 3], f64)> = Vec::new();
    let (mut frames, mut by_kind) = (0, BTreeMap::new());
    let mut refused = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f[0] {
            "refused:" => refused.push(line.to_string()),
            "box" => {
                let (g, i): (u32, usize) = (f[1].parse().unwrap(), f[2].parse().unwrap());
                let v = numbers(&f[3..]);
                let b = Obb {
                    center: [v[0], v[1], v[2]],
                    axes: [[v[3], v[4], v[5]], [v[6], v[7], v[8]], [v[9], v[10], v[11]]],
                    half: [v[12], v[13], v[14]],
                    group: g,
                };
                let group = groups.entry(g).or_default();
                // A group's boxes come in order from 0: index 0 starts it again.
                if i == 0 {
                    group.clear();
                }
                assert_eq!(group.len(), i, "{line}");
                group.push(b);
            }
            "pose" => {
                let v = numbers(&f[2..]);
                let pose = Pose {
                    rotation: [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]],
                    translation: [v[9], v[10], v[11]],
                };
                poses.insert(f[1].parse().unwrap(), pose);
            }
            "pair" => {
                let ids: Vec<u32> = f[1..5].iter().map(|v| v.parse().unwrap()).collect();
                let v = numbers(&f[5..]);
                listed.push((ids[0], ids[1], ids[2], ids[3], [v[0], v[1], v[2]], v[3]));
            }
            "frame" => {
                // The boxes where their groups' poses place them; the engine's order: the
                // static group 0, then groups 1, 2.
                let placed = groups
                    .iter()
                    .map(|(g, boxes)| {
                        let pose = poses.get(g).copied().unwrap_or(Pose::IDENTITY);
                        (*g, boxes.iter().map(|b| pose.apply(b)).collect())
                    })
                    .collect();
                let want = common::brute(&placed, &[0], &GroupMask::Cross);
                let got: Vec<(u32, u32, u32, u32)> =
                    listed.iter().map(|p| (p.0, p.1, p.2, p.3)).collect();
                let want_ids: Vec<(u32, u32, u32, u32)> = want
                    .iter()
                    .map(|(p, _, _)| (p.group_a, p.index_a, p.group_b, p.index_b))
                    .collect();
                assert_eq!(got, want_ids, "{line}");
                assert_eq!(f[3], want.len().to_string(), "{line}");
                for (p, (_, a, b)) in listed.iter().zip(&want) {
                    // The normal points from the pair's first box to its second.
                    let c = contact(a, b);
                    assert_eq!((p.4, p.5), (c.normal, c.depth), "{line}: {p:?}");
                }
                for p in &listed {
                    *by_kind.entry((p.0, p.2)).or_insert(0) += 1;
                }
                listed.clear();
                frames += 1;
            }
            _ => assert!(line.starts_with("frames=200 "), "{line}"),
        }
    }
    // The example's bad box, then its skewed rotation.
    assert_eq!(refused.len(), 2, "{refused:?}");
    assert!(
        refused[0].contains("status 3") && refused[0].contains("group 1: obb 0: field `half`"),
        "{}",
        refused[0]
    );
    assert!(
        refused[1].contains("status 2")
            && refused[1].contains("group 1: the pose's rotation is not orthonormal"),
        "{}",
        refused[1]
    );
    assert_eq!(poses.len(), 1, "the instrument was never posed");
    assert_eq!(frames, 200);
    // The run is not empty: the instrument meets the tissue and the other instrument.
    assert!(
        by_kind.get(&(0, 1)).is_some_and(|&n| n > 100),
        "{by_kind:?}"
    );
    assert!(by_kind.contains_key(&(1, 2)), "{by_kind:?}");
}

/// The C++ example: its wrapper frees the engine and throws obbcd's reason; the probe's pairs
/// and depths are those worked out by hand from its boxes.
#[test]
fn cpp_example_runs() {
    let exe = build("c++", "c++17", "engine.cpp");
    let out = common::run(&mut Command::new(&exe));
    // The probe spans x in [0.7, 1.3] + 2k and z in [0.05, 0.65]: strip boxes 2k and 2k+1
    // (x in [i, i+1], z in [-0.1, 0.1]), 0.05 deep along z.
    let mut want = String::new();
    for k in 0..5 {
        want += &format!(
            "frame {k}: 0.{}-1.0 depth 0.050 0.{}-1.0 depth 0.050\n",
            2 * k,
            2 * k + 1
        );
    }
    want += "error: group 1: obb 0: field `half` has -1: half-lengths must be >= 0\n";
    assert_eq!(String::from_utf8_lossy(&out.stdout), want);
}
