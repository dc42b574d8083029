//! A free horizon (issue 52, item 1), end to end: the built-in arm's minimum time at 0 and 1 kg
//! against a shorter fixed horizon under the one rule, the result's `horizon_s`, and the task
//! file's errors.

use crate::support;

use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use support::{scratch, succeed_with_out, task_with};

/// The repository's task as a minimum-time problem: T free in [0.3, 1.2] s, w_T = 1 per s, every
/// other weight 0 and no box; written in `dir`.
fn minimum_time_task(dir: &Path) -> PathBuf {
    task_with(dir, |task| {
        task["motion"]["horizon_s"] = json!({"free": [0.3, 1.2]});
        task["weights"] = json!({"position": 0, "velocity": 0, "control": 0, "time": 1});
        task["cartesian_box"] = json!({});
    })
}

/// Whether the one rule finds a feasible trajectory of the repository's task at `payload` kg
/// with the fixed duration `seconds`.
fn fixed_feasible(dir: &Path, payload: &str, seconds: f64) -> bool {
    let out = dir.join("fixed.json");
    let duration = format!("{seconds}");
    let args = ["solve", "--payload", payload, "--duration", &duration];
    succeed_with_out(&args, &out).1["feasible"] == true
}

/// At 0 and 1 kg (actuation space, the original design), T* is feasible and at 0.97 T* the
/// fixed-horizon rule finds nothing: J* = T* and `horizon_s` = T*, the last time of the
/// trajectory.
#[test]
fn the_minimum_time_is_feasible_and_a_shorter_fixed_horizon_is_not() {
    let dir = scratch("horizon_cli");
    let task = minimum_time_task(&dir);
    let task = task.to_str().unwrap();
    for payload in ["0", "1"] {
        let args = ["solve", "--task", task, "--payload", payload];
        let (text, result) = succeed_with_out(&args, &dir.join("free.json"));
        assert_eq!(result["feasible"], true, "{result}");
        let t_star = result["horizon_s"].as_f64().unwrap();
        assert!(text.contains("free horizon: T* = "), "{text}");
        assert_eq!(result["cost"].as_f64().unwrap(), t_star);
        assert_eq!(result["cost_terms"]["time"].as_f64().unwrap(), t_star);
        let times = result["trajectory"]["time"].as_array().unwrap();
        let last = times.last().and_then(Value::as_f64).unwrap();
        assert!(
            (last - t_star).abs() <= 1e-12 * t_star,
            "{last} vs {t_star}"
        );
        assert!(!fixed_feasible(&dir, payload, 0.97 * t_star));
    }
}

/// A free horizon's errors name the field; `--duration` fixes T again.
#[test]
fn a_free_horizon_is_checked_and_duration_fixes_it() {
    let dir = scratch("horizon_cli_errors");
    for (horizon, expected) in [
        (json!({"free": [1.2, 0.3]}), "T_min < T_max"),
        (json!({"free": [0.001, 1.0]}), "motion.horizon_s.free[0]"),
        (json!({"free": [0.3]}), "free duration"),
    ] {
        let task = task_with(&dir, |task| task["motion"]["horizon_s"] = horizon.clone());
        let output = support::codesign(&["solve", "--task", task.to_str().unwrap()]);
        support::fails_saying(&output, expected);
    }
    let task = minimum_time_task(&dir);
    let args = [
        "solve",
        "--task",
        task.to_str().unwrap(),
        "--duration",
        "0.9",
    ];
    let (_, result) = succeed_with_out(&args, &dir.join("fixed.json"));
    assert_eq!(result["horizon_s"], Value::Null);
    assert_eq!(result["inputs"]["task"]["motion"]["horizon_s"], 0.9);
    assert_eq!(result["cost"].as_f64().unwrap(), 0.9);
}

/// `capacity --duration T` moves each payload in T: a longer motion carries no less (the built-in
/// arm's original design, actuation space), and the document records T.
#[test]
fn the_capacity_within_a_duration_grows_with_it() {
    let dir = scratch("horizon_cli_capacity");
    let capacity = |duration: Option<&str>, file: &str| {
        let mut args = vec!["capacity", "--resolution", "0.05"];
        if let Some(duration) = duration {
            args.extend(["--duration", duration]);
        }
        let (_, document) = succeed_with_out(&args, &dir.join(file));
        document
    };
    let task = capacity(None, "task.json");
    let slow = capacity(Some("1.2"), "slow.json");
    assert_eq!(task["inputs"]["duration_s"], Value::Null);
    assert_eq!(slow["inputs"]["duration_s"], 1.2);
    let kg = |document: &Value| document["capacity_kg"].as_f64().unwrap();
    assert!(kg(&slow) >= kg(&task), "{} < {}", kg(&slow), kg(&task));
    let output = support::codesign(&["capacity", "--duration", "0"]);
    support::refused_as_usage(&output, "--duration 0");
}
