//! Reading a URDF (through `urdf-rs`) into a serial [`Chain`], with every check the dynamics rely on.
//!
//! Supported: one tree of links. The joints from the root link to the TCP link (the task's
//! `tcp.link`) form the chain: its revolute and continuous joints move; its fixed joints, and its
//! revolute joints with `lower == upper` (locked at that angle), merge their child links into the
//! body they hang from (mass, centre of mass and inertia combined). Joints on branches that do
//! not lead to the TCP link (gripper fingers, sensors) are locked at q = 0 and merged likewise,
//! whatever their type (prismatic, mimic, ...). Without a TCP link every non-fixed joint must lie
//! on one serial chain. A link of mass 0 that carries an inertia (a flange, `tool0`) has its
//! inertia ignored. Each lock and ignored inertia is recorded in [`Chain::notes`].
//!
//! Refused with an error naming the joint or link: unreadable XML (a joint or link with two
//! elements of one kind, e.g. two `<limit>`s, is named), duplicate names, joints naming unknown
//! links, kinematic loops, several root links, branching chains (without a TCP link), prismatic,
//! floating and planar joints on the chain, mimic joints on the chain, revolute joints without
//! `<limit>` or with lower > upper, zero or non-finite axes, non-finite origins, negative masses,
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

/// The link at the end of the longest chain of revolute and continuous joints from the root
/// (a link fixed after it counts as further out): the TCP's link when no task names one.
/// Branches through other joints (prismatic fingers, mimic joints) are not followed; ties go to
/// the link written first. `file` names the URDF in errors.
pub fn tip_link(urdf: &str, file: &str) -> Result<String, ModelError> {
    let robot = parse(urdf, file)?;
    let parent: std::collections::HashMap<&str, &urdf_rs::Joint> = robot
        .joints
        .iter()
        .map(|joint| (joint.child.link.as_str(), joint))
        .collect();
    let reach = |link: &str| -> Option<(usize, usize)> {
        let (mut moving, mut steps, mut at) = (0, 0, link);
        while let Some(joint) = parent.get(at) {
            match joint.joint_type {
                JointType::Revolute | JointType::Continuous if joint.mimic.is_none() => moving += 1,
                JointType::Fixed => {}
                _ => return None,
            }
            steps += 1;
            if steps > robot.links.len() {
                return None;
            }
            at = &joint.parent.link;
        }
        Some((moving, steps))
    };
    let mut best: Option<((usize, usize), &str)> = None;
    for link in &robot.links {
        if let Some(depth) = reach(&link.name) {
            if best.is_none_or(|(most, _)| depth > most) {
                best = Some((depth, &link.name));
            }
        }
    }
    best.map(|(_, name)| name.to_owned())
        .ok_or_else(|| ModelError::new(file, "robot", "has no link"))
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
