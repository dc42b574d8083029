//! Checks of URDF loading: the belt arm of robots/README.md, fixed-joint merging, and the
//! errors for malformed descriptions, each naming the element at fault.

use super::chain::{JointKind, MassProperties};
use super::task::Task;
use super::urdf::read_chain;
use super::{ModelError, Robot};
use nalgebra::{Matrix3, Vector3};
use std::path::PathBuf;

fn root() -> PathBuf {
    crate::testing::repository()
}

fn task() -> Task {
    crate::testing::task()
}

fn belt_arm_text() -> String {
    std::fs::read_to_string(root().join("robots/belt_arm.urdf")).unwrap()
}

fn load(text: &str) -> Result<Robot, ModelError> {
    Robot::from_urdf_str(text, "test.urdf", &task())
}

/// `from` must occur in the belt arm's URDF; the edited text must fail naming every `expected`.
fn assert_fails(from: &str, to: &str, expected: &[&str]) {
    let text = belt_arm_text();
    assert!(text.contains(from), "{from}");
    let error = load(&text.replacen(from, to, 1)).unwrap_err();
    let message = error.to_string();
    assert!(message.starts_with("test.urdf: "), "{message}");
    for part in expected {
        assert!(message.contains(part), "'{part}' not in: {message}");
    }
}

#[test]
fn belt_arm_has_the_spec_joints_limits_and_masses() {
    let robot = Robot::load(&task()).unwrap();
    assert_eq!(robot.dof(), 4);
    assert_eq!(
        robot.joint_names(),
        ["joint_arm_1", "joint_arm_2", "joint_arm_3", "joint_arm_4"]
    );
    assert_eq!(
        robot.position_limits(),
        [(-3.5, 3.5), (-3.0, 3.0), (-3.0, 3.0), (-3.0, 3.0)]
    );
    let masses: Vec<f64> = robot.chain().bodies.iter().map(|b| b.mass.mass).collect();
    assert_eq!(masses, [1.0992, 0.75688, 0.14631, 0.36192]);
    assert_eq!(robot.payload_kg(), 0.0);
    assert_eq!(robot.with_payload(3.0).payload_kg(), 3.0);
    assert!(robot.with_payload(-1.0).payload_kg().is_nan());
    assert_eq!(robot.gravity(), &Vector3::new(0.0, 0.0, -9.81));
    assert_eq!(robot.tcp().body, Some(3));
    assert_eq!(robot.tcp().point, Vector3::new(0.0, 0.0, 0.15));
    // Joints 1-3 turn about the world x axis at q = 0 (up to the file's 1.5708 ~ pi/2).
    let axis_1 = robot.chain().bodies[0].joint_placement.rotation * robot.chain().bodies[0].axis;
    assert!((axis_1 - Vector3::x()).norm() < 1e-4, "{axis_1}");
}

#[test]
fn fixed_joints_merge_mass_properties_and_keep_link_frames() {
    // One body described as two links joined by a fixed joint, and as one link.
    let two_links = r#"<robot name="r">
      <link name="base"/>
      <link name="a"><inertial><origin xyz="0 0 0"/><mass value="2"/>
        <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
      <link name="b"><inertial><origin xyz="0 0 0"/><mass value="2"/>
        <inertia ixx="0.3" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.1"/></inertial></link>
      <link name="tip"/>
      <joint name="hinge" type="continuous"><parent link="base"/><child link="a"/>
        <axis xyz="0 2 0"/></joint>
      <joint name="weld" type="fixed"><parent link="a"/><child link="b"/>
        <origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/></joint>
      <joint name="tool" type="fixed"><parent link="b"/><child link="tip"/>
        <origin xyz="0 0.1 0"/></joint>
    </robot>"#;
    let mut task = task();
    task.tcp.link = "tip".into();
    task.tcp.point = [0.0, 0.0, 0.0];
    task.payload.at.link = "b".into();
    let robot = Robot::from_urdf_str(two_links, "two.urdf", &task).unwrap();
    assert_eq!(robot.dof(), 1);
    assert_eq!(
        robot.position_limits(),
        [(f64::NEG_INFINITY, f64::INFINITY)]
    );
    assert_eq!(robot.chain().bodies[0].axis, Vector3::y());
    // By hand: mass 4 at (0.25, 0, 0); b's inertia turned by 90 degrees about z is
    // diag(0.2, 0.3, 0.1); each half adds 2 * 0.25^2 about y and z.
    let expected = MassProperties {
        mass: 4.0,
        com: Vector3::new(0.25, 0.0, 0.0),
        inertia: Matrix3::from_diagonal(&Vector3::new(0.3, 0.65, 0.45)),
    };
    let got = robot.chain().bodies[0].mass;
    assert_eq!(got.mass, expected.mass);
    assert!((got.com - expected.com).norm() < 1e-15);
    assert!(
        (got.inertia - expected.inertia).norm() < 1e-15,
        "{}",
        got.inertia
    );
    // The tool link sits 0.1 m along b's y, which is -x of a: at (0.4, 0, 0) in the body frame.
    assert!((robot.tcp().point - Vector3::new(0.4, 0.0, 0.0)).norm() < 1e-15);
    assert!((robot.payload_point().point - Vector3::new(0.5, 0.0, 0.15)).norm() < 1e-15);
}

#[test]
fn missing_parent_link_is_named() {
    assert_fails(
        "<parent link=\"link_1\"/>",
        "<parent link=\"link_9\"/>",
        &["joint 'joint_arm_2' <parent>", "link_9"],
    );
}

#[test]
fn loops_and_branches_are_named() {
    // A second parent for link_1: a loop.
    assert_fails(
        "</robot>",
        "<joint name=\"closing\" type=\"revolute\"><parent link=\"link_4\"/><child link=\"link_1\"/>\
         <axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>",
        &["link 'link_1'", "'joint_arm_1'", "'closing'", "loop"],
    );
    // The root hung from the tip: no root at all.
    assert_fails(
        "</robot>",
        "<joint name=\"closing\" type=\"fixed\"><parent link=\"link_4\"/><child link=\"base_link_al\"/></joint></robot>",
        &["robot", "'closing'", "'joint_arm_4'", "loop"],
    );
    // A second moving joint on the forearm: a branch, refused without a TCP link.
    let branched = belt_arm_text().replacen(
        "</robot>",
        "<link name=\"link_5\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" \
         iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\
         <joint name=\"joint_arm_5\" type=\"revolute\"><parent link=\"link_2\"/><child link=\"link_5\"/>\
         <axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>",
        1,
    );
    let message = read_chain(&branched, "test.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("serial") && message.contains("link_2"),
        "{message}"
    );
    // With the TCP link on link_4 the branch is locked.
    let robot = load(&branched).unwrap();
    assert_eq!(robot.dof(), 4);
    assert_eq!(
        robot.notes(),
        ["joint 'joint_arm_5' (revolute) is not on the chain to the TCP link 'link_4': locked at \
          q = 0 (treated as fixed)"]
    );
    // Two roots.
    assert_fails(
        "</robot>",
        "<link name=\"stray\"/></robot>",
        &["'base_link_al'", "'stray'", "roots"],
    );
}

#[test]
fn bad_masses_and_inertias_are_named() {
    assert_fails(
        "<mass value=\"0.75688\"/>",
        "<mass value=\"-0.75688\"/>",
        &["link 'link_2' <mass>", "-0.75688"],
    );
    assert_fails(
        "ixx=\"3.8635E-05\"",
        "ixx=\"-3.8635E-05\"",
        &["link 'link_3' <inertia>", "positive definite"],
    );
    // Off-diagonal terms too large for the diagonal.
    assert_fails(
        "ixy=\"1.4333E-06\"",
        "ixy=\"1\"",
        &["link 'link_4' <inertia>", "positive definite"],
    );
    // Positive definite, but no body has ixx > iyy + izz.
    assert_fails(
        "ixx=\"3.8635E-05\"",
        "ixx=\"1\"",
        &[
            "link 'link_3' <inertia>",
            "exceeds the sum of the other two",
        ],
    );
    // Massless with an inertia: the inertia is ignored, and the body has no mass.
    assert_fails(
        "<mass value=\"0.14631\"/>",
        "<mass value=\"0\"/>",
        &["joint 'joint_arm_3'", "without mass"],
    );
}

/// A number urdf-rs cannot read (`invalid float literal`) is named with its element, the
/// link or joint it lies in, the attribute and the line.
#[test]
fn numbers_that_are_none_are_named_with_their_line() {
    let text = belt_arm_text();
    let line = |needle: &str| 1 + text[..text.find(needle).unwrap()].matches('\n').count();
    let mass = format!(
        "line {}: value=\"0.75688kg\" is not a number",
        line("0.75688")
    );
    assert_fails(
        "<mass value=\"0.75688\"/>",
        "<mass value=\"0.75688kg\"/>",
        &["link 'link_2' <mass>: ", &mass, "invalid float literal"],
    );
    let inertia = format!(
        "line {}: ixy=\"1.4333E-06 x\" is not a number",
        line("1.4333E-06")
    );
    assert_fails(
        "ixy=\"1.4333E-06\"",
        "ixy=\"1.4333E-06 x\"",
        &["link 'link_4' <inertia>: ", &inertia],
    );
}

#[test]
fn unsupported_joints_are_named() {
    let swap = |kind: &str| {
        assert_fails(
            "<joint name=\"joint_arm_3\" type=\"revolute\">",
            &format!("<joint name=\"joint_arm_3\" type=\"{kind}\">"),
            &["joint 'joint_arm_3'", kind],
        )
    };
    swap("floating");
    swap("planar");
    assert_fails(
        "<axis xyz=\"0 0 -1\"/>\n    <limit lower=\"-3\" upper=\"3\" effort=\"6\"",
        "<axis xyz=\"0 0 0\"/>\n    <limit lower=\"-3\" upper=\"3\" effort=\"6\"",
        &["joint 'joint_arm_2' <axis>"],
    );
    // The public file's joint_arm_1 limits.
    assert_fails(
        "lower=\"-3.5\" upper=\"3.5\"",
        "lower=\"3\" upper=\"2\"",
        &["joint 'joint_arm_1' <limit>", "lower = 3"],
    );
    assert_fails(
        "<joint name=\"joint_arm_2\" type=\"revolute\">",
        "<joint name=\"joint_arm_2\" type=\"revolute\"><mimic joint=\"joint_arm_1\"/>",
        &["joint 'joint_arm_2' <mimic>"],
    );
}

#[test]
fn unknown_task_links_and_unreadable_files_are_named() {
    let mut task = task();
    task.tcp.link = "link_9".into();
    let message = Robot::load(&task).unwrap_err().to_string();
    assert!(
        message.contains("belt_arm.urdf")
            && message.contains("task tcp.link")
            && message.contains("'link_9'"),
        "{message}"
    );
    let mut task = self::task();
    task.payload.at.link = "gripper".into();
    let message = Robot::load(&task).unwrap_err().to_string();
    assert!(message.contains("task payload.at.link"), "{message}");
    let mut task = Task::built_in().unwrap();
    task.tcp.link = "link_9".into();
    let message = Robot::load(&task).unwrap_err().to_string();
    assert!(
        message.starts_with("built-in robot (robots/belt_arm.urdf): task tcp.link"),
        "{message}"
    );
    let mut task = self::task();
    task.robot = Some(PathBuf::from("/nonexistent/arm.urdf"));
    let message = Robot::load(&task).unwrap_err().to_string();
    assert!(
        message.starts_with("/nonexistent/arm.urdf: file: cannot read"),
        "{message}"
    );
    let message = load("<robot name=\"r\"><link name=\"a\"")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("test.urdf: robot: not a readable URDF")
            && message.contains("ends before its closing </robot>"),
        "{message}"
    );
    let message = load("<robot name=\"r\"><link name=\"link_4\"/></robot>")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("no revolute, continuous or prismatic joint"),
        "{message}"
    );
}

fn idiom(name: &str) -> String {
    std::fs::read_to_string(root().join("tests/data/urdf").join(name)).unwrap()
}

/// Bodies equal to 1e-12 in every number.
fn assert_same_bodies(got: &Robot, want: &Robot) {
    assert_eq!(got.dof(), want.dof());
    for (g, w) in got.chain().bodies.iter().zip(&want.chain().bodies) {
        let close = |a: &Matrix3<f64>, b: &Matrix3<f64>| (a - b).norm() < 1e-12;
        assert!(close(
            &g.joint_placement.rotation,
            &w.joint_placement.rotation
        ));
        assert!((g.joint_placement.translation - w.joint_placement.translation).norm() < 1e-12);
        assert_eq!(g.axis, w.axis);
        assert!((g.mass.mass - w.mass.mass).abs() < 1e-12);
        assert!((g.mass.com - w.mass.com).norm() < 1e-12, "{}", g.mass.com);
        assert!(close(&g.mass.inertia, &w.mass.inertia));
    }
}

#[test]
fn the_belt_arm_has_no_notes() {
    assert!(Robot::load(&task()).unwrap().notes().is_empty());
}

#[test]
fn a_prismatic_joint_with_lower_equal_to_upper_is_locked_at_that_length() {
    let text = idiom("prismatic_on_chain.urdf");
    let locked = text.replacen(
        "<limit lower=\"0\" upper=\"0.3\"",
        "<limit lower=\"0.25\" upper=\"0.25\"",
        1,
    );
    let robot = load(&locked).unwrap();
    assert_eq!(robot.joint_names(), ["joint_1", "joint_2"]);
    assert_eq!(
        robot.notes(),
        ["joint 'slider' has lower = upper = 0.25: locked at 0.25 m (treated as fixed)"]
    );
    // The same as a fixed joint 0.25 m further along its axis (z).
    let fixed = text
        .replacen(
            "<joint name=\"slider\" type=\"prismatic\">",
            "<joint name=\"slider\" type=\"fixed\">",
            1,
        )
        .replacen(
            "<origin xyz=\"0 0 0.2\"/><axis xyz=\"0 0 1\"/>",
            "<origin xyz=\"0 0 0.45\"/>",
            1,
        );
    assert_same_bodies(&robot, &load(&fixed).unwrap());
}

#[test]
fn a_joint_with_lower_equal_to_upper_is_locked_at_that_angle() {
    let text = idiom("locked_joint.urdf");
    let robot = load(&text).unwrap();
    assert_eq!(robot.joint_names(), ["joint_1", "joint_2"]);
    assert_eq!(
        robot.notes(),
        ["joint 'wrist_locked' has lower = upper = 0.5: locked at 0.5 rad (treated as fixed)"]
    );
    // The same as a fixed joint turned by 0.5 rad about its x axis.
    let fixed = text.replacen(
        "<joint name=\"wrist_locked\" type=\"revolute\">",
        "<joint name=\"wrist_locked\" type=\"fixed\">",
        1,
    );
    let fixed = fixed.replacen(
        "<origin xyz=\"0 0 0.2\"/><axis xyz=\"1 0 0\"/>",
        "<origin xyz=\"0 0 0.2\" rpy=\"0.5 0 0\"/>",
        1,
    );
    assert_same_bodies(&robot, &load(&fixed).unwrap());
}

#[test]
fn joints_off_the_chain_to_the_tcp_are_locked_at_zero() {
    let text = idiom("gripper.urdf");
    let robot = load(&text).unwrap();
    assert_eq!(robot.joint_names(), ["joint_1", "joint_2"]);
    let notes = robot.notes().join("\n");
    for finger in ["'finger_left' (prismatic)", "'finger_right' (prismatic)"] {
        assert!(
            notes.contains(&format!(
                "joint {finger} is not on the chain to the TCP link 'link_4': locked at q = 0 \
                 (treated as fixed)"
            )),
            "{notes}"
        );
    }
    let fixed = text.replace("type=\"prismatic\"", "type=\"fixed\"");
    let fixed_robot = load(&fixed).unwrap();
    assert!(fixed_robot.notes().is_empty());
    assert_same_bodies(&robot, &fixed_robot);
    // The hand and fingers ride on the second body: 1 + 0.5 + 2 * 0.05 kg.
    assert!((robot.chain().bodies[1].mass.mass - 1.6).abs() < 1e-12);
    // Without a TCP link the fingers are moving joints, which cannot be.
    let message = read_chain(&text, "g.urdf", None).unwrap_err().to_string();
    assert!(message.starts_with("g.urdf: joint 'finger_"), "{message}");
}

#[test]
fn a_massless_link_with_an_inertia_is_taken_with_a_note() {
    let robot = load(&idiom("massless_flange.urdf")).unwrap();
    assert_eq!(robot.dof(), 2);
    assert_eq!(
        robot.notes(),
        ["link 'flange' has mass 0 and a nonzero inertia: its inertia is ignored (a massless link \
          has none)"]
    );
    assert_eq!(robot.chain().bodies[1].mass.mass, 1.0);
    assert!((robot.tcp().point - Vector3::new(0.0, 0.0, 0.37)).norm() < 1e-12);
    // A negative mass is still refused.
    let negative =
        idiom("massless_flange.urdf").replacen("<mass value=\"0\"/>", "<mass value=\"-1\"/>", 1);
    let message = load(&negative).unwrap_err().to_string();
    assert!(message.contains("link 'flange' <mass>"), "{message}");
}

#[test]
fn a_prismatic_joint_on_the_chain_moves_and_a_second_limit_is_named() {
    let robot = load(&idiom("prismatic_on_chain.urdf")).unwrap();
    assert_eq!(robot.dof(), 3);
    assert_eq!(robot.joint_names()[1], "slider");
    assert_eq!(robot.joint_kind(1), JointKind::Prismatic);
    assert_eq!(robot.position_limits()[1], (0.0, 0.3));
    let message = load(&idiom("duplicate_limit.urdf"))
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with(
            "test.urdf: joint 'joint_2' <limit>: has 2 <limit> elements: a joint has at most one"
        ),
        "{message}"
    );
    // A joint without <parent> is named too; a revolute one without <limit> is refused.
    let text = idiom("locked_joint.urdf");
    let orphan = text.replacen("<parent link=\"link_1\"/>", "", 1);
    let message = load(&orphan).unwrap_err().to_string();
    assert!(message.contains("joint 'wrist_locked'"), "{message}");
    let unlimited = text.replacen(
        "<limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"3\"/>",
        "",
        1,
    );
    let message = load(&unlimited).unwrap_err().to_string();
    assert!(message.contains("joint 'joint_1' <limit>"), "{message}");
}

#[test]
fn magnitudes_that_overflow_the_dynamics_are_refused_naming_the_link() {
    // Issue 38, item 13: a mass or an origin of 1e308 gave NaN gravity torques.
    assert_fails(
        "<mass value=\"5.2318\"/>",
        "<mass value=\"1e308\"/>",
        &[
            "<mass>",
            "must be a finite mass >= 0 kg, at most 1000000 kg",
        ],
    );
    assert_fails(
        "<origin xyz=\"-0.023234 0.080829 2.4543E-05\" rpy=\"0 0 0\"/>",
        "<origin xyz=\"1e308 0 0\" rpy=\"0 0 0\"/>",
        &[
            "<inertial><origin>",
            "a position at most 1000 m from its frame",
        ],
    );
    assert_fails(
        "<origin xyz=\"0 -0.5 -0.07\" rpy=\"0 -1.5708 0\"/>",
        "<origin xyz=\"0 -1e308 -0.07\" rpy=\"0 -1.5708 0\"/>",
        &["<origin>", "a position at most 1000 m from its frame"],
    );
}

#[test]
fn elements_nested_past_the_bound_are_refused_before_parsing() {
    // Issue 38, item 7: 16,000 nested elements overflowed the XML parser's stack (SIGABRT).
    let nested = |levels: usize| {
        let text = belt_arm_text();
        let deep = format!("{}{}</robot>", "<a>".repeat(levels), "</a>".repeat(levels));
        text.replacen("</robot>", &deep, 1)
    };
    let message = load(&nested(16_000)).unwrap_err().to_string();
    assert!(
        message.starts_with("test.urdf: robot: line ")
            && message.contains("elements nested deeper than 64 levels"),
        "{message}"
    );
    // The root and 63 levels below it are read (urdf-rs skips elements it does not know).
    assert!(load(&nested(63)).is_ok());
    assert!(load(&nested(64)).is_err());
    // Tags inside comments and declarations do not count.
    let commented = belt_arm_text().replacen(
        "</robot>",
        &format!("<!-- {} --></robot>", "<a>".repeat(100)),
        1,
    );
    assert!(load(&commented).is_ok());
    let cdata = belt_arm_text().replacen(
        "</robot>",
        &format!(
            "<gazebo><![CDATA[ {} ]]></gazebo></robot>",
            "<a>".repeat(100)
        ),
        1,
    );
    assert!(load(&cdata).is_ok());
}
