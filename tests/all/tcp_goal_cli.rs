//! A TCP goal (issue 52, item 3), end to end: a goal field of the wrong form or numbers is
//! refused naming it; `check` refuses a TCP goal out of the arm's reach before any solve and
//! passes a reachable one; the solve ends inside its ball at rest and reports the pose it chose;
//! a motion of a task's several gives its own TCP goal.

use crate::support;

use serde_json::json;
use support::{codesign, fails_saying, scratch, succeed_with_out, task_with};

#[test]
fn a_bad_goal_is_refused_naming_its_field() {
    let dir = scratch("tcp_goal_fields");
    for (goal, expected) in [
        (
            json!({"tcp": [0.0, -0.25, 0.15], "tol_m": 0.0}),
            "motion.goal.tol_m = 0 must be",
        ),
        (json!({"tcp": [0.0, -0.25, 0.15]}), "missing field `tol_m`"),
        (
            json!("up"),
            "a goal is a list of joint angles (rad) or {\"tcp\"",
        ),
    ] {
        let task = task_with(&dir, |task| task["motion"]["goal"] = goal.clone());
        let output = codesign(&["check", "--task", task.to_str().unwrap()]);
        fails_saying(&output, "motion.goal");
        fails_saying(&output, expected);
    }
}

#[test]
fn check_refuses_an_unreachable_tcp_goal_and_a_solve_ends_in_a_reachable_ones_ball() {
    let dir = scratch("tcp_goal_cli");
    let far = task_with(&dir, |task| {
        task["motion"]["goal"] = json!({"tcp": [2.0, 0.0, 0.5], "tol_m": 0.01});
    });
    let output = codesign(&["check", "--task", far.to_str().unwrap()]);
    fails_saying(&output, "motion.goal.tcp lies 2.");
    fails_saying(&output, "beyond the arm's reach of at most 0.948 m");
    let goal = [0.0, -0.25, 0.15];
    let reachable = task_with(&dir, |task| {
        task["motion"]["goal"] = json!({"tcp": goal, "tol_m": 0.005});
        task["motion"]["ends"] = json!("hold");
    });
    let reachable = reachable.to_str().unwrap();
    let output = codesign(&["check", "--task", reachable]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}");
    assert!(
        text.contains("ok   goal: the TCP goal within the arm's reach"),
        "{text}"
    );
    let args = ["solve", "--task", reachable, "--payload", "0.5"];
    let (_, result) = succeed_with_out(&args, &dir.join("goal.json"));
    assert_eq!(result["feasible"], true, "{result}");
    assert!(result["violations"]["goal_tcp"].as_f64().unwrap() <= 1e-6);
    let last = |key: &str| {
        let values = result["trajectory"][key].as_array().unwrap();
        values[values.len() - 1].clone()
    };
    assert_eq!(result["goal_pose"], last("q"));
    let tcp = [last("tcp_x"), last("tcp_y"), last("tcp_z")].map(|p| p.as_f64().unwrap());
    let distance = (tcp.iter().zip(goal))
        .map(|(p, g)| (p - g).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(distance <= 0.005 + 1e-6, "{distance}");
    let speeds = last("v");
    assert!(speeds
        .as_array()
        .unwrap()
        .iter()
        .all(|v| v.as_f64().unwrap().abs() < 1e-9));
    assert_eq!(result["static_hold"]["goal_guessed"], json!(null));
}

#[test]
fn a_motion_of_several_gives_its_own_tcp_goal() {
    let dir = scratch("tcp_goal_motions");
    let task = task_with(&dir, |task| {
        task["motions"] = json!([
            {"name": "joints"},
            {"name": "tcp", "goal": {"tcp": [0.0, -0.25, 0.15], "tol_m": 0.005}}
        ]);
    });
    let task = task.to_str().unwrap();
    let args = ["solve", "--task", task, "--motion", "tcp", "--steps", "20"];
    let (_, result) = succeed_with_out(&args, &dir.join("tcp.json"));
    assert_eq!(result["feasible"], true, "{result}");
    assert!(result["goal_pose"].is_array(), "{result}");
}
