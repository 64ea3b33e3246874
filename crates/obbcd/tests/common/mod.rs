//! Running obbcd from the tests: success, failure with a message, scratch files, output fields.

use std::path::PathBuf;
use std::process::{Command, Output};

pub fn obbcd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obbcd"))
        .args(args)
        .output()
        .expect("obbcd runs")
}

/// Runs obbcd and requires success, showing its stderr otherwise.
pub fn ok(args: &[&str]) -> Output {
    let out = obbcd(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Each command fails, without a panic, with a message containing its text and stating each
/// cause once (no part of the `a: b: c` chain repeated).
pub fn fails_with(cases: &[(&[&str], &str)]) {
    for (args, want) in cases {
        let out = obbcd(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
        assert!(!err.contains("panicked"), "{args:?} panicked");
        let parts: Vec<&str> = err.trim().split(": ").collect();
        for (k, part) in parts.iter().enumerate() {
            assert!(
                !parts[k + 1..].contains(part),
                "{args:?}: `{err}` says `{part}` twice"
            );
        }
    }
}

pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("obbcd-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[allow(dead_code)] // not every test binary reads output fields
pub fn field<'a>(line: &'a str, key: &str) -> &'a str {
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key}= in `{line}`"))
}
