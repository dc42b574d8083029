//! The built-in task and robot: `codesign solve` works from a folder that holds nothing of the
//! repository, and `codesign task` (with `--urdf`) writes files that load back as the same task.

use crate::support;

use std::path::Path;
use support::{codesign_in, scratch};

/// Runs codesign in `dir` and returns its stdout; fails the test on an error.
fn succeed(dir: &Path, args: &[&str]) -> Vec<u8> {
    let output = codesign_in(dir, args);
    assert!(
        output.status.success(),
        "codesign {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
}

/// `codesign solve` of the original design at 0 kg in actuation space, in `dir`, with `extra`
/// flags; returns the result file.
fn solve(dir: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "solve",
        "--space",
        "actuation",
        "--payload",
        "0",
        "--ratios",
        "6,3,1,1",
        "--out",
        "result.json",
    ];
    args.extend_from_slice(extra);
    succeed(dir, &args);
    let text = std::fs::read_to_string(dir.join("result.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn solves_from_a_folder_without_the_repository_and_the_printed_task_loads_back() {
    let dir = scratch("solve");
    let built_in = solve(&dir, &[]);
    assert_eq!(built_in["status"], "Solve_Succeeded");
    assert_eq!(built_in["inputs"]["task_file"], "built-in");
    // The optimum of tests/data/ocp_reference.json for this case.
    let cost = built_in["cost"].as_f64().unwrap();
    assert!((cost - 43.674068420336255).abs() < 1e-6 * cost, "{cost}");

    // The printed task in tasks/, the printed URDF beside tasks/: the task's own robot path,
    // ../belt_arm.urdf, finds it.
    std::fs::create_dir(dir.join("tasks")).unwrap();
    let task = succeed(&dir, &["task"]);
    std::fs::write(dir.join("tasks/my.json"), &task).unwrap();
    let urdf = succeed(&dir, &["task", "--urdf"]);
    std::fs::write(dir.join("belt_arm.urdf"), &urdf).unwrap();
    let from_files = solve(&dir, &["--task", "tasks/my.json"]);
    assert_eq!(from_files["inputs"]["task_file"], "tasks/my.json");
    for key in ["status", "cost", "iterations", "trajectory"] {
        assert_eq!(from_files[key], built_in[key], "{key}");
    }
    // The printed task is the built-in one, its ends included: the same problem, by its hash.
    assert_eq!(
        from_files["inputs"]["task_hash"], built_in["inputs"]["task_hash"],
        "the printed task poses another problem than the built-in one"
    );
    assert_eq!(from_files["inputs"]["task"]["motion"]["ends"], "paper");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_task_file_whose_robot_is_missing_names_the_urdf() {
    let dir = scratch("missing-robot");
    let task = succeed(&dir, &["task"]);
    std::fs::write(dir.join("my.json"), &task).unwrap();
    let output = codesign_in(&dir, &["solve", "--task", "my.json"]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("../belt_arm.urdf: file: cannot read")
            && stderr.contains("the `robot` of task file my.json"),
        "{stderr}"
    );
}
