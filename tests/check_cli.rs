//! `codesign check`: the inspection of a robot and its task, a verdict per check, and every
//! problem listed with exit 1.

mod support;

use support::{codesign, fails_saying, scratch, task_with};

#[test]
fn the_built_in_task_passes_every_check() {
    let output = codesign(&["check"]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for line in [
        "4 moving joints, payload 0 kg",
        "joint 2 'joint_arm_2'",
        "G:",
        "G^-1:",
        "ok   motion",
        "ok   design",
        "ok   hold at start",
        "ok   hold at goal",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let json = codesign(&["check", "--json"]);
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["joints"].as_array().unwrap().len(), 4);
    assert_eq!(value["g"][3][3], -1.0);
    assert_eq!(value["holds"][0]["pose"], "start");
}

#[test]
fn every_problem_is_listed() {
    // 3 kg on the best 3 kg design of the reproduction's rows: the motors cannot hold it still.
    let output = codesign(&["check", "--payload", "3", "--ratios", "9,5,3,3"]);
    fails_saying(&output, "2 problem(s) found: hold at start: motor 2 needs");
    fails_saying(&output, "hold at goal: motor 2 needs");
    let dir = scratch("check");
    let task = task_with(&dir, |task| task["motion"]["start"][1] = 9.0.into());
    let output = codesign(&[
        "check",
        "--task",
        task.to_str().unwrap(),
        "--ratios",
        "6,7,1,1",
    ]);
    fails_saying(
        &output,
        "motion: motion.start[1] = 9 rad is outside joint 'joint_arm_2'",
    );
    fails_saying(&output, "design: ");
    std::fs::remove_dir_all(&dir).unwrap();
}
