//! `codesign solve --plot` end to end on robots of other shapes than the built-in arm: the plots
//! name the joints as the URDF does and the motors by number, draw the TCP's path in the world
//! plane it moves in, and give a prismatic joint's units.

use crate::support;

use std::path::Path;
use support::{codesign, scratch};

/// A planar arm of two revolute joints about world y, `shoulder` and `elbow`: its TCP moves
/// in the world x-z plane only.
const PLANAR_XZ: &str = r#"<?xml version="1.0"?>
<robot name="planar_xz">
  <link name="base_link"/>
  <link name="upper"><inertial><origin xyz="0 0 0.2"/><mass value="0.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial></link>
  <link name="fore"><inertial><origin xyz="0 0 0.15"/><mass value="0.3"/><inertia ixx="0.005" ixy="0" ixz="0" iyy="0.005" iyz="0" izz="0.001"/></inertial></link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/>
  </joint>
</robot>
"#;

/// The task of the planar arm: two ratios, a box in x and z.
fn planar_task(dir: &Path) -> std::path::PathBuf {
    std::fs::write(dir.join("planar_xz.urdf"), PLANAR_XZ).unwrap();
    support::task_with(dir, |task| {
        task["robot"] = dir.join("planar_xz.urdf").to_str().unwrap().into();
        let tip = serde_json::json!({ "link": "fore", "point": [0.0, 0.0, 0.3] });
        task["tcp"] = tip.clone();
        task["payload"]["at"] = tip;
        task["motion"]["start"] = serde_json::json!([0.0, 0.0]);
        task["motion"]["goal"] = serde_json::json!([1.2, -0.8]);
        task["motion"]["steps"] = 12.into();
        task["cartesian_box"] = serde_json::json!({
            "x": { "range": [-0.1, 0.95], "weight": 1000.0 },
            "z": { "range": [0.2, 1.3], "weight": 1000.0 }
        });
        task["transmission"] = serde_json::json!({
            "matrix": [["r1", 0], [1, "r2"]],
            "original": [4.0, 2.0],
            "bounds": [[1.0, 9.0], [1.0, 9.0]],
            "order": []
        });
    })
}

/// Solves `task` (the built-in one when `None`) in the actuation space with `--plot`, and reads
/// the plots back by name.
fn plots(dir: &Path, task: Option<&Path>) -> impl Fn(&str) -> String {
    plots_in(dir, task, "actuation")
}

/// [`plots`] in `space`.
fn plots_in(dir: &Path, task: Option<&Path>, space: &str) -> impl Fn(&str) -> String {
    let folder = dir.join("plots");
    let mut args = vec!["solve", "--space", space, "--payload", "0.2"];
    if let Some(task) = task {
        args.extend(["--task", task.to_str().unwrap()]);
    }
    args.extend(["--plot", folder.to_str().unwrap()]);
    let output = codesign(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    move |name: &str| std::fs::read_to_string(folder.join(name)).unwrap()
}

#[test]
fn a_planar_arm_is_plotted_with_its_joint_names_in_its_plane() {
    let dir = scratch("planar");
    let task = planar_task(&dir);
    let plot = plots(&dir, Some(&task));
    for name in ["joint_positions.svg", "joint_torques.svg"] {
        let svg = plot(name);
        assert!(svg.contains("shoulder") && svg.contains("elbow"), "{name}");
        assert!(!svg.contains("joint 1"), "{name}");
    }
    let motors = plot("motor_torques.svg");
    assert!(motors.contains("motor 1") && motors.contains("motor 2"));
    assert!(!motors.contains("motor 3"));
    let path = plot("tcp_path.svg");
    assert!(path.contains("world x [m]") && path.contains("world z [m]"));
    assert!(!path.contains("world y [m]"));
    assert!(path.contains("r = (4.000, 2.000)"));
    // The arm itself: five poses of base, shoulder, elbow and TCP, in the x-z plane; and the
    // animation through every node of the motion.
    let poses = plot("poses.svg");
    assert!(poses.contains("world x-z plane"));
    let arms: Vec<&str> = poses
        .split("<polyline class=\"links\" points=\"")
        .skip(1)
        .filter(|part| part.contains("stroke-width=\"5\""))
        .collect();
    assert_eq!(arms.len(), 5, "{poses}");
    for arm in arms {
        let points = arm.split('"').next().unwrap();
        assert_eq!(points.split(' ').count(), 4, "{points}");
    }
    assert_eq!(poses.matches("t = ").count(), 5);
    let motion = plot("motion.svg");
    let values = motion
        .split("attributeName=\"points\"")
        .nth(1)
        .and_then(|rest| rest.split("values=\"").nth(1))
        .and_then(|rest| rest.split('"').next())
        .unwrap();
    let steps = support::read_json(&task)["motion"]["steps"]
        .as_u64()
        .unwrap() as usize;
    assert_eq!(values.split(';').count(), steps + 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every plot is well-formed XML when the motors' names hold control characters (an escape,
/// U+001B, which XML refuses even as a reference) and markup: each is written as its escape
/// (issue 57, item 12).
#[test]
fn plots_stay_well_formed_xml_with_control_characters_in_names() {
    let dir = scratch("markup");
    let examples = support::root().join("robots/examples/planar_2dof");
    let task = support::task_with(&dir, |task| {
        *task = support::read_json(&examples.join("task.json"));
        task["robot"] = examples.join("robot.urdf").to_str().unwrap().into();
        task["motion"]["steps"] = 10.into();
        task["motors"]["names"] = serde_json::json!(["sh\u{1b}[31mould<er>", "el&bow\u{7}"]);
    });
    let plot = plots(&dir, Some(&task));
    for name in [
        "joint_positions.svg",
        "joint_torques.svg",
        "motor_torques.svg",
        "tcp_path.svg",
        "poses.svg",
        "motion.svg",
    ] {
        let svg = plot(name);
        for event in xml::EventReader::from_str(&svg) {
            if let Err(error) = event {
                panic!("{name} is not well-formed XML: {error}");
            }
        }
    }
    let motors = plot("motor_torques.svg");
    assert!(motors.contains("sh\\u{1b}[31mould&lt;er&gt;"), "{motors}");
    assert!(motors.contains("el&amp;bow\\u{7}"), "{motors}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_built_in_arm_keeps_its_path_in_y_z() {
    let dir = scratch("built-in");
    let plot = plots(&dir, None);
    let svg = plot("joint_positions.svg");
    for i in 1..=4 {
        assert!(svg.contains(&format!("joint_arm_{i}")), "joint_arm_{i}");
    }
    let path = plot("tcp_path.svg");
    assert!(path.contains("world y [m]") && path.contains("world z [m]"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The joint space's plots where G changes with the pose (no torque box to draw), and a
/// prismatic joint's units named on the joint charts.
#[test]
fn linkages_and_prismatic_joints_are_plotted_in_the_joint_space() {
    let dir = scratch("linkages");
    let examples = support::root().join("robots/examples");
    let screw = examples.join("planar_2dof/ball_screw.json");
    let plot = plots_in(&dir, Some(&screw), "joint");
    assert!(plot("joint_torques.svg").contains("tau [N m]"));
    let scara = examples.join("scara_3dof/task.json");
    let plot = plots_in(&dir, Some(&scara), "joint");
    assert!(plot("joint_positions.svg").contains("q [rad; m: quill]"));
    assert!(plot("joint_torques.svg").contains("tau [N m; N: quill]"));
    std::fs::remove_dir_all(&dir).unwrap();
}
