//! `codesign solve --start FILE`: a solve started from an earlier result's point and
//! multipliers, a start that does not fit refused naming why; and `--fail-if-infeasible`, the
//! exit code a script tells an infeasible design by.

use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;
use support::{codesign_in, fails_saying, read_json, scratch};

/// The built-in task on 10 steps: a solve in a few hundredths of a second.
const SMALL: [&str; 3] = ["solve", "--steps", "10"];

/// `solve` of [`SMALL`] in `space` at `payload` kg with `more`, in `dir`.
fn solve_small(dir: &Path, space: &str, payload: &str, more: &[&str]) -> Output {
    let mut args = SMALL.to_vec();
    args.extend(["--space", space, "--payload", payload]);
    args.extend(more);
    codesign_in(dir, &args)
}

/// Solves [`SMALL`] at 1 kg in the actuation space into `dir/start.json` and returns its path.
fn write_start(dir: &Path) -> PathBuf {
    let output = solve_small(dir, "actuation", "1", &["--out", "start.json"]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    dir.join("start.json")
}

#[test]
fn a_warm_start_lands_on_the_same_optimum_in_fewer_iterations() {
    let dir = scratch("warm");
    let cold = read_json(&write_start(&dir));
    assert!(
        cold["inputs"].get("start").is_none(),
        "a cold solve records no start"
    );
    let point = &cold["start_point"];
    assert_eq!(point["kind"], "hard");
    assert_eq!(
        (point["space"].as_str(), point["steps"].as_u64()),
        (Some("actuation"), Some(10))
    );
    assert_eq!(point["task_hash"], cold["inputs"]["task_hash"]);
    assert_eq!(point["status"], "Solve_Succeeded");
    // 4 n N + 2 n variables (n = 4 joints, N = 10 steps).
    for part in ["x", "z_lower", "z_upper"] {
        assert_eq!(point[part].as_array().unwrap().len(), 168, "{part}");
    }
    assert!(!point["lambda"].as_array().unwrap().is_empty());

    let output = solve_small(
        &dir,
        "actuation",
        "1",
        &["--start", "start.json", "--out", "warm.json"],
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    assert!(
        stdout.contains("started from start.json (its design r = (6, 3, 1, 1), payload 1 kg)"),
        "{stdout}"
    );
    let warm = read_json(&dir.join("warm.json"));
    assert_eq!(warm["feasible"], true);
    let (j_cold, j_warm) = (
        cold["cost"].as_f64().unwrap(),
        warm["cost"].as_f64().unwrap(),
    );
    assert!(
        (j_cold - j_warm).abs() <= 1e-6 * j_cold,
        "{j_cold} vs {j_warm}"
    );
    let (it_cold, it_warm) = (cold["iterations"].as_u64(), warm["iterations"].as_u64());
    assert!(
        it_warm < it_cold,
        "{it_warm:?} iterations warm, {it_cold:?} cold"
    );
    let record = &warm["inputs"]["start"];
    assert_eq!(record["file"], "start.json");
    assert_eq!(record["ratios"], serde_json::json!([6.0, 3.0, 1.0, 1.0]));
    assert_eq!(record["payload_kg"], 1.0);
    // The warm result is a start too.
    assert_eq!(warm["start_point"]["kind"], "hard");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Writes `start` with `edit` applied to `dir/NAME`.
fn edited(dir: &Path, name: &str, start: &Value, edit: impl Fn(&mut Value)) {
    let mut value = start.clone();
    edit(&mut value);
    std::fs::write(dir.join(name), value.to_string()).unwrap();
}

#[test]
fn a_start_that_does_not_fit_is_refused_naming_why() {
    let dir = scratch("refused");
    let start = read_json(&write_start(&dir));
    let refused = |space: &str, more: &[&str], expected: &str| {
        fails_saying(&solve_small(&dir, space, "1", more), expected);
    };
    refused(
        "joint",
        &["--start", "start.json"],
        "--start start.json: the start was solved in the actuation space, this solve is in the \
         joint space",
    );
    let steps = ["solve", "--steps", "12", "--start", "start.json"];
    fails_saying(
        &codesign_in(&dir, &steps),
        "--start start.json: the start was solved on 10 steps, this solve on 12",
    );
    refused(
        "actuation",
        &["--start", "start.json", "--elastic"],
        "the start is a point of the hard problem, this solve poses the elastic problem",
    );
    refused(
        "actuation",
        &["--start", "start.json", "--ends", "hold"],
        "the start was solved for another task (task hash",
    );
    refused(
        "actuation",
        &["--start", "start.json", "--out", "start.json"],
        "--out start.json",
    );

    // Files that are no start: cut short, another kind, without a point, edited.
    let text = std::fs::read_to_string(dir.join("start.json")).unwrap();
    std::fs::write(dir.join("cut.json"), &text[..text.len() / 2]).unwrap();
    let capacity = r#"{"schema": "codesign/capacity", "version": 2}"#;
    std::fs::write(dir.join("capacity.json"), capacity).unwrap();
    edited(&dir, "pointless.json", &start, |v| {
        v.as_object_mut().unwrap().remove("start_point");
    });
    edited(&dir, "short.json", &start, |v| {
        v["start_point"]["lambda"].as_array_mut().unwrap().pop();
    });
    edited(&dir, "spoilt.json", &start, |v| {
        v["start_point"]["x"][5] = "five".into();
    });
    // A key given twice (issue 57, item 21): serde would keep the last value silently.
    let twice = text.replacen('{', "{\n  \"cost\": 0.0,", 1);
    std::fs::write(dir.join("twice.json"), twice).unwrap();
    for (file, expected) in [
        ("cut.json", "--start cut.json: not JSON"),
        (
            "capacity.json",
            "--start capacity.json: not a codesign capacity result",
        ),
        ("pointless.json", "a solve result without `start_point`"),
        ("short.json", "--start short.json: the start's lambda has"),
        (
            "spoilt.json",
            "--start spoilt.json: not a codesign solve result",
        ),
        (
            "twice.json",
            "--start twice.json: the key `cost` is given twice in one object",
        ),
        ("missing.json", "--start missing.json"),
    ] {
        refused("actuation", &["--start", file], expected);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An infeasible design exits 0 by default and 3 under `--fail-if-infeasible`, the result
/// written either way; a feasible one exits 0 under it.
#[test]
fn an_infeasible_design_fails_only_when_asked_with_its_own_code() {
    let dir = scratch("infeasible");
    // 3 kg held at rest at the ends: the motors cannot hold it, so no start can help.
    let held = ["--ends", "hold", "--out", "held.json"];
    let asked = [&held[..], &["--fail-if-infeasible"]].concat();
    let output = solve_small(&dir, "actuation", "3", &asked);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("the design is infeasible (cannot hold the load at rest"),
        "{stderr}"
    );
    assert!(stderr.contains("--fail-if-infeasible"), "{stderr}");
    assert_eq!(read_json(&dir.join("held.json"))["feasible"], false);
    std::fs::remove_file(dir.join("held.json")).unwrap();
    let output = solve_small(&dir, "actuation", "3", &held);
    assert_eq!(output.status.code(), Some(0));
    assert_eq!(read_json(&dir.join("held.json"))["feasible"], false);
    let output = solve_small(&dir, "actuation", "1", &["--fail-if-infeasible"]);
    assert_eq!(output.status.code(), Some(0));
    std::fs::remove_dir_all(&dir).unwrap();
}
