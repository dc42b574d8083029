//! The numbers of a linkage row at the ends of what a float holds, end to end: a length beyond
//! the documented range refused naming its field (never a panic), a crank axis of huge or tiny
//! components read as its direction.

use crate::support::{self, codesign, fails_saying, scratch};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The planar example `name` (`ball_screw.json`, `four_bar.json`) at 10 steps with its robot's
/// path made absolute and `edit` applied to its linkage row, written to `dir/<name>`.
fn example_with(dir: &Path, name: &str, edit: impl Fn(&mut Value)) -> PathBuf {
    let example = support::root().join("robots/examples/planar_2dof");
    let text = std::fs::read_to_string(example.join(name)).unwrap();
    let mut task: Value = serde_json::from_str(&text).unwrap();
    task["robot"] = example.join("robot.urdf").to_str().unwrap().into();
    task["motion"]["steps"] = 10.into();
    edit(&mut task["transmission"]["matrix"][1]);
    let file = dir.join(name);
    std::fs::write(&file, task.to_string()).unwrap();
    file
}

/// A lead or a crank radius of 1e-300 m overflowed G(q) and panicked in nalgebra's SVD ("Singular
/// value was NaN", exit 101), and a subnormal lead passed: `solve` and `check` now refuse each,
/// naming the field and the range.
#[test]
fn a_linkage_length_out_of_range_is_refused_naming_the_field() {
    let dir = scratch("lengths");
    let cases = [
        ("ball_screw.json", "linear", "lead_m", json!(1e-300)),
        ("ball_screw.json", "linear", "lead_m", json!(5e-324)),
        ("four_bar.json", "crank_rod", "radius_m", json!(1e-300)),
        ("four_bar.json", "crank_rod", "rod_m", json!(1e-300)),
    ];
    for (name, kind, field, value) in cases {
        let task = example_with(&dir, name, |row| match field {
            "radius_m" => row[kind]["crank"][field] = value.clone(),
            _ => row[kind][field] = value.clone(),
        });
        let path = if field == "radius_m" {
            "crank.radius_m"
        } else {
            field
        };
        let expected =
            format!("transmission.matrix[1].{kind}.{path} = {value} m is outside [1e-6, 100] m");
        let task = task.to_str().unwrap();
        fails_saying(
            &codesign(&["solve", "--task", task, "--payload", "0.5"]),
            &expected,
        );
        fails_saying(&codesign(&["check", "--task", task]), &expected);
    }
}

/// A crank axis [0, -1e308, 0] was normalised to zero (its norm overflowed) and solved to a
/// wrong J with exit 0, while [0, -1e-300, 0] was refused as zero: both are [0, -1, 0].
#[test]
fn a_crank_axis_of_huge_or_tiny_components_solves_as_its_direction() {
    let dir = scratch("axes");
    let cost = |axis: Value| {
        let task = example_with(&dir, "four_bar.json", |row| {
            row["crank_rod"]["crank"]["axis"] = axis.clone();
        });
        let out = dir.join("out.json");
        let args = ["solve", "--task", task.to_str().unwrap()];
        let (_, result) = support::succeed_with_out(&args, &out);
        result["cost"].as_f64().unwrap()
    };
    let unit = cost(json!([0, -1, 0]));
    assert_eq!(cost(json!([0, -1e308, 0])), unit);
    assert_eq!(cost(json!([0, -1e-300, 0])), unit);
}

/// The ball screw with its forearm anchor on the forearm's axis, [0.1, 0, 0], at 10 steps: its
/// optimum jumps the elbow across 0, where the screw's ratio changes sign, between two nodes. The
/// result said feasible; it is infeasible, listing the crossing, and `check` names the angle.
#[test]
fn a_screw_passing_its_dead_point_between_nodes_is_infeasible_and_checked() {
    let dir = scratch("dead");
    let task = example_with(&dir, "ball_screw.json", |row| {
        row["linear"]["to"]["point"] = json!([0.1, 0, 0]);
    });
    let task = task.to_str().unwrap();
    let out = dir.join("out.json");
    let (stdout, result) = support::succeed_with_out(&["solve", "--task", task], &out);
    assert_eq!(result["feasible"], json!(false), "{stdout}");
    assert_eq!(result["dead_points"][0]["motors"], json!([1]));
    let reason = result["reason"].as_str().unwrap();
    assert!(
        reason.contains("the linkage of motor 2 passes a dead point"),
        "{reason}"
    );
    let output = codesign(&["check", "--task", task]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        text.contains("its ratio to joint elbow changes sign")
            && text.contains("the motor passes a dead point near elbow = "),
        "{text}"
    );
}
