//! Reading a URDF (through `urdf-rs`) into a serial [`Chain`], with every check the dynamics rely on.
//!
//! Supported: one tree of links. The joints from the root link to the TCP link (the task's
//! `tcp.link`) form the chain: its revolute, continuous and prismatic joints move (a prismatic
//! joint's coordinate in m); its fixed joints, and its revolute and prismatic joints with
//! `lower == upper` (locked at that angle or length), merge their child links into the body they
//! hang from (mass, centre of mass and inertia combined). Joints on branches that do
//! not lead to the TCP link (gripper fingers, sensors) are locked at q = 0 and merged likewise,
//! whatever their type (prismatic, mimic, ...). Without a TCP link every non-fixed joint must lie
//! on one serial chain. A link of mass 0 that carries an inertia (a flange, `tool0`) has its
//! inertia ignored. Each lock and ignored inertia is recorded in [`Chain::notes`].
//!
//! Refused with an error naming the joint or link: unreadable XML (a joint or link with two
//! elements of one kind, e.g. two `<limit>`s, is named), duplicate names, joints naming unknown
//! links, kinematic loops, several root links, branching chains (without a TCP link), floating
//! and planar joints on the chain, mimic joints on the chain, revolute and prismatic joints
//! without `<limit>` or with lower > upper, zero or non-finite axes, non-finite origins, negative masses,
//! inertias of massive links that are not positive definite or break the triangle inequality of
//! principal moments (ixx > iyy + izz), and moving bodies without mass. Links of the fixed base
//! never move, so their mass properties are only checked, not used.

mod checks;
mod tree;
mod walk;
mod xml;

use super::chain::Chain;
use super::error::ModelError;
use tree::Tree;
use urdf_rs::JointType;

/// Reads the URDF text `urdf` into the chain from its root link to `tcp_link` (the task's
/// `tcp.link`; `None`: every non-fixed joint, which must then form one serial chain); `file`
/// names it in errors.
pub fn read_chain(urdf: &str, file: &str, tcp_link: Option<&str>) -> Result<Chain, ModelError> {
    let robot = parse(urdf, file)?;
    let elements = xml::top_elements(urdf);
    let tree = Tree::new(&robot, file)?;
    walk::chain(&tree, tcp_link, &elements)
}

/// Parses the URDF text `urdf` (`file` names it in errors): refuses a xacro file, a text that
/// is no URDF, and more links or moving joints than a chain of this tool has.
fn parse(urdf: &str, file: &str) -> Result<urdf_rs::Robot, ModelError> {
    if urdf.contains("xacro:") || urdf.contains("${") {
        return Err(ModelError::new(
            file,
            "robot",
            "this is a xacro file: run xacro first (`xacro FILE.urdf.xacro > FILE.urdf`)",
        ));
    }
    if let Some(line) = xml::too_deep(urdf, MAX_XML_DEPTH) {
        return Err(ModelError::new(
            file,
            "robot",
            format!(
                "line {line}: elements nested deeper than {MAX_XML_DEPTH} levels (a URDF nests \
                 about 6: robot, link, visual, geometry, mesh)"
            ),
        ));
    }
    let robot = urdf_rs::read_from_string(urdf).map_err(|e| parse_error(urdf, file, &e))?;
    let moving = robot
        .joints
        .iter()
        .filter(|joint| !matches!(joint.joint_type, JointType::Fixed))
        .count();
    if robot.links.len() > MAX_LINKS || moving > MAX_MOVING_JOINTS {
        return Err(ModelError::new(
            file,
            "robot",
            format!(
                "{} links and {moving} moving joints: at most {MAX_LINKS} links and \
                 {MAX_MOVING_JOINTS} moving joints (an arm has tens; the trajectory problem \
                 grows with the square of the joints at every node)",
                robot.links.len()
            ),
        ));
    }
    Ok(robot)
}

/// The names of tool frames by convention (ROS-Industrial's `tool0` among them), in the order
/// they are preferred: a link of one of these names is the TCP's link when no task names one.
pub const TOOL_FRAMES: [&str; 6] = ["tcp", "tool0", "tool", "ee_link", "end_effector", "flange"];

/// The TCP's link when no task names one: a tool frame by its conventional name
/// ([`TOOL_FRAMES`]) on a chain of revolute, continuous and fixed joints from the root; else the
/// end of the longest such chain (a link fixed after it counts as further out), where the
/// longest chains part (a gripper's two fingers) the link where they part, and from there the
/// one link fixed to it, if it has exactly one. Branches through other joints (prismatic
/// fingers, mimic joints) are not followed: a chain with a prismatic joint names its TCP link
/// in the task. `file` names the URDF in errors.
pub fn tip_link(urdf: &str, file: &str) -> Result<String, ModelError> {
    let robot = parse(urdf, file)?;
    let parent: std::collections::HashMap<&str, &urdf_rs::Joint> = robot
        .joints
        .iter()
        .map(|joint| (joint.child.link.as_str(), joint))
        .collect();
    // The links from `link` up to the root, and the number of moving joints on the way; None
    // where the way passes another kind of joint.
    let way = |link: &str| -> Option<(Vec<String>, usize)> {
        let (mut links, mut moving, mut at) = (vec![link.to_owned()], 0, link);
        while let Some(joint) = parent.get(at) {
            match joint.joint_type {
                JointType::Revolute | JointType::Continuous if joint.mimic.is_none() => moving += 1,
                JointType::Fixed => {}
                _ => return None,
            }
            if links.len() > robot.links.len() {
                return None;
            }
            at = &joint.parent.link;
            links.push(at.to_owned());
        }
        Some((links, moving))
    };
    for frame in TOOL_FRAMES {
        if robot.links.iter().any(|link| link.name == frame) && way(frame).is_some() {
            return Ok(frame.to_owned());
        }
    }
    let ways: Vec<(Vec<String>, usize)> = robot
        .links
        .iter()
        .filter_map(|link| way(&link.name))
        .collect();
    let Some(most) = ways.iter().map(|(_, moving)| *moving).max() else {
        return Err(ModelError::new(file, "robot", "has no link"));
    };
    let tips: Vec<&Vec<String>> = (ways.iter())
        .filter(|(_, moving)| *moving == most)
        .map(|(links, _)| links)
        .collect();
    let deepest = tips.iter().map(|links| links.len()).max().unwrap_or(0);
    let far: Vec<&Vec<String>> = tips.into_iter().filter(|l| l.len() == deepest).collect();
    let Some(first) = far.first() else {
        return Err(ModelError::new(file, "robot", "has no link"));
    };
    if far.len() == 1 {
        return Ok(first[0].clone());
    }
    // The chains part: the last link they share, then its one fixed child, if one.
    let shared = (first.iter().rev())
        .take_while(|link| far.iter().all(|other| other.contains(link)))
        .last()
        .cloned()
        .unwrap_or_else(|| first[0].clone());
    let fixed: Vec<&urdf_rs::Joint> = (robot.joints.iter())
        .filter(|j| j.parent.link == shared && matches!(j.joint_type, JointType::Fixed))
        .collect();
    Ok(match fixed.as_slice() {
        [only] => only.child.link.clone(),
        _ => shared,
    })
}

/// The error for a URDF that `urdf-rs` cannot read: the joint or link at fault when the text
/// shows it, else what is wrong with the file as a whole, with urdf-rs's message.
fn parse_error(urdf: &str, file: &str, e: &urdf_rs::UrdfError) -> ModelError {
    if let Some((element, message)) = xml::fault(urdf, &e.to_string()) {
        return ModelError::new(file, element, format!("{message} (urdf-rs: {e})"));
    }
    let message = if urdf.trim().is_empty() {
        "the file is empty".to_owned()
    } else if !urdf.contains("<robot") {
        format!("not a URDF: it has no <robot> element ({e})")
    } else if !urdf.contains("</robot>") {
        format!(
            "not a readable URDF: {e} (the file ends before its closing </robot>: is it cut short?)"
        )
    } else {
        format!("not a readable URDF: {e}")
    };
    ModelError::new(file, "robot", message)
}

/// The most links a URDF may have: arms with their sensors and tools have tens.
pub const MAX_LINKS: usize = 1000;

/// The deepest nesting of XML elements read in a URDF, the root counting 1: far above any
/// robot's (vendors' Gazebo plugins reach about 10), far below what overflows the parser's stack.
pub const MAX_XML_DEPTH: usize = 64;

/// The most moving joints a URDF may have: the serial arms this tool designs have a few.
pub const MAX_MOVING_JOINTS: usize = 64;

#[cfg(test)]
mod tests {
    use super::tip_link;

    /// A two-joint arm whose last link holds `tail`.
    fn arm(tail: &str) -> String {
        let inertial = r#"<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>"#;
        let joint = |name: &str, kind: &str, parent: &str, child: &str| {
            format!(
                r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
            )
        };
        format!(
            r#"<robot name="r"><link name="base"/><link name="l1">{inertial}</link><link name="l2">{inertial}</link>{}{}{tail}</robot>"#,
            joint("j1", "revolute", "base", "l1"),
            joint("j2", "revolute", "l1", "l2"),
        )
    }

    /// Two fingers on revolute joints after `l2`, and `extra` beside them.
    fn gripper(extra: &str) -> String {
        let finger = |name: &str| {
            format!(
                r#"<link name="{name}"/><joint name="j_{name}" type="revolute"><parent link="l2"/><child link="{name}"/><axis xyz="0 0 1"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint>"#
            )
        };
        arm(&format!(
            "{}{}{extra}",
            finger("left_finger"),
            finger("right_finger")
        ))
    }

    fn fixed(name: &str) -> String {
        format!(
            r#"<link name="{name}"/><joint name="j_{name}" type="fixed"><parent link="l2"/><child link="{name}"/></joint>"#
        )
    }

    /// A tool frame by its conventional name is the TCP's link; where the longest chains part,
    /// at a gripper's fingers, the link where they part, or the one link fixed to it; a single
    /// longest chain ends at its last link (a link fixed after it counts as further out).
    #[test]
    fn the_tip_is_the_tool_frame_or_where_the_fingers_part() {
        let tip = |urdf: &str| tip_link(urdf, "r.urdf").unwrap();
        assert_eq!(tip(&gripper(&fixed("tcp"))), "tcp");
        assert_eq!(tip(&gripper(&fixed("grasp_point"))), "grasp_point");
        assert_eq!(tip(&gripper("")), "l2");
        assert_eq!(
            tip(&gripper(&format!("{}{}", fixed("a"), fixed("b")))),
            "l2"
        );
        assert_eq!(tip(&arm(&fixed("tool0"))), "tool0");
        assert_eq!(tip(&arm(&fixed("camera"))), "camera");
        assert_eq!(tip(&arm("")), "l2");
    }
}
