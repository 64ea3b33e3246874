//! A cache of slow builds (simulators, yosys netlists), keyed by the SHA-256 of everything the
//! build reads. An entry is built in a directory of its own and renamed into place when
//! complete, so that concurrent builds (two shells) never see half-built files; within one
//! process (parallel tests) builds of one entry take turns.

use anyhow::{bail, Context, Result};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The cache directory: `$OBBCD_CACHE`, else `$XDG_CACHE_HOME/obbcd`, else `~/.cache/obbcd`,
/// else below the system's temporary directory.
pub fn default_dir() -> PathBuf {
    let var = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    var("OBBCD_CACHE")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("obbcd")))
        .or_else(|| var("HOME").map(|d| d.join(".cache/obbcd")))
        .unwrap_or_else(|| std::env::temp_dir().join("obbcd-cache"))
}

/// A key from the build's inputs: the first 16 hex digits of their SHA-256.
pub fn key(parts: &[&[u8]]) -> String {
    let mut h = Sha256::new();
    for p in parts {
        h.update((p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.finalize()[..8]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The entry `name` in `cache` if it is built, without building it.
pub fn built(cache: &Path, name: &str) -> Option<PathBuf> {
    let dir = cache.join(name);
    dir.join("ok").is_file().then_some(dir)
}

/// The entry `name` in `cache`, built by `build` (in a fresh directory) if it is not there yet.
/// Returns the entry's directory and whether it was already built.
pub fn entry(
    cache: &Path,
    name: &str,
    build: impl FnOnce(&Path) -> Result<()>,
) -> Result<(PathBuf, bool)> {
    // One build of an entry at a time in this process: threads that want the same entry wait
    // for it instead of building it again, while other entries build beside it (a yosys
    // synthesis takes one core for minutes). A poisoned lock only means another build failed.
    static BUILDING: Mutex<BTreeMap<PathBuf, Arc<Mutex<()>>>> = Mutex::new(BTreeMap::new());
    let this = BUILDING
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .entry(cache.join(name))
        .or_default()
        .clone();
    let _one = this.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(dir) = built(cache, name) {
        return Ok((dir, true));
    }
    let dir = cache.join(name);
    std::fs::create_dir_all(cache).with_context(|| format!("cannot create {}", cache.display()))?;
    // (Removed when dropped: a build that fails leaves nothing in the cache.)
    let work = tempfile::Builder::new()
        .prefix(&format!("{name}."))
        .suffix(".tmp")
        .tempdir_in(cache)
        .with_context(|| format!("cannot create a directory in {}", cache.display()))?;
    build(work.path())?;
    std::fs::write(work.path().join("ok"), "")?;
    let work = work.keep();
    if std::fs::rename(&work, &dir).is_err() {
        // Another build of the same key finished first: use it.
        let _ = std::fs::remove_dir_all(&work);
        if !dir.join("ok").is_file() {
            bail!("cannot move the build into {}", dir.display());
        }
    }
    Ok((dir, false))
}
