//! Reading a URDF (through `urdf-rs`) into a serial [`Chain`], with every check the dynamics rely on.
//!
//! Supported: one tree of links whose moving joints (revolute, continuous) form a single serial
//! chain; fixed joints anywhere, their child links merged into the body they are fixed to (mass,
//! centre of mass and inertia combined). Rejected with an error naming the element: unreadable
//! XML, duplicate names, joints naming unknown links, kinematic loops, several root links,
//! branching chains, joint types other than revolute, continuous and fixed, mimic joints, zero or
//! non-finite axes, non-finite origins, revolute limits with lower >= upper, negative masses,
//! inertias that are not positive definite or break the triangle inequality of principal moments
//! (ixx > iyy + izz), and moving bodies without mass. Links of the fixed
//! base never move, so their mass properties are only checked, not used.

use super::chain::{Body, Chain, LinkFrame, MassProperties, Placement};
use super::error::ModelError;
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::collections::{HashMap, HashSet};
use urdf_rs::{JointType, Pose};

/// Reads the URDF text `urdf`; `file` names it in errors.
pub fn read_chain(urdf: &str, file: &str) -> Result<Chain, ModelError> {
    if urdf.contains("xacro:") || urdf.contains("${") {
        return Err(ModelError::new(
            file,
            "robot",
            "this is a xacro file: run xacro first (`xacro FILE.urdf.xacro > FILE.urdf`)",
        ));
    }
    let robot = urdf_rs::read_from_string(urdf).map_err(|e| {
        let message = if urdf.trim().is_empty() {
            "the file is empty".to_owned()
        } else if !urdf.contains("<robot") {
            format!("not a URDF: it has no <robot> element ({e})")
        } else if !urdf.contains("</robot>") {
            format!("not a readable URDF: {e} (the file ends before its closing </robot>: is it cut short?)")
        } else {
            format!("not a readable URDF: {e}")
        };
        ModelError::new(file, "robot", message)
    })?;
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
    Tree::new(&robot, file)?.chain()
}

/// The most links a URDF may have: arms with their sensors and tools have tens.
pub const MAX_LINKS: usize = 1000;

/// The most moving joints a URDF may have: the serial arms this tool designs have a few.
pub const MAX_MOVING_JOINTS: usize = 64;

/// The links and joints of a URDF as a tree, checked for being one.
struct Tree<'a> {
    robot: &'a urdf_rs::Robot,
    file: &'a str,
    /// Index of the root link.
    root: usize,
    /// How the joints connect the links.
    edges: Edges,
}

/// How the joints connect the links.
struct Edges {
    /// Per link, the indices of the joints whose parent it is.
    child_joints: Vec<Vec<usize>>,
    /// Per link, the index of the joint whose child it is.
    parent_joint: Vec<Option<usize>>,
    /// Per joint, the index of its child link.
    child_link: Vec<usize>,
}

/// The index of each link by name; an error for a name declared twice or a robot without links.
fn link_indices<'a>(
    robot: &'a urdf_rs::Robot,
    file: &str,
) -> Result<HashMap<&'a str, usize>, ModelError> {
    let mut link_index = HashMap::new();
    for (i, link) in robot.links.iter().enumerate() {
        if link_index.insert(link.name.as_str(), i).is_some() {
            return Err(ModelError::new(
                file,
                format!("link '{}'", link.name),
                "is declared twice",
            ));
        }
    }
    if robot.links.is_empty() {
        return Err(ModelError::new(file, "robot", "has no <link>"));
    }
    Ok(link_index)
}

/// The joints between the links; an error for a joint declared twice, one naming an unknown
/// link, or a link that is the child of two joints.
fn connect(
    robot: &urdf_rs::Robot,
    link_index: &HashMap<&str, usize>,
    file: &str,
) -> Result<Edges, ModelError> {
    let error = |element: String, message: String| ModelError::new(file, element, message);
    let mut joint_names = HashSet::new();
    let mut edges = Edges {
        child_joints: vec![Vec::new(); robot.links.len()],
        parent_joint: vec![None; robot.links.len()],
        child_link: Vec::with_capacity(robot.joints.len()),
    };
    for (j, joint) in robot.joints.iter().enumerate() {
        let element = format!("joint '{}'", joint.name);
        if !joint_names.insert(joint.name.as_str()) {
            return Err(error(element, "is declared twice".into()));
        }
        let find = |role: &str, name: &str| {
            link_index.get(name).copied().ok_or_else(|| {
                error(
                    format!("{element} <{role}>"),
                    format!("link '{name}' is not a <link> of the robot"),
                )
            })
        };
        let parent = find("parent", &joint.parent.link)?;
        let child = find("child", &joint.child.link)?;
        if let Some(other) = edges.parent_joint[child] {
            return Err(error(
                format!("link '{}'", joint.child.link),
                format!(
                    "is the child of both joint '{}' and joint '{}': kinematic loops are not supported",
                    robot.joints[other].name, joint.name
                ),
            ));
        }
        edges.parent_joint[child] = Some(j);
        edges.child_joints[parent].push(j);
        edges.child_link.push(child);
    }
    Ok(edges)
}

/// The one link that is the child of no joint; an error naming a loop when there is none, or
/// two roots when there are several.
fn find_root(robot: &urdf_rs::Robot, edges: &Edges, file: &str) -> Result<usize, ModelError> {
    let roots: Vec<usize> = (0..robot.links.len())
        .filter(|&i| edges.parent_joint[i].is_none())
        .collect();
    match roots.as_slice() {
        [root] => Ok(*root),
        [] => Err(ModelError::new(
            file,
            "robot",
            format!(
                "every link is the child of a joint: the joints {} form a kinematic loop",
                loop_through(robot, &edges.parent_joint, 0)
            ),
        )),
        [first, second, ..] => Err(ModelError::new(
            file,
            "robot",
            format!(
                "links '{}' and '{}' are both roots (child of no joint): the links do not form one tree",
                robot.links[*first].name, robot.links[*second].name
            ),
        )),
    }
}

/// Ok when the root reaches every link. With one root and at most one parent per link, a link
/// the root does not reach lies on a loop, which the error names.
fn check_reached(
    robot: &urdf_rs::Robot,
    edges: &Edges,
    root: usize,
    file: &str,
) -> Result<(), ModelError> {
    let mut reached = vec![false; robot.links.len()];
    let mut stack = vec![root];
    while let Some(link) = stack.pop() {
        reached[link] = true;
        stack.extend(
            edges.child_joints[link]
                .iter()
                .map(|&j| edges.child_link[j]),
        );
    }
    match reached.iter().position(|&r| !r) {
        Some(stray) => Err(ModelError::new(
            file,
            "robot",
            format!(
                "the joints {} form a kinematic loop, apart from the root link '{}'",
                loop_through(robot, &edges.parent_joint, stray),
                robot.links[root].name
            ),
        )),
        None => Ok(()),
    }
}

impl<'a> Tree<'a> {
    /// The links and joints of `robot` (read from `file`), checked for forming one tree.
    fn new(robot: &'a urdf_rs::Robot, file: &'a str) -> Result<Tree<'a>, ModelError> {
        let link_index = link_indices(robot, file)?;
        let edges = connect(robot, &link_index, file)?;
        let root = find_root(robot, &edges, file)?;
        check_reached(robot, &edges, root, file)?;
        Ok(Tree {
            robot,
            file,
            root,
            edges,
        })
    }

    fn error(&self, element: String, message: String) -> ModelError {
        ModelError::new(self.file, element, message)
    }

    /// Walks the tree from the root, merging fixed joints, and builds the chain.
    fn chain(&self) -> Result<Chain, ModelError> {
        let mut chain = Chain {
            bodies: Vec::new(),
            joint_names: Vec::new(),
            limits: Vec::new(),
            links: Vec::new(),
        };
        let mut stack = vec![(self.root, None, Placement::identity())];
        while let Some((link, body, placement)) = stack.pop() {
            self.add_link(&mut chain, link, body, placement)?;
            for &j in &self.edges.child_joints[link] {
                let joint = &self.robot.joints[j];
                let element = format!("joint '{}'", joint.name);
                let origin = pose(&joint.origin)
                    .ok_or_else(|| self.error(format!("{element} <origin>"), not_finite()))?;
                let at_joint = placement.then(&origin);
                let child = self.edges.child_link[j];
                match joint.joint_type {
                    JointType::Fixed => stack.push((child, body, at_joint)),
                    JointType::Revolute | JointType::Continuous => {
                        let last = chain.bodies.len().checked_sub(1);
                        if body != last {
                            let taken = &chain.joint_names[body.map_or(0, |b| b + 1)];
                            return Err(self.error(
                                element,
                                format!(
                                    "is a second moving joint on the body of link '{}', which \
                                     already carries joint '{taken}': only serial chains are supported",
                                    self.robot.links[link].name
                                ),
                            ));
                        }
                        self.add_body(&mut chain, joint, at_joint)?;
                        stack.push((child, Some(chain.bodies.len() - 1), Placement::identity()));
                    }
                    ref other => {
                        let kind = format!("{other:?}").to_lowercase();
                        return Err(self.error(
                            element,
                            format!(
                                "has type {kind}: only revolute, continuous and fixed joints are supported"
                            ),
                        ));
                    }
                }
            }
        }
        if chain.bodies.is_empty() {
            return Err(self.error("robot".into(), "has no revolute or continuous joint".into()));
        }
        for (i, body) in chain.bodies.iter().enumerate() {
            if body.mass.mass <= 0.0 {
                return Err(self.error(
                    format!("joint '{}'", chain.joint_names[i]),
                    "moves links without mass: every moving body needs a positive mass".into(),
                ));
            }
        }
        Ok(chain)
    }

    /// Adds a moving body for `joint`, whose frame sits at `at_joint` in the parent body's frame.
    fn add_body(
        &self,
        chain: &mut Chain,
        joint: &urdf_rs::Joint,
        at_joint: Placement,
    ) -> Result<(), ModelError> {
        let element = format!("joint '{}'", joint.name);
        if joint.mimic.is_some() {
            return Err(self.error(
                format!("{element} <mimic>"),
                "mimic joints are not supported".into(),
            ));
        }
        let axis = Vector3::from(joint.axis.xyz.0);
        let norm = axis.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(self.error(
                format!("{element} <axis>"),
                format!("xyz = {:?} is not a direction", joint.axis.xyz.0),
            ));
        }
        let limits = if joint.joint_type == JointType::Continuous {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let (lower, upper) = (joint.limit.lower, joint.limit.upper);
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(self.error(
                    format!("{element} <limit>"),
                    format!(
                        "lower = {lower} must be below upper = {upper}, both finite (a revolute \
                         joint needs both; a joint without limits is of type continuous)"
                    ),
                ));
            }
            (lower, upper)
        };
        chain.bodies.push(Body {
            joint_placement: at_joint,
            axis: axis / norm,
            mass: MassProperties::zero(),
        });
        chain.joint_names.push(joint.name.clone());
        chain.limits.push(limits);
        Ok(())
    }

    /// Records where `link` sits and adds its mass to its body (none to the fixed base).
    fn add_link(
        &self,
        chain: &mut Chain,
        link: usize,
        body: Option<usize>,
        placement: Placement,
    ) -> Result<(), ModelError> {
        let link_data = &self.robot.links[link];
        let mass = self.mass_properties(link_data)?;
        if let Some(b) = body {
            let body_mass = &mut chain.bodies[b].mass;
            *body_mass = body_mass.combined(&mass.transformed(&placement));
        }
        chain.links.push(LinkFrame {
            name: link_data.name.clone(),
            body,
            placement,
        });
        Ok(())
    }

    /// The link's mass properties in the link's frame, checked.
    fn mass_properties(&self, link: &urdf_rs::Link) -> Result<MassProperties, ModelError> {
        let element = |tag: &str| format!("link '{}' <{tag}>", link.name);
        let inertial = &link.inertial;
        let origin = pose(&inertial.origin)
            .ok_or_else(|| self.error(element("inertial><origin"), not_finite()))?;
        let mass = inertial.mass.value;
        if !(mass.is_finite() && mass >= 0.0) {
            return Err(self.error(
                element("mass"),
                format!("value = {mass} must be a finite mass >= 0 kg"),
            ));
        }
        let i = &inertial.inertia;
        let inertia = Matrix3::new(
            i.ixx, i.ixy, i.ixz, //
            i.ixy, i.iyy, i.iyz, //
            i.ixz, i.iyz, i.izz,
        );
        if !inertia.iter().all(|v| v.is_finite()) {
            return Err(self.error(element("inertia"), not_finite()));
        }
        if mass == 0.0 && inertia != Matrix3::zeros() {
            return Err(self.error(
                element("inertia"),
                "is not zero although the mass is 0: a massless link has no inertia".into(),
            ));
        }
        if mass > 0.0 && inertia.cholesky().is_none() {
            return Err(self.error(
                element("inertia"),
                format!(
                    "ixx = {}, ixy = {}, ixz = {}, iyy = {}, iyz = {}, izz = {} is not positive definite",
                    i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz
                ),
            ));
        }
        if mass > 0.0 && !principal_moments_physical(&inertia) {
            return Err(self.error(
                element("inertia"),
                format!(
                    "ixx = {}, iyy = {}, izz = {} (ixy = {}, ixz = {}, iyz = {}) is not the inertia of a body: a principal moment exceeds the sum of the other two",
                    i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz
                ),
            ));
        }
        Ok(MassProperties {
            mass,
            com: Vector3::zeros(),
            inertia,
        }
        .transformed(&origin))
    }
}

/// Whether the principal moments of a positive definite `inertia` satisfy the triangle
/// inequality that every mass distribution does (each at most the sum of the other two, up to
/// rounding).
fn principal_moments_physical(inertia: &Matrix3<f64>) -> bool {
    let moments = inertia.symmetric_eigen().eigenvalues;
    let sum = moments.sum();
    moments.iter().all(|&m| m <= sum - m + 1e-9 * sum)
}

/// The placement of a URDF `<origin>` (rotation R = Rz(yaw) Ry(pitch) Rx(roll)), if finite.
fn pose(origin: &Pose) -> Option<Placement> {
    let [roll, pitch, yaw] = origin.rpy.0;
    let translation = Vector3::from(origin.xyz.0);
    let rotation = Rotation3::from_euler_angles(roll, pitch, yaw).into_inner();
    (translation
        .iter()
        .chain(origin.rpy.0.iter())
        .all(|v| v.is_finite()))
    .then_some(Placement {
        rotation,
        translation,
    })
}

fn not_finite() -> String {
    "has a value that is not a finite number".into()
}

/// The joints on the loop reached by walking up from link `start`, quoted and comma-separated.
fn loop_through(robot: &urdf_rs::Robot, parent_joint: &[Option<usize>], start: usize) -> String {
    let link_of = |name: &str| robot.links.iter().position(|l| l.name == name);
    let mut seen = vec![false; robot.links.len()];
    let mut link = start;
    // Walk up until a link repeats: it lies on the loop.
    while !seen[link] {
        seen[link] = true;
        match parent_joint[link].and_then(|j| link_of(&robot.joints[j].parent.link)) {
            Some(parent) => link = parent,
            None => return String::new(),
        }
    }
    let first = link;
    let mut names = Vec::new();
    while let Some(j) = parent_joint[link] {
        names.push(format!("'{}'", robot.joints[j].name));
        match link_of(&robot.joints[j].parent.link) {
            Some(parent) if parent != first => link = parent,
            _ => break,
        }
    }
    names.reverse();
    names.join(", ")
}
