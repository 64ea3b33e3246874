//! The scene a command runs on: the `--scene` file, or without it the built-in surgical scene
//! (what `obbcd scene surgical` writes), so that the first command a newcomer types runs.

use anyhow::{Context, Result};
use obb_model::generate::{surgical, SURGICAL_DEFAULT_N};
use obb_model::Scene;
use std::path::Path;

/// The seed of generated scenes unless `--seed` says otherwise, the built-in scene's included.
pub const DEFAULT_SEED: u64 = 1;

/// Loads `path`, or generates the built-in surgical scene and says so on stderr.
pub fn scene_or_builtin(path: Option<&Path>) -> Result<Scene> {
    if let Some(path) = path {
        return Ok(Scene::load(path)?);
    }
    let scene = surgical(SURGICAL_DEFAULT_N, DEFAULT_SEED)
        .context("cannot generate the built-in surgical scene")?;
    eprintln!(
        "scene: the built-in surgical scene, {} OBBs (tissue: group 0, two grippers: groups 1 \
         and 2); `obbcd scene surgical -o scene.json` writes it, `--scene FILE` takes another",
        scene.obbs.len()
    );
    Ok(scene)
}
