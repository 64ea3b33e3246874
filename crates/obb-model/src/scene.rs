//! The scene: a list of oriented bounding boxes, its JSON interchange form and its validation.

use serde::{Deserialize, Serialize};
use std::path::Path;
use thiserror::Error;

/// Largest accepted |coordinate| and half-length, in scene units (mm). Bounding the range keeps
/// every product in the separating-axis test far from overflow and every grid cell index in range.
pub const COORD_LIMIT: f64 = 1.0e6;

/// Most boxes in a scene (engines pack box indices into 29 bits).
pub const MAX_OBBS: usize = 1 << 28;

/// Largest accepted deviation of an OBB's axes from orthonormality: every entry of `A Aᵀ - I`,
/// where the rows of `A` are the three axes, must be at most this. Rotations computed in single
/// precision are orthonormal to about 1e-7; the SAT stays conservative for any deviation up to
/// 1e-3 (docs/sat.md), so this limit only rejects axes that are plainly wrong.
pub const ORTHO_TOL: f64 = 1.0e-5;

/// One oriented bounding box: the set `center + Σ_k t_k · half[k] · axes[k]`, |t_k| ≤ 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obb {
    pub center: [f64; 3],
    /// Three unit direction vectors, one per row.
    pub axes: [[f64; 3]; 3],
    /// Half-lengths along `axes[0]`, `axes[1]`, `axes[2]`.
    pub half: [f64; 3],
    /// Object id: in the surgical scene 0 is tissue, 1 and 2 the instruments.
    #[serde(default)]
    pub group: u32,
}

/// A scene: the OBBs, indexed by their position in `obbs`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    pub obbs: Vec<Obb>,
}

/// What is wrong with a scene file or a scene. Each message states its cause itself (the
/// causes are not also chained as `source`, which would print them twice under `{:#}`).
#[derive(Debug, Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    #[error("cannot write scene file {path}: {cause}")]
    Write { path: String, cause: std::io::Error },
    #[error("scene file {path} is empty")]
    Empty { path: String },
    /// Malformed JSON or a value of the wrong shape; `at` names the OBB and the field where the
    /// parser got that far (`obb 3, field `center``), else the JSON path.
    #[error("scene file {path} is not a valid scene: {at}{cause}")]
    Json {
        path: String,
        at: String,
        cause: serde_json::Error,
    },
    #[error("the scene has {0} obbs, more than the limit of {MAX_OBBS}")]
    TooMany(usize),
    #[error("obb {index}: field `{field}` {problem}")]
    Invalid {
        index: usize,
        field: &'static str,
        problem: String,
    },
}

impl Obb {
    /// An axis-aligned box.
    pub fn aligned(center: [f64; 3], half: [f64; 3], group: u32) -> Obb {
        Obb {
            center,
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            half,
            group,
        }
    }

    /// Largest |entry| of `A Aᵀ - I` (A: the axes as rows), as computed in f64.
    pub fn ortho_error(&self) -> f64 {
        let a = &self.axes;
        let mut worst: f64 = 0.0;
        for i in 0..3 {
            for k in i..3 {
                let g = a[i][0] * a[k][0] + a[i][1] * a[k][1] + a[i][2] * a[k][2];
                let target = if i == k { 1.0 } else { 0.0 };
                worst = worst.max((g - target).abs());
            }
        }
        worst
    }

    /// Checks one OBB; `index` names it in the error.
    pub fn validate(&self, index: usize) -> Result<(), SceneError> {
        let invalid = |field, problem: String| SceneError::Invalid {
            index,
            field,
            problem,
        };
        let in_range = |v: f64| v.is_finite() && v.abs() <= COORD_LIMIT;
        if let Some(v) = self.center.iter().find(|v| !in_range(**v)) {
            return Err(invalid(
                "center",
                format!("has {v}, not a finite number within ±{COORD_LIMIT:e}"),
            ));
        }
        if let Some(v) = self.axes.iter().flatten().find(|v| !v.is_finite()) {
            return Err(invalid("axes", format!("has {v}, not a finite number")));
        }
        if let Some(v) = self.half.iter().find(|v| !v.is_finite()) {
            return Err(invalid("half", format!("has {v}, not a finite number")));
        }
        if let Some(v) = self.half.iter().find(|v| **v < 0.0) {
            return Err(invalid(
                "half",
                format!("has {v}: half-lengths must be >= 0"),
            ));
        }
        if let Some(v) = self.half.iter().find(|v| **v > COORD_LIMIT) {
            return Err(invalid("half", format!("has {v}, above {COORD_LIMIT:e}")));
        }
        let err = self.ortho_error();
        if err > ORTHO_TOL {
            return Err(invalid(
                "axes",
                format!(
                    "are not orthonormal: an entry of A·Aᵀ - I is {err:.3e}, the limit is {ORTHO_TOL:e}"
                ),
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// Checks every OBB; the first problem found is returned.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.obbs.len() > MAX_OBBS {
            return Err(SceneError::TooMany(self.obbs.len()));
        }
        self.obbs
            .iter()
            .enumerate()
            .try_for_each(|(i, obb)| obb.validate(i))
    }

    /// Parses and validates the JSON form.
    pub fn from_json(text: &str, path: &str) -> Result<Scene, SceneError> {
        if text.trim().is_empty() {
            return Err(SceneError::Empty { path: path.into() });
        }
        let mut json = serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(&mut json).map_err(|e| {
            let at = json_location(e.path());
            SceneError::Json {
                path: path.into(),
                at,
                cause: e.into_inner(),
            }
        })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads and validates a JSON scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|cause| SceneError::Io {
            path: name.clone(),
            cause,
        })?;
        Scene::from_json(&text, &name)
    }

    /// The JSON form: `{"obbs":[{"center":..,"axes":..,"half":..,"group":..}, ...]}`.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a scene of finite numbers always serialises")
    }

    /// Writes the JSON form.
    pub fn save(&self, path: &Path) -> Result<(), SceneError> {
        std::fs::write(path, self.to_json()).map_err(|cause| SceneError::Write {
            path: path.display().to_string(),
            cause,
        })
    }
}

/// Where in a scene file the parser stopped, as the validation names it (`obb 3, field
/// `center`: `), or the JSON path outside the boxes; empty at the top level.
fn json_location(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let segments: Vec<&Segment> = path.iter().collect();
    match segments.as_slice() {
        [] => String::new(),
        [Segment::Map { key }, Segment::Seq { index }, rest @ ..] if key == "obbs" => {
            let field: Vec<String> = rest.iter().map(|s| s.to_string()).collect();
            match field.as_slice() {
                [] => format!("obb {index}: "),
                _ => format!(
                    "obb {index}, field `{}`: ",
                    field.join("").trim_start_matches('.')
                ),
            }
        }
        _ => format!("at `{path}`: "),
    }
}
