//! Scene files: the exact JSON form, and clear errors naming the OBB and the field.

use obb_model::generate::{surgical, uniform, GenerateError};
use obb_model::{Obb, Scene, SceneError};

fn err(json: &str) -> String {
    Scene::from_json(json, "t.json").unwrap_err().to_string()
}

fn one(center: &str, axes: &str, half: &str) -> String {
    format!(
        r#"{{"obbs":[{{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1],"group":0}},{{"center":{center},"axes":{axes},"half":{half},"group":1}}]}}"#
    )
}

const I: &str = "[[1,0,0],[0,1,0],[0,0,1]]";

#[test]
fn reads_and_writes_the_interchange_form_exactly() {
    let json = r#"{"obbs":[{"center":[1.5,-2.0,3.25],"axes":[[1.0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,1.0]],"half":[0.5,0.25,0.0],"group":2}]}"#;
    let s = Scene::from_json(json, "t").unwrap();
    assert_eq!(s.obbs[0].half, [0.5, 0.25, 0.0]);
    assert_eq!(s.obbs[0].group, 2);
    assert_eq!(s.to_json(), json);
    // Round trip of a generated scene is bit-exact, and extra fields are ignored.
    let g = surgical(300, 9).unwrap();
    assert_eq!(Scene::from_json(&g.to_json(), "g").unwrap(), g);
    let extra = r#"{"name":"x","obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1],"group":0,"color":"red"}]}"#;
    assert_eq!(Scene::from_json(extra, "e").unwrap().obbs.len(), 1);
}

#[test]
fn bad_input_is_an_error_naming_the_obb_and_field() {
    assert!(err("").contains("is empty"));
    assert!(err("  \n").contains("is empty"));
    assert!(err("{\"obbs\":[").contains("not a valid scene"));
    assert!(err("[1,2]").contains("not a valid scene"));
    assert!(
        err(r#"{"obbs":[{"center":[0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]}]}"#)
            .contains("not a valid scene")
    );
    let cases = [
        (one("[0,0,1e400]", I, "[1,1,1]"), "not a valid scene"),
        (one("[0,0,2e6]", I, "[1,1,1]"), "obb 1: field `center`"),
        (
            one("[0,0,0]", I, "[1,-0.5,1]"),
            "obb 1: field `half` has -0.5",
        ),
        (one("[0,0,0]", I, "[1,1,3e6]"), "obb 1: field `half`"),
        (
            one("[0,0,0]", "[[1,0,0],[0,1,0],[0,1,0]]", "[1,1,1]"),
            "obb 1: field `axes` are not orthonormal",
        ),
        (
            one("[0,0,0]", "[[1.001,0,0],[0,1,0],[0,0,1]]", "[1,1,1]"),
            "obb 1: field `axes` are not orthonormal",
        ),
    ];
    for (json, want) in cases {
        let e = err(&json);
        assert!(e.contains(want), "`{e}` should contain `{want}`");
    }
    // Values JSON cannot carry are caught when a scene is built in code.
    let mut s = Scene {
        obbs: vec![Obb::aligned([0.0; 3], [1.0; 3], 0); 3],
    };
    s.obbs[2].axes[1][2] = f64::NAN;
    assert!(s
        .validate()
        .unwrap_err()
        .to_string()
        .contains("obb 2: field `axes` has NaN"));
    s.obbs[2] = Obb::aligned([f64::INFINITY, 0.0, 0.0], [1.0; 3], 0);
    assert!(s
        .validate()
        .unwrap_err()
        .to_string()
        .contains("obb 2: field `center` has inf"));
    assert!(matches!(
        Scene::load(std::path::Path::new("/no/such/file.json")),
        Err(SceneError::Io { .. })
    ));
}

#[test]
fn single_precision_rotations_are_accepted() {
    // Axes rounded to f32 are orthonormal to about 1e-7: accepted (the limit is 1e-5).
    let u = uniform(2000, 4, 0.1).unwrap();
    let mut s = u.clone();
    for o in s.obbs.iter_mut() {
        o.axes = o.axes.map(|r| r.map(|v| v as f32 as f64));
    }
    s.validate().unwrap();
    let worst = s.obbs.iter().map(Obb::ortho_error).fold(0.0, f64::max);
    assert!(worst > 1e-9 && worst < 1e-6, "f32 rounding error {worst}");
}

#[test]
fn generators_are_deterministic_exact_in_count_and_valid() {
    for n in [1, 2, 7, 100, 1001, 17_500] {
        let s = surgical(n, 1).unwrap();
        assert_eq!(s.obbs.len(), n);
        s.validate().unwrap();
        assert_eq!(s, surgical(n, 1).unwrap());
    }
    let s = surgical(17_500, 1).unwrap();
    let count = |g| s.obbs.iter().filter(|o| o.group == g).count();
    assert_eq!((count(0), count(1), count(2)), (10_000, 3_750, 3_750));
    assert_ne!(surgical(500, 1).unwrap(), surgical(500, 2).unwrap());
    let u = uniform(1000, 3, 0.2).unwrap();
    assert_eq!(u.obbs.len(), 1000);
    u.validate().unwrap();
    assert_eq!(u, uniform(1000, 3, 0.2).unwrap());
    assert_eq!(surgical(0, 1).unwrap_err(), GenerateError::TooFew(0));
    assert_eq!(
        uniform(10, 1, 0.0).unwrap_err(),
        GenerateError::Density(0.0)
    );
    assert_eq!(
        uniform(10, 1, f64::NAN).unwrap_err().to_string(),
        "--density must be a number in (0, 100], got NaN"
    );
}

#[test]
fn surgical_jaws_touch_the_tissue() {
    use obb_model::{detect, EngineKind, GroupMask, Prepared};
    let s = surgical(17_500, 1).unwrap();
    let mut prepared = Prepared::default();
    let boxes = prepared.update(&s.obbs);
    let (pairs, _) = detect(
        EngineKind::Grid,
        &boxes,
        &GroupMask::Pairs(vec![(0, 1), (0, 2)]),
    );
    let by = |g: u32| {
        pairs
            .iter()
            .filter(|p| s.obbs[p[1] as usize].group == g)
            .count()
    };
    assert!(
        by(1) > 0 && by(2) > 0,
        "both grippers reach the tissue: {} {}",
        by(1),
        by(2)
    );
    // Only the jaw tips: a handful of contacts, not a gripper buried in tissue.
    assert!(pairs.len() < 200, "{} tissue contacts", pairs.len());
}
