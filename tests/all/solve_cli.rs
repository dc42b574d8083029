//! `codesign solve` end to end: the result file, the plots, and clear errors on bad input.

use crate::support;

use std::path::Path;
use support::{codesign, codesign_command, scratch};

#[test]
fn writes_the_result_file_and_plots() {
    let dir = scratch("ok");
    let out = dir.join("result.json");
    let plots = dir.join("plots");
    let output = codesign(&[
        "solve",
        "--space",
        "joint",
        "--payload",
        "0",
        "--ratios",
        "6,3,1,1",
        "--out",
        out.to_str().unwrap(),
        "--plot",
        plots.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("Solve_Succeeded"), "{stdout}");
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    for key in [
        "status",
        "feasible",
        "cost",
        "iterations",
        "max_motor_torque",
        "violations",
        "trajectory",
        "tool",
        "inputs",
    ] {
        assert!(result.get(key).is_some(), "missing {key}");
    }
    assert_eq!(result["status"], "Solve_Succeeded");
    assert!(
        result.get("elastic").is_none(),
        "a hard solve has no elastic measures"
    );
    assert_eq!(result["inputs"]["space"], "joint");
    assert_eq!(
        result["tool"]["ipopt_version"],
        codesign_core::ipopt::IPOPT_VERSION
    );
    for key in ["total", "callbacks", "ipopt"] {
        assert!(result["solve_seconds"][key].as_f64().unwrap() >= 0.0);
    }
    let trajectory = &result["trajectory"];
    assert_eq!(trajectory["q"].as_array().unwrap().len(), 51);
    assert_eq!(trajectory["motor_torque"].as_array().unwrap().len(), 50);
    for name in [
        "joint_positions.svg",
        "joint_torques.svg",
        "motor_torques.svg",
        "tcp_path.svg",
    ] {
        let svg = std::fs::read_to_string(plots.join(name)).unwrap();
        assert!(svg.starts_with("<svg"), "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `solve --elastic` classifies the original design at 3 kg in actuation space, which the hard
/// problem cannot solve: it succeeds, prints the deficit and writes the elastic measures.
#[test]
fn elastic_solve_reports_the_torque_deficit() {
    let dir = scratch("elastic");
    let out = dir.join("result.json");
    let output = codesign(&[
        "solve",
        "--elastic",
        "--space",
        "actuation",
        "--payload",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("Solve_Succeeded"), "{stdout}");
    assert!(stdout.contains("INFEASIBLE"), "{stdout}");
    assert!(
        stdout.contains("relaxed problem (limits may give way, at a price added to J): over the motion the motors lack"),
        "{stdout}"
    );
    assert!(
        stdout.contains("INFEASIBLE (judged by the relaxed problem, whose limits may give way: the least extra torque"),
        "{stdout}"
    );
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(result["feasible"], false);
    assert!(result["elastic"]["torque_deficit"].as_f64().unwrap() > 0.0);
    assert!(result["elastic"]["speed_excess"].as_f64().unwrap() >= 0.0);
    assert!(result["elastic"]["objective"].as_f64().unwrap() > result["cost"].as_f64().unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--check-derivatives` runs IPOPT's checker on the problem as the command line builds it (here
/// 5 steps: the same formulas at every node, in a fraction of a second) and finds nothing, in
/// both spaces and with a torque-speed envelope.
#[test]
fn the_derivative_checker_finds_nothing() {
    let envelope = support::root().join("robots/tasks/pick_place_envelope.json");
    for (task, space) in [
        (support::task_path(), "actuation"),
        (support::task_path(), "joint"),
        (envelope, "actuation"),
    ] {
        let output = codesign(&[
            "solve",
            "--task",
            task.to_str().unwrap(),
            "--space",
            space,
            "--payload",
            "1",
            "--ratios",
            "9,7.7,3,3",
            "--steps",
            "5",
            "--check-derivatives",
        ]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(output.status.success(), "{space}: {stdout}");
        assert!(
            stdout.contains("first and second order, at the initial guess): 0 error(s)"),
            "{space}: {stdout}"
        );
    }
}

/// Asserts that `args` fail with exit `code` (2: a usage error, clap's or a flag's value out
/// of its range; 1: any other) and an error saying each of `expected`.
fn fails_with(args: &[&str], code: i32, expected: &[&str]) {
    let output = codesign(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
    for text in expected {
        assert!(stderr.contains(text), "{args:?}: {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn bad_input_gets_a_clear_error() {
    fails_with(
        &["solve", "--ratios", "10,3,1,1"],
        1,
        &["--ratios", "r1 = 10"],
    );
    fails_with(&["solve", "--ratios", "6,7,1,1"], 1, &["r2 < r1"]);
    fails_with(
        &["solve", "--ratios", "NaN,3,1,1"],
        2,
        &["--ratios", "a gear ratio must be a finite number"],
    );
    fails_with(&["solve", "--ratios", "6,3,1"], 1, &["--ratios"]);
    fails_with(&["solve", "--payload", "-1"], 2, &["--payload"]);
    fails_with(&["solve", "--duration", "0"], 2, &["--duration"]);
    fails_with(
        &["solve", "--task", "robots/tasks/absent.json"],
        1,
        &["absent.json"],
    );
    fails_with(
        &["solve", "--robot", "robots/absent.urdf"],
        1,
        &["absent.urdf"],
    );
    fails_with(
        &["solve", "--out", "/nonexistent-folder/result.json"],
        1,
        &["/nonexistent-folder/result.json"],
    );
    fails_with(&["solve", "--space", "sideways"], 2, &["sideways"]);
    assert!(!Path::new("/nonexistent-folder").exists());
}

/// A reader that closes its end of the pipe neither makes codesign panic nor stops the result
/// file being written; like most Unix tools, codesign then ends quietly (exit 0). Output that
/// cannot be written for another reason (a full disk, a closed stdout) exits 1: see
/// tests/hostile_cli.rs.
#[test]
fn a_closed_pipe_is_no_reason_to_panic() {
    let dir = scratch("pipe");
    let out = dir.join("result.json");
    let mut child = codesign_command(support::root(), &["solve", "--out", out.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("cannot write"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task whose G has scaled entries (`k*r<i>`) solves, with its gradient; a zero scale is
/// refused naming the entry.
#[test]
fn scaled_ratio_entries_solve() {
    let dir = scratch("scaled");
    let scaled = support::task_with(&dir, |task| {
        task["transmission"]["matrix"][1][0] = "0.5*r2".into();
        task["transmission"]["matrix"][2][1] = "-2*r3".into();
        task["transmission"]["matrix"][3][1] = "-2*r3".into();
    });
    let out = dir.join("scaled.json");
    let output = codesign(&[
        "solve",
        "--task",
        scaled.to_str().unwrap(),
        "--payload",
        "1",
        // A design whose motors hold 1 kg at rest with the halved r2 (7,4,2,2 cannot).
        "--ratios",
        "9,8,2,2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(result["feasible"], true);
    assert_eq!(result["cost_gradient"].as_array().unwrap().len(), 4);
    let zero = support::task_with(&dir, |task| {
        task["transmission"]["matrix"][1][0] = "0*r2".into();
    });
    let output = codesign(&["solve", "--task", zero.to_str().unwrap()]);
    support::fails_saying(&output, "transmission.matrix[1][0] = \"0*r2\"");
    std::fs::remove_dir_all(&dir).unwrap();
}
