//! Runs the machine could not finish are refused before they start: a problem whose solve needs
//! more memory than the machine has, and a budget whose result no reader takes.

use crate::support::{self, fails_saying, refused_as_usage, scratch, task_with};
use std::fmt::Write;
use std::path::Path;

/// A serial chain of `joints` revolute joints about alternating axes, 0.05 m and 0.1 kg a
/// link, ending in link `tip`.
fn chain_urdf(joints: usize) -> String {
    let link = |name: &str| {
        format!(
            "<link name=\"{name}\"><inertial><origin xyz=\"0 0 0.025\"/><mass value=\"0.1\"/>\
             <inertia ixx=\"1e-4\" ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" izz=\"1e-4\"/>\
             </inertial></link>\n"
        )
    };
    let mut urdf = String::from("<robot name=\"chain\">\n");
    urdf += &link("l0");
    for j in 1..=joints {
        let child = if j == joints {
            "tip".to_owned()
        } else {
            format!("l{j}")
        };
        urdf += &link(&child);
        let axis = if j % 2 == 0 { "0 1 0" } else { "1 0 0" };
        writeln!(
            urdf,
            "<joint name=\"j{j}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"{child}\"/>\
             <origin xyz=\"0 0 0.05\"/><axis xyz=\"{axis}\"/>\
             <limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"10\"/></joint>",
            j - 1
        )
        .unwrap();
    }
    urdf + "</robot>\n"
}

/// The task of the chain of `joints` joints at `steps` intervals, one ratio driving every joint.
fn chain_task(dir: &Path, joints: usize, steps: usize) -> std::path::PathBuf {
    let urdf = dir.join("chain.urdf");
    std::fs::write(&urdf, chain_urdf(joints)).unwrap();
    task_with(dir, |task| {
        let matrix: Vec<Vec<serde_json::Value>> = (0..joints)
            .map(|i| {
                (0..joints)
                    .map(|j| match (i == j, i) {
                        (true, 0) => "r1".into(),
                        (true, _) => 1.0.into(),
                        _ => 0.0.into(),
                    })
                    .collect()
            })
            .collect();
        task["robot"] = urdf.to_str().unwrap().into();
        task["tcp"]["link"] = "tip".into();
        task["payload"]["at"]["link"] = "tip".into();
        task["motion"]["start"] = vec![0.0; joints].into();
        task["motion"]["goal"] = vec![0.5; joints].into();
        task["motion"]["steps"] = steps.into();
        task["transmission"] = serde_json::json!({
            "matrix": matrix, "original": [2.0], "bounds": [[1.0, 9.0]], "order": []
        });
    })
}

#[test]
fn a_solve_the_machine_cannot_hold_is_refused_naming_the_estimate() {
    // 64 joints at 5000 steps: about 41 GB were reported; the estimate names its figure.
    let dir = scratch("limits-memory");
    let task = chain_task(&dir, 64, 5000);
    let available = codesign_core::problem::available_bytes().unwrap();
    let output = support::codesign(&["solve", "--task", task.to_str().unwrap(), "--payload", "0"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    if available > 200 << 30 {
        eprintln!("skipped: this machine has {available} bytes available");
        return;
    }
    fails_saying(&output, "motion.steps = 5000 with 64 joints needs about");
    assert!(stderr.contains("GiB for one solve"), "{stderr}");
    assert!(stderr.contains("available: use fewer steps"), "{stderr}");
    // `check` refuses the same task in the same words.
    let check = support::codesign(&["check", "--task", task.to_str().unwrap()]);
    fails_saying(&check, "motion.steps = 5000 with 64 joints needs about");
    // The same chain at 50 steps fits, so the estimate is not a refusal of the chain itself.
    let small = chain_task(&dir, 64, 50);
    let checked = support::codesign(&["check", "--task", small.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&checked.stderr);
    assert!(!stderr.contains("needs about"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_budget_whose_result_no_reader_takes_is_refused_naming_both_flags() {
    let dir = scratch("limits-budget");
    let output = support::codesign_in(
        &dir,
        &[
            "optimize",
            "--space",
            "actuation",
            "--payload",
            "1",
            "--seed",
            "0",
            "--population",
            "10000",
            "--generations",
            "30000",
        ],
    );
    refused_as_usage(&output, "--generations 30000: with population 10000");
    assert!(String::from_utf8_lossy(&output.stderr).contains("300010000 evaluations"));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
