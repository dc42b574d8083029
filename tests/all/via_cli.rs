//! Via points and an upright link (issue 52, item 3), end to end: `check` refuses a TCP via
//! point out of the arm's reach and a joint via point outside the joint limits, naming their
//! fields, before any solve; a reachable one passes the check, and the solve, judged by the one
//! rule, passes through it.

use crate::support;

use serde_json::json;
use support::{codesign, fails_saying, scratch, succeed_with_out, task_with};

#[test]
fn check_refuses_unreachable_via_points_and_a_solve_passes_a_reachable_one() {
    let dir = scratch("via_cli");
    let task = task_with(&dir, |task| {
        task["motion"]["via"] = json!([
            {"t_s": 0.4, "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01},
            {"t_s": 0.6, "tcp": [2.0, 0.0, 0.5], "tol_m": 0.01},
            {"t_s": 0.2, "q": [0.0, 3.5, 0.0, 0.0], "tol_rad": 0.1}
        ]);
        task["motion"]["upright"] =
            json!({"link": "no_such_link", "axis": [0, 0, 1], "tol_rad": 0.5});
    });
    let task = task.to_str().unwrap();
    let output = codesign(&["check", "--task", task]);
    fails_saying(&output, "motion.via[1].tcp lies 2.");
    for expected in [
        "beyond the arm's reach of at most 0.948 m",
        "motion.via[2].q[1] = 3.5 lies outside the joint limits",
        "motion.upright.link: 'no_such_link' is not a link of this URDF",
    ] {
        fails_saying(&output, expected);
    }
    fails_saying(
        &codesign(&["solve", "--task", task]),
        "motion.via[2].q[1] = 3.5",
    );
    let reachable = task_with(&dir, |task| {
        task["motion"]["via"] = json!([{"t_s": 0.4, "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01}]);
    });
    let reachable = reachable.to_str().unwrap();
    let output = codesign(&["check", "--task", reachable]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}");
    assert!(text.contains("ok   via: 1 via point(s)"), "{text}");
    let args = ["solve", "--task", reachable, "--payload", "1"];
    let (_, result) = succeed_with_out(&args, &dir.join("via.json"));
    assert_eq!(result["feasible"], true, "{result}");
    assert!(result["violations"]["via_tcp"].as_f64().unwrap() <= 1e-6);
    let at = |axis: &str| result["trajectory"][axis][25].as_f64().unwrap();
    let distance =
        (at("tcp_x").powi(2) + (at("tcp_y") + 0.7).powi(2) + (at("tcp_z") + 0.1).powi(2)).sqrt();
    assert!(distance <= 0.01 + 1e-6, "{distance}");
}

/// A via point within a window of time: `check` refuses windows that overlap, naming the field,
/// before any solve; `solve` reports the time it chose within the window, in its summary and its
/// result, where the node's time is.
#[test]
fn a_window_is_checked_and_the_time_a_solve_chose_is_reported() {
    let dir = scratch("via_window_cli");
    let overlapping = task_with(&dir, |task| {
        task["motion"]["via"] = json!([
            {"window_s": [0.3, 0.5], "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01},
            {"window_s": [0.45, 0.6], "tcp": [0.0, -0.6, 0.0], "tol_m": 0.01}
        ]);
    });
    fails_saying(
        &codesign(&["check", "--task", overlapping.to_str().unwrap()]),
        "motion.via[1].window_s = [0.45, 0.6] must begin after motion.via[0] ends at 0.5 s",
    );
    let windowed = task_with(&dir, |task| {
        task["motion"]["via"] =
            json!([{"window_s": [0.3, 0.5], "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01}]);
    });
    let args = [
        "solve",
        "--task",
        windowed.to_str().unwrap(),
        "--steps",
        "20",
    ];
    let (out, result) = succeed_with_out(&args, &dir.join("window.json"));
    assert_eq!(result["feasible"], true, "{result}");
    let t = result["via_times_s"][0].as_f64().unwrap();
    assert!((0.3..=0.5).contains(&t), "{t}");
    assert_eq!(result["trajectory"]["time"][10].as_f64(), Some(t));
    assert!(
        out.contains("via points passed at: via[0] ") && out.contains("(window [0.3, 0.5] s)"),
        "{out}"
    );
}
