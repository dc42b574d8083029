//! A task file's sections written as arrays: serde's derived structs read a sequence of their
//! fields in order, so `"motors": [0.6, 250]` was read as a torque limit of 0.6 N m and a speed
//! limit of 250 rad/s. Every object of the task, its `experiment` and its `solver` section is
//! refused as an array, naming the field.

use super::task::TaskFile;
use crate::solve::SolveSettings;
use std::path::Path;

/// The task file `path` (in the repository) with `from` replaced by `to` must fail naming
/// `field` (with its line where the task's own reader names it) as an array where an object is
/// expected.
fn refused(path: &str, from: &str, to: &str, field: &str) {
    let path = crate::testing::repository().join(path);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{from}");
    let folder = path.parent().unwrap_or(Path::new("."));
    let edited = text.replacen(from, to, 1);
    let error = TaskFile::from_text(&edited, "edited", folder)
        .unwrap_err()
        .to_string();
    let expected = "invalid type: an array, expected an object (write its fields by name)";
    assert!(
        [" at line ", ": "]
            .iter()
            .any(|after| error.contains(&format!("edited: {field}{after}")))
            && error.ends_with(expected),
        "{field}: {error}"
    );
}

#[test]
fn a_section_written_as_an_array_is_refused_naming_it() {
    let task = "robots/tasks/pick_place.json";
    let point = r#"{ "link": "link_4", "point": [0.0, 0.0, 0.15] }"#;
    let listed = r#"["link_4", [0.0, 0.0, 0.15]]"#;
    refused(
        task,
        &format!(r#""tcp": {point}"#),
        &format!(r#""tcp": {listed}"#),
        "tcp",
    );
    refused(
        task,
        &format!(r#""payload": {{ "mass_kg": 0.0, "at": {point} }}"#),
        &format!(r#""payload": [0.0, {point}]"#),
        "payload",
    );
    refused(
        task,
        &format!(r#""at": {point}"#),
        &format!(r#""at": {listed}"#),
        "payload.at",
    );
    refused(
        task,
        r#""motors": { "torque_limit_nm": 1.7, "speed_limit_rad_s": 100.0 }"#,
        r#""motors": [1.7, 100.0]"#,
        "motors",
    );
    refused(
        task,
        r#""weights": { "position": 0.01, "velocity": 0.01, "control": 0.001 }"#,
        r#""weights": [0.01, 0.01, 0.001]"#,
        "weights",
    );
    refused(
        task,
        r#""limit_modes": { "torque": "paper", "speed": "exact" }"#,
        r#""limit_modes": ["paper", "exact"]"#,
        "limit_modes",
    );
    refused(
        task,
        r#""y": { "range": [-1.0, 0.4], "weight": 1000.0 }"#,
        r#""y": [[-1.0, 0.4], 1000.0]"#,
        "cartesian_box.y",
    );
    refused(
        task,
        r#""cartesian_box": {
    "y": { "range": [-1.0, 0.4], "weight": 1000.0 },
    "z": { "range": [-0.9, 0.6], "weight": 1000.0 }
  }"#,
        r#""cartesian_box": [null, { "range": [-1.0, 0.4], "weight": 1000.0 }, null]"#,
        "cartesian_box",
    );
    refused(
        task,
        r#""motion": {
    "start": [0.0, 1.8849555921538759, 0.0, 0.0],
    "goal": [-3.141592653589793, -1.5707963267948966, -1.5707963267948966, 0.0],
    "horizon_s": 0.8,
    "steps": 50,
    "ends": "paper"
  }"#,
        r#""motion": [[0.0, 1.88, 0.0, 0.0], [-3.14, -1.57, -1.57, 0.0], 0.8, 50, "paper"]"#,
        "motion",
    );
    refused(
        task,
        r#""transmission": {
    "matrix": [
      ["r1", 0, 0, 0],
      ["r2", "r2", 0, 0],
      [1, "r3", "r4", "r4"],
      [1, "r3", "r4", "-r4"]
    ],
    "original": [6.0, 3.0, 1.0, 1.0],
    "bounds": [[1.0, 9.0], [1.0, 9.0], [1.0, 3.0], [1.0, 3.0]],
    "order": ["r3 <= r2", "r2 < r1"]
  }"#,
        r#""transmission": [[["r1", 0, 0, 0], ["r2", "r2", 0, 0], [1, "r3", "r4", "r4"],
            [1, "r3", "r4", "-r4"]], [6.0, 3.0, 1.0, 1.0],
            [[1.0, 9.0], [1.0, 9.0], [1.0, 3.0], [1.0, 3.0]], ["r3 <= r2", "r2 < r1"]]"#,
        "transmission",
    );
    refused(
        task,
        r#""limit_modes""#,
        r#""experiment": {"budget": [5, 40, 60, 40, 60]}, "limit_modes""#,
        "experiment.budget",
    );
    refused(
        task,
        r#""limit_modes""#,
        r#""experiment": [[0.0], [1.0], null, null, null, null], "limit_modes""#,
        "experiment",
    );
    refused(
        "robots/examples/planar_2dof/ball_screw.json",
        r#""from": { "link": "upper_arm", "point": [0.15, 0, 0] }"#,
        r#""from": ["upper_arm", [0.15, 0, 0]]"#,
        "transmission.matrix[1].linear.from",
    );
}

/// The `solver` section, read apart from the task, is held to the same rule.
#[test]
fn a_solver_section_written_as_an_array_is_refused() {
    let error = SolveSettings::from_section(Some(&serde_json::json!([1e-8, 3000])))
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("solver: invalid type: an array, expected an object"),
        "{error}"
    );
}
