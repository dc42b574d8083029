//! The ends of the motion as a choice (`motion.ends`, `--ends`; issue 33), end to end: each
//! value on the built-in arm and on an example, the task hash and the log header that record
//! it, and a resume refused across it.

use crate::support;

use serde_json::Value;
use support::{codesign, scratch};

/// Runs codesign with `args` and `--out` a file named `file` in this test's scratch folder:
/// its stdout and the result's JSON; asserts exit 0.
fn run(args: &[&str], file: &str) -> (String, Value) {
    support::succeed_with_out(args, &scratch("ends_cli").join(file))
}

/// The built-in arm's original design at 1 kg, actuation space: its motor 2 cannot hold 1 kg
/// at rest. Under the built-in task's `paper` (and `--ends paper`) it is feasible with dJ*/dr,
/// the hold reported and not judged; under `hold` and `rest` infeasible, naming the end and the
/// motor. Each records its ends and its own task hash (`hold` the one of a task without the
/// key).
#[test]
fn each_ends_value_on_the_built_in_arm() {
    let solve = |ends: Option<&str>| {
        let mut args = vec!["solve", "--space", "actuation", "--payload", "1"];
        if let Some(ends) = ends {
            args.extend(["--ends", ends]);
        }
        run(&args, &format!("arm-{}.json", ends.unwrap_or("task")))
    };
    let (text, task) = solve(None);
    let (_, paper) = solve(Some("paper"));
    assert_eq!(task["inputs"]["task_hash"], paper["inputs"]["task_hash"]);
    for result in [&task, &paper] {
        assert_eq!(result["feasible"], true, "{result}");
        assert!((result["cost"].as_f64().unwrap() - 171.2605).abs() < 1e-3);
        assert_eq!(result["reason"], Value::Null);
        assert_eq!(result["cost_gradient"].as_array().unwrap().len(), 4);
        assert_eq!(result["static_hold"]["judged"], false);
        assert_eq!(result["static_hold"]["start"]["holds"], false);
    }
    assert_eq!(paper["inputs"]["task"]["motion"]["ends"], "paper");
    assert!(text.contains("static hold (reported, not required: ends paper): cannot hold"));
    let mut hashes = vec![paper["inputs"]["task_hash"].clone()];
    for ends in ["hold", "rest"] {
        let (text, held) = solve(Some(ends));
        let result = &held;
        assert_eq!(result["feasible"], false, "{ends}");
        let reason = result["reason"].as_str().unwrap();
        assert!(
            reason.starts_with("cannot hold the load at rest at the start: motor 2 needs 2.13 N m"),
            "{reason}"
        );
        assert_eq!(result["static_hold"]["judged"], true);
        assert_eq!(held["inputs"]["task"]["motion"]["ends"], ends);
        assert!(text.contains("INFEASIBLE"), "{text}");
        hashes.push(held["inputs"]["task_hash"].clone());
    }
    hashes.dedup();
    assert_eq!(hashes.len(), 3, "each ends its own task: {hashes:?}");
}

/// The planar example holds `hold` in its file; at 10 steps, a payload its motors cannot hold
/// at rest is feasible under `--ends paper`, infeasible under its own `hold`; `rest` on a
/// payload it holds stands still over the first and the last interval.
#[test]
fn each_ends_value_on_an_example() {
    let task = support::root()
        .join("robots/examples/planar_2dof/task.json")
        .to_str()
        .unwrap()
        .to_owned();
    let base = [
        "solve",
        "--task",
        &task,
        "--space",
        "actuation",
        "--steps",
        "10",
    ];
    let solve = |payload: &str, ends: &str| {
        let mut args = base.to_vec();
        args.extend(["--payload", payload, "--ends", ends]);
        run(&args, &format!("planar-{payload}-{ends}.json")).1
    };
    // The payload just above what the motors hold at rest (from `capacity`'s hold bound).
    let capacity = {
        let mut args = vec!["capacity", "--task", &task, "--space", "actuation"];
        args.extend(["--ends", "hold"]);
        run(&args, "planar-capacity.json").1
    };
    let held_kg = capacity["hold_kg"].as_f64().unwrap();
    assert_eq!(capacity["inputs"]["ends"], "hold");
    let over = format!("{}", (held_kg * 1.05 * 1000.0).round() / 1000.0);
    let paper = solve(&over, "paper");
    let hold = solve(&over, "hold");
    assert_eq!(hold["feasible"], false, "{hold}");
    assert!(hold["reason"]
        .as_str()
        .unwrap()
        .starts_with("cannot hold the load at rest"));
    assert_eq!(paper["static_hold"]["judged"], false);
    if paper["feasible"] == true {
        assert!(paper["cost_gradient"].is_array());
    }
    let rest = solve("0", "rest");
    assert_eq!(rest["feasible"], true, "{rest}");
    let a = rest["trajectory"]["a"].as_array().unwrap();
    for k in [0, a.len() - 1] {
        for value in a[k].as_array().unwrap() {
            assert!(value.as_f64().unwrap().abs() <= 1e-9, "a_{k}: {value}");
        }
    }
}

/// A log made under one `ends` does not resume under another: the refusal names the
/// difference.
#[test]
fn a_log_of_other_ends_refuses_to_resume() {
    let dir = scratch("ends_cli_resume");
    let out = dir.join("run.json");
    let out_text = out.to_str().unwrap().to_owned();
    let optimize = |ends: &str, start: &str| {
        codesign(&[
            "optimize",
            "--space",
            "actuation",
            "--payload",
            "0",
            "--seed",
            "0",
            "--population",
            "5",
            "--generations",
            "1",
            "--workers",
            "1",
            "--ends",
            ends,
            start,
            "--out",
            &out_text,
        ])
    };
    let first = optimize("paper", "--overwrite");
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let log = std::fs::read_to_string(dir.join("run.log.jsonl")).unwrap();
    let header: Value = serde_json::from_str(log.lines().next().unwrap()).unwrap();
    assert_eq!(header["run"]["task"]["motion"]["ends"], "paper");
    let refused = optimize("hold", "--resume");
    assert_eq!(refused.status.code(), Some(1));
    let error = String::from_utf8_lossy(&refused.stderr);
    assert!(
        error.contains("task.motion.ends: log \"paper\", this command \"hold\""),
        "{error}"
    );
    let again = optimize("paper", "--resume");
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
}

/// A joint-space result says whether the motors can execute it: under the paper's joint limits
/// the original design's trajectory asks more of them than they have, and `solve` says by how
/// much on its summary.
#[test]
fn a_joint_space_result_says_whether_the_motors_can_execute_it() {
    let args = [
        "solve",
        "--space",
        "joint",
        "--payload",
        "0",
        "--steps",
        "10",
    ];
    let (text, result) = run(&args, "joint-execute.json");
    assert_eq!(result["feasible"], true, "{result}");
    let execute = &result["motors_execute"];
    assert_eq!(execute["executes"], false, "{execute}");
    let excess = execute["torque_excess_nm"].as_array().unwrap();
    assert_eq!(excess.len(), 4);
    assert!(
        excess.iter().any(|e| e.as_f64().unwrap() > 0.0),
        "{execute}"
    );
    assert!(
        text.contains("joint space, paper limits: the motors CANNOT execute it: motor "),
        "{text}"
    );
    let exact = ["--torque-mode", "exact"];
    let (_, bounded) = run(&[&args[..], &exact[..]].concat(), "joint-exact.json");
    assert_eq!(bounded["motors_execute"]["executes"], true, "{bounded}");
}
