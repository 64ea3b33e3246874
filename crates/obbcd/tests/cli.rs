//! The command line end to end: scene -> detect -> pairs file, and clear errors on bad input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn obbcd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obbcd"))
        .args(args)
        .output()
        .expect("obbcd runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("obbcd-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn field<'a>(line: &'a str, key: &str) -> &'a str {
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key}= in `{line}`"))
}

#[test]
fn scene_detect_and_stats() {
    let scene = tmp("s.json");
    let out = obbcd(&[
        "scene",
        "surgical",
        "--n",
        "1200",
        "--seed",
        "4",
        "-o",
        scene.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut results = Vec::new();
    for engine in ["brute", "sap", "improved-sap", "sweep", "grid"] {
        let pairs = tmp(&format!("{engine}.json"));
        let out = obbcd(&[
            "detect",
            "--scene",
            scene.to_str().unwrap(),
            "--engine",
            engine,
            "--groups",
            "cross",
            "--repeat",
            "3",
            "-o",
            pairs.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let line = String::from_utf8(out.stdout).unwrap();
        assert_eq!(field(&line, "engine"), engine);
        assert_eq!(field(&line, "obbs"), "1200");
        field(&line, "time_ms").parse::<f64>().unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&pairs).unwrap()).unwrap();
        let list = json["pairs"].as_array().unwrap().clone();
        assert_eq!(list.len().to_string(), field(&line, "pairs"));
        results.push(list);
    }
    assert!(results.iter().all(|r| *r == results[0]));
    let out = obbcd(&["stats", "--scene", scene.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("groups\tpairs\toverlap_x"));
    assert_eq!(
        text.lines().count(),
        1 + 1 + 6 + 1,
        "header, all, six group pairs, grid"
    );
    assert!(text.lines().last().unwrap().starts_with("grid cell_mm="));
}

#[test]
fn bad_input_fails_with_a_message() {
    let bad = tmp("bad.json");
    std::fs::write(&bad, r#"{"obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,-1,1],"group":0}]}"#).unwrap();
    let empty = tmp("empty.json");
    std::fs::write(&empty, "").unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["detect", "--scene", bad.to_str().unwrap()],
            "obb 0: field `half` has -1",
        ),
        (&["detect", "--scene", empty.to_str().unwrap()], "is empty"),
        (
            &["detect", "--scene", "/no/such.json"],
            "cannot read scene file",
        ),
        (
            &[
                "detect",
                "--scene",
                bad.to_str().unwrap(),
                "--engine",
                "fast",
            ],
            "unknown engine `fast`",
        ),
        (
            &[
                "detect",
                "--scene",
                bad.to_str().unwrap(),
                "--groups",
                "0:1",
            ],
            "not a pair like 0-1",
        ),
        (
            &["scene", "uniform", "--n", "0", "-o", "/tmp/x.json"],
            "--n must be at least 1",
        ),
    ];
    for (args, want) in cases {
        let out = obbcd(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
        assert!(!err.contains("panicked"), "{args:?} panicked");
    }
}
