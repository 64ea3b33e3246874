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

/// A test's own scratch directory, removed with everything in it when the test drops it.
pub struct Scratch(tempfile::TempDir);

impl Scratch {
    pub fn new() -> Self {
        Self(
            tempfile::Builder::new()
                .prefix("obbcd-cli-")
                .tempdir()
                .expect("a scratch directory"),
        )
    }

    /// The path of a file `name` in the directory.
    pub fn file(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }

    /// Writes `contents` to the file `name` in the directory; its path.
    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let path = self.file(name);
        std::fs::write(&path, contents).unwrap();
        path
    }
}

#[allow(dead_code)] // not every test binary reads output fields
pub fn field<'a>(line: &'a str, key: &str) -> &'a str {
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key}= in `{line}`"))
}
