//! `codesign solve --export FILE.csv --rate HZ`: the trajectory at a controller's rate equals the
//! solution at its nodes, follows the integration rows between them, gives currents where the
//! task gives the motors' torque constants, and bad flags are refused before the solve with
//! nothing written.

use crate::support;

use serde_json::Value;
use std::path::Path;
use support::{codesign_in, fails_saying, read_json, refused_as_usage, scratch, succeed_in};

/// The CSV at `path`: its header's names, and its rows as numbers.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|line| line.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (names, rows)
}

/// Row `row` of `rows` at the columns named `prefix*` (in the header's order).
fn columns(names: &[String], row: &[f64], prefix: &str) -> Vec<f64> {
    let picked = names.iter().zip(row).filter(|(n, _)| n.starts_with(prefix));
    picked.map(|(_, &x)| x).collect()
}

/// The numbers of `value`'s array `key` at index `k` (a row of numbers).
fn node(trajectory: &Value, key: &str, k: usize) -> Vec<f64> {
    let row = trajectory[key][k].as_array().unwrap();
    row.iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The largest |a_i - b_i|, failing where the lengths differ.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Solves `task_args` with `--out` and `--export` at 1 kHz in `dir`; the result's trajectory
/// and the export.
fn solve_and_export(dir: &Path, task_args: &[&str]) -> (Value, Vec<String>, Vec<Vec<f64>>) {
    let mut args = vec![
        "solve", "--out", "r.json", "--export", "t.csv", "--rate", "1000",
    ];
    args.extend(task_args);
    let said = succeed_in(dir, &args);
    assert!(said.contains("trajectory exported to t.csv"), "{said}");
    let (names, rows) = read_csv(&dir.join("t.csv"));
    (
        read_json(&dir.join("r.json"))["trajectory"].clone(),
        names,
        rows,
    )
}

/// Checks that each node of `trajectory` is a row of the export within 1e-12, the interval
/// quantities those of the interval that starts there (the last one's at the last node).
fn nodes_reproduced(trajectory: &Value, names: &[String], rows: &[Vec<f64>]) {
    let times = trajectory["time"].as_array().unwrap();
    let steps = times.len() - 1;
    for (k, time) in times.iter().enumerate() {
        let time = time.as_f64().unwrap();
        let at: Vec<&Vec<f64>> = rows.iter().filter(|r| (r[0] - time).abs() < 1e-9).collect();
        assert_eq!(at.len(), 1, "node {k} at {time} s");
        let (row, interval) = (at[0], k.min(steps - 1));
        let pairs = [
            ("q_", "q", k),
            ("v_", "v", k),
            ("a_", "a", interval),
            ("tau_", "joint_torque", interval),
            ("v_u_", "motor_speed", k),
            ("tau_u_", "motor_torque", interval),
        ];
        for (prefix, key, index) in pairs {
            // The joints' `v_` and `tau_` columns come before the motors' `v_u_`, `tau_u_`.
            let mut found = columns(names, row, prefix);
            if !prefix.contains("_u_") {
                found.truncate(node(trajectory, key, index).len());
            }
            let error = largest_difference(&found, &node(trajectory, key, index));
            assert!(error <= 1e-12, "{key} at node {k}: {error:e}");
        }
        if trajectory.get("motor_position").is_some() {
            let error = largest_difference(
                &columns(names, row, "q_u_"),
                &node(trajectory, "motor_position", k),
            );
            assert!(error <= 1e-12, "motor_position at node {k}: {error:e}");
        }
    }
}

#[test]
fn the_export_at_1_khz_reproduces_the_built_in_arms_nodes() {
    let dir = scratch("export");
    let (trajectory, names, rows) = solve_and_export(&dir, &[]);
    // 0.8 s at 1 kHz: 801 rows, a node every 16.
    assert_eq!(rows.len(), 801);
    assert_eq!(names[..2], ["time_s", "q_joint_arm_1_rad"]);
    assert!(names.contains(&"tau_u_motor_4_Nm".to_owned()));
    assert!(
        !names.iter().any(|n| n.starts_with("i_u_")),
        "no k_t, no current"
    );
    nodes_reproduced(&trajectory, &names, &rows);
    // Between the nodes, the integration rows' laws: q(t) = q_k + s v_k+1, v(t) = v_k + s a_k.
    let row = &rows[16 * 7 + 5];
    let s = row[0] - trajectory["time"][7].as_f64().unwrap();
    let q: Vec<f64> = node(&trajectory, "q", 7)
        .iter()
        .zip(node(&trajectory, "v", 8))
        .map(|(q, v)| q + s * v)
        .collect();
    let v: Vec<f64> = node(&trajectory, "v", 7)
        .iter()
        .zip(node(&trajectory, "a", 7))
        .map(|(v, a)| v + s * a)
        .collect();
    assert!(largest_difference(&columns(&names, row, "q_joint"), &q) < 1e-12);
    assert!(largest_difference(&columns(&names, row, "v_joint"), &v) < 1e-12);
    // A constant G: the motors' angles and speeds are G q(t) and G v(t) (motor 1 = r1 q_1 at
    // the original design r1 = 6).
    let motor_1 = columns(&names, row, "q_u_motor_1")[0];
    assert!((motor_1 - 6.0 * q[0]).abs() < 1e-12);
}

#[test]
fn a_linkage_and_torque_constants_give_motor_angles_and_currents() {
    let dir = scratch("export-linkage");
    let example = support::root().join("robots/examples/planar_2dof/ball_screw.json");
    let mut task: Value =
        serde_json::from_str(&std::fs::read_to_string(&example).unwrap()).unwrap();
    let robot = example.parent().unwrap().join("robot.urdf");
    task["robot"] = robot.to_str().unwrap().into();
    task["motors"]["torque_constant_nm_per_a"] = serde_json::json!([0.1, 0.05]);
    task["motors"]["resistance_ohm"] = 1.0.into();
    std::fs::write(dir.join("task.json"), task.to_string()).unwrap();
    let (trajectory, names, rows) = solve_and_export(&dir, &["--task", "task.json"]);
    nodes_reproduced(&trajectory, &names, &rows);
    for row in &rows {
        let (torques, currents) = (columns(&names, row, "tau_u_"), columns(&names, row, "i_u_"));
        assert_eq!(currents, [torques[0] / 0.1, torques[1] / 0.05]);
    }
}

#[test]
fn bad_rates_and_files_are_refused_before_the_solve_and_nothing_is_written() {
    let dir = scratch("export-refused");
    let run = |args: &[&str]| {
        let mut all = vec!["solve", "--export", "t.csv"];
        all.extend(args);
        codesign_in(&dir, &all)
    };
    for rate in ["0", "-5", "nan", "inf"] {
        let output = run(&["--rate", rate]);
        refused_as_usage(&output, "--rate");
        refused_as_usage(&output, "finite number of samples per second above 0");
    }
    refused_as_usage(
        &run(&["--rate", "1e9"]),
        "more than the 200000 an export holds",
    );
    refused_as_usage(&run(&[]), "--rate");
    let same = run(&["--rate", "100", "--out", "t.csv"]);
    refused_as_usage(&same, "--export t.csv: the same file as --out");
    assert!(!dir.join("t.csv").exists());
    let elsewhere = codesign_in(&dir, &["solve", "--export", "none/t.csv", "--rate", "100"]);
    fails_saying(&elsewhere, "--export none/t.csv");
    // A file in the way is replaced whole only by a finished export.
    std::fs::write(dir.join("t.csv"), "earlier\n").unwrap();
    refused_as_usage(&run(&["--rate", "0"]), "--rate 0");
    assert_eq!(
        std::fs::read_to_string(dir.join("t.csv")).unwrap(),
        "earlier\n"
    );
    succeed_in(&dir, &["solve", "--export", "t.csv", "--rate", "50"]);
    let (_, rows) = read_csv(&dir.join("t.csv"));
    assert_eq!(rows.len(), 41);
}
