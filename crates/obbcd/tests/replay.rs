//! `obbcd replay`: the built-in moving scene's pairs frame by frame against brute force on
//! frames the test assembles itself, recordings in both formats replaying the same, the summary,
//! clear errors on bad frame files, and the frames beside a neighbour's reads.

mod common;

use common::{fails_with, field, ok, Scratch};
use obb_model::generate::SurgicalMotion;
use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared};
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The CSV's rows as (t_ms, tissue_update, pairs), the latency left out.
fn rows(csv: &Path) -> Vec<(String, String, usize)> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("frame,t_ms,tissue_update,latency_ms,pairs")
    );
    lines
        .enumerate()
        .map(|(k, line)| {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f[0], k.to_string());
            assert!(f[3].parse::<f64>().unwrap() >= 0.0);
            (f[1].to_string(), f[2].to_string(), f[4].parse().unwrap())
        })
        .collect()
}

/// The built-in scene's run the tests check: 700 boxes, 600 frames.
const RUN: [&str; 7] = ["replay", "--n", "700", "--seed", "3", "--frames", "600"];

/// 700 boxes, 600 frames: the grippers come down into the tissue. Every 10th frame's pairs are
/// those brute force finds on the scene assembled here from the motion's frames (each frame
/// replaces its groups' boxes; the scene lists them by group).
#[test]
fn builtin_frames_give_brute_forces_pairs() {
    let scratch = Scratch::new();
    let csv = scratch.file("builtin.csv");
    let out = ok(&[&RUN[..], &["--csv", s(&csv)]].concat());
    let line = String::from_utf8(out.stdout).unwrap();
    assert_eq!(field(&line, "frames"), "600");
    assert_eq!(field(&line, "tissue_updates"), "15");
    assert_eq!(field(&line, "haptic_frames"), "585");
    assert_eq!(field(&line, "groups"), "cross");
    for key in ["p50_ms", "p99_ms", "max_ms", "tissue_p99_ms"] {
        assert!(field(&line, key).parse::<f64>().unwrap() > 0.0, "{key}");
    }
    let got = rows(&csv);
    assert_eq!(got.len(), 600);
    let motion = SurgicalMotion::new(700, 3).unwrap();
    let mut by_group: Vec<Vec<Obb>> = vec![Vec::new(); 3];
    let mut prepared = Prepared::default();
    let mut touching = 0;
    for (k, row) in got.iter().enumerate() {
        let f = motion.frame(k);
        assert_eq!(row.0, f.t_ms.to_string(), "frame {k}");
        assert_eq!(row.1, (k % 40 == 0).to_string(), "frame {k}");
        for g in &f.replace {
            by_group[*g as usize] = f.obbs.iter().filter(|b| b.group == *g).cloned().collect();
        }
        if k % 10 == 0 {
            let scene: Vec<Obb> = by_group.concat();
            let frame = prepared.update(&scene);
            let (pairs, _) = detect(EngineKind::Brute, &frame, &GroupMask::Cross);
            assert_eq!(row.2, pairs.len(), "frame {k}");
            touching += usize::from(!pairs.is_empty());
        }
    }
    assert!(touching > 10, "the grippers reach the tissue: {touching}");
    assert_eq!(got[0].2, 0, "the grippers start above the tissue");
    // The tissue resident: the same pairs on every frame, all pairs and cross-group.
    for groups in ["cross", "all"] {
        let (full, resident) = (scratch.file("full.csv"), scratch.file("resident.csv"));
        let run = |csv: &Path, extra: &[&str]| {
            let mut args = [&RUN[..], &["--groups", groups, "--csv", s(csv)]].concat();
            args.extend(extra);
            String::from_utf8(ok(&args).stdout).unwrap()
        };
        run(&full, &[]);
        let line = run(&resident, &["--resident"]);
        assert_eq!(field(&line, "resident"), "0");
        assert_eq!(rows(&resident), rows(&full), "{groups}");
        // Through the C ABI, as a C caller runs it.
        let capi = scratch.file("capi.csv");
        let line = run(&capi, &["--capi"]);
        assert_eq!(field(&line, "capi"), "1");
        assert_eq!(rows(&capi), rows(&full), "{groups}");
        // The grippers as rigid bodies moved by poses.
        let rigid = scratch.file("rigid.csv");
        let line = run(&rigid, &["--rigid"]);
        assert_eq!(field(&line, "rigid"), "1");
        assert_eq!(field(&line, "obbs"), "700");
        assert_eq!(rows(&rigid), rows(&full), "{groups}");
        // And posed through the C ABI.
        let line = run(&rigid, &["--rigid", "--capi"]);
        assert_eq!((field(&line, "rigid"), field(&line, "capi")), ("1", "1"));
        assert_eq!(field(&line, "obbs"), "700");
        assert_eq!(rows(&rigid), rows(&full), "{groups}");
    }
}

/// A run recorded as JSON lines replays to the same rows as the built-in scene; a binary
/// recording (single precision) replays to the same rows as its own JSON lines re-recording.
#[test]
fn recordings_replay_the_same() {
    let scratch = Scratch::new();
    let run = |extra: &[&str], csv: &Path| {
        let mut args = vec!["replay", "--csv", s(csv)];
        args.extend(extra);
        ok(&args);
        rows(csv)
    };
    let common = ["--n", "350", "--seed", "2", "--frames", "450"];
    let (jsonl, bin, again) = (
        scratch.file("r.jsonl"),
        scratch.file("r.bin"),
        scratch.file("again.jsonl"),
    );
    let builtin = run(
        &[&common[..], &["--record", s(&jsonl)]].concat(),
        &scratch.file("a.csv"),
    );
    assert!(builtin.iter().any(|r| r.2 > 0), "some frame has pairs");
    assert_eq!(
        run(&["--input", s(&jsonl)], &scratch.file("b.csv")),
        builtin
    );
    run(
        &[&common[..], &["--record", s(&bin)]].concat(),
        &scratch.file("c.csv"),
    );
    let binary = run(
        &["--input", s(&bin), "--record", s(&again)],
        &scratch.file("d.csv"),
    );
    assert_eq!(run(&["--input", s(&again)], &scratch.file("e.csv")), binary);
    let short = run(
        &["--input", s(&bin), "--frames", "7"],
        &scratch.file("f.csv"),
    );
    assert_eq!(short[..], binary[..7]);
    // 8-byte header, then per frame (12 of them with the tissue's 200 boxes): t_ms, group count and groups, box count, 64 bytes a box.
    let size = std::fs::metadata(&bin).unwrap().len();
    let boxes: u64 = 12 * 200 + 450 * 150;
    let groups: u64 = 450 * 2 + 12;
    assert_eq!(size, 8 + 450 * (8 + 4 + 4) + 4 * groups + 64 * boxes);
}

/// `--neighbour-mb` runs its reads beside the frames, on a core the worker threads leave free
/// (with none free it refuses), and the summary gives their size and pace.
#[test]
fn replay_beside_a_neighbour() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let all = cores.to_string();
    fails_with(&[(
        &[
            "--threads",
            all.as_str(),
            "replay",
            "--frames",
            "5",
            "--neighbour-mb",
            "2",
        ],
        "--neighbour-mb needs a core of its own beside the",
    )]);
    assert!(
        cores >= 2,
        "a neighbour beside one worker thread needs two cores"
    );
    let out = ok(&[
        "--threads",
        "1",
        "replay",
        "--n",
        "700",
        "--frames",
        "100",
        "--rigid",
        "--neighbour-mb",
        "2",
    ]);
    let line = String::from_utf8(out.stdout).unwrap();
    assert_eq!(field(&line, "frames"), "100");
    assert_eq!(field(&line, "neighbour_mb"), "2");
    let ns: f64 = field(&line, "neighbour_ns").parse().unwrap();
    assert!(ns > 0.0 && ns < 1e5, "{ns} ns a load");
}

/// [`Scratch::write`], the path as a string.
fn file(scratch: &Scratch, name: &str, bytes: &[u8]) -> String {
    s(&scratch.write(name, bytes)).to_string()
}

#[test]
fn bad_frame_files_fail_with_a_message() {
    let scratch = Scratch::new();
    let frame = |replace: &str, group: u32| {
        format!(
            r#"{{"t_ms":0,"replace":{replace},"obbs":[{{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1],"group":{group}}}]}}"#
        )
    };
    let good = frame("[0]", 0);
    let wrong_group = file(
        &scratch,
        "wrong.jsonl",
        format!("{good}\n{}\n", frame("[1]", 0)).as_bytes(),
    );
    let bad_json = file(
        &scratch,
        "bad.jsonl",
        format!("{good}\n\n{{\"t_ms\":\n").as_bytes(),
    );
    let empty = file(&scratch, "empty.jsonl", b"");
    let magic = file(&scratch, "magic.bin", b"NOTFRAMExxxx");
    let mut cut = b"OBBFRM01".to_vec();
    cut.extend(0f64.to_le_bytes());
    cut.extend(1u32.to_le_bytes());
    cut.extend(0u32.to_le_bytes());
    cut.extend(2u32.to_le_bytes());
    cut.extend([0u8; 64]);
    let cut = file(&scratch, "cut.bin", &cut);
    let good_file = file(&scratch, "good.jsonl", good.as_bytes());
    let cases: Vec<(Vec<&str>, String)> = vec![
        (vec!["replay", "--input", &wrong_group], format!("{wrong_group}: frame 1: box 0 has group 0, not one of the groups the frame replaces [1]")),
        (vec!["replay", "--input", &bad_json], format!("{bad_json} line 3")),
        (vec!["replay", "--input", &empty], format!("{empty} holds no frame")),
        (vec!["replay", "--input", &magic], "is not an obbcd frame file".into()),
        (vec!["replay", "--input", &cut], format!("{cut}: frame 0 is cut short")),
        (vec!["replay", "--input", &good_file, "--n", "5"], "--n is for the built-in scene".into()),
        (vec!["replay", "--frames", "0"], "--frames must be at least 1".into()),
        (vec!["replay", "--resident", "--engine", "sweep"], "--resident, --capi and --rigid keep the tissue in a grid".into()),
        (vec!["replay", "--rigid", "--engine", "brute"], "--resident, --capi and --rigid keep the tissue in a grid".into()),
        (vec!["replay", "--capi", "--resident"], "cannot be used with".into()),
        (vec!["replay", "--rigid", "--input", &good_file], "cannot be used with".into()),
    ];
    let cases: Vec<(&[&str], &str)> = cases
        .iter()
        .map(|(a, w)| (a.as_slice(), w.as_str()))
        .collect();
    fails_with(&cases);
}
