//! The load held at rest (issue 22, item 1), end to end on the UR5-class example: its payload
//! capacity is bounded by what its motors hold still at the ends of the motion, and `solve` at a
//! heavier payload is infeasible, naming the end and the motor.

use crate::support;

use serde_json::Value;
use support::scratch;

fn ur5_task() -> String {
    support::root()
        .join("robots/examples/ur5_6dof/task.json")
        .to_str()
        .unwrap()
        .to_owned()
}

/// Runs codesign with `args`, `--task` of the UR5 example and `--out dir/file`: its stdout and
/// the result file's JSON; asserts exit 0.
fn run(args: &[&str], file: &str) -> (String, Value) {
    let task = ur5_task();
    let mut all = args.to_vec();
    all.extend(["--task", &task]);
    support::succeed_with_out(&all, &scratch("hold_cli").join(file))
}

#[test]
fn the_ur5_capacity_is_bounded_by_what_its_motors_hold_at_rest() {
    for space in ["actuation", "joint"] {
        let (text, result) = run(
            &["capacity", "--space", space, "--max", "64"],
            &format!("capacity-{space}.json"),
        );
        let hold = result["hold_kg"].as_f64().unwrap();
        // `codesign check` shows the motors holding about 6.2 kg still (motor 3 at the goal).
        assert!((6.0..6.5).contains(&hold), "{space}: {hold}");
        assert_eq!(
            result["capacity_kg"].as_f64(),
            Some(hold),
            "{space}: {result}"
        );
        assert_eq!(result["limited_by"], "hold", "{space}");
        for probe in result["probes"].as_array().unwrap() {
            assert!(probe["payload_kg"].as_f64().unwrap() <= hold, "{probe}");
        }
        assert!(text.contains("bounded by static hold"), "{text}");
    }
}

#[test]
fn solve_at_a_payload_the_motors_cannot_hold_is_infeasible_naming_the_end_and_the_motor() {
    let (text, result) = run(
        &["solve", "--space", "actuation", "--payload", "7"],
        "solve-7kg.json",
    );
    let reason = result["reason"].as_str().unwrap();
    assert_eq!(result["feasible"], false, "{result}");
    assert!(
        reason.starts_with("cannot hold the load at rest at the goal: motor 3 needs "),
        "{reason}"
    );
    assert!(reason.ends_with("N m (limit 0.5)"), "{reason}");
    assert!(text.contains("INFEASIBLE"), "{text}");
    assert!(text.contains(&format!("static hold: {reason}")), "{text}");
    let hold = &result["static_hold"];
    assert_eq!(hold["rows"], "motors");
    assert_eq!(hold["start"]["holds"], true);
    assert_eq!(hold["goal"]["holds"], false);
    let margins = hold["goal"]["margins_nm"].as_array().unwrap();
    assert_eq!(margins.len(), 6);
    assert!(margins[2].as_f64().unwrap() < 0.0, "{margins:?}");
    assert!(result.get("cost_gradient").is_none());
    // At a payload it holds, the same solve is feasible and says the load is held.
    let (text, result) = run(
        &["solve", "--space", "actuation", "--payload", "5"],
        "solve-5kg.json",
    );
    assert_eq!(result["feasible"], true, "{result}");
    assert_eq!(result["static_hold"]["goal"]["holds"], true);
    assert!(
        text.contains("static hold: the load is held at rest"),
        "{text}"
    );
}

/// Issue 57, item 17: where only the hold fails, the elastic solve needs no slack, so its
/// verdict names the hold, not a shortfall of the relaxed problem it did not find.
#[test]
fn an_elastic_solve_infeasible_only_by_the_hold_says_so() {
    let (text, result) = run(
        &[
            "solve",
            "--elastic",
            "--space",
            "actuation",
            "--payload",
            "7",
            "--steps",
            "10",
        ],
        "elastic-7kg.json",
    );
    assert_eq!(result["feasible"], false, "{result}");
    assert_eq!(result["elastic"]["torque_deficit"], 0.0, "{result}");
    let verdict = text.lines().nth(1).unwrap();
    assert!(
        verdict.contains("INFEASIBLE: the motors cannot hold the load at rest at an end"),
        "{text}"
    );
    assert!(verdict.contains("the motion itself is feasible"), "{text}");
    assert!(!text.contains("above zero"), "{text}");
}
