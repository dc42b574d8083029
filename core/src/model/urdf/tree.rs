//! The links and joints of a URDF as a tree: checked for being one, with the path to a link.

use crate::model::error::ModelError;
use std::collections::{HashMap, HashSet};

/// The links and joints of a URDF as a tree, checked for being one.
pub(super) struct Tree<'a> {
    /// The URDF as urdf-rs reads it.
    pub robot: &'a urdf_rs::Robot,
    /// The file, named in errors.
    pub file: &'a str,
    /// Index of the root link.
    pub root: usize,
    /// How the joints connect the links.
    pub edges: Edges,
    /// The index of each link by name.
    link_index: HashMap<&'a str, usize>,
}

/// How the joints connect the links.
pub(super) struct Edges {
    /// Per link, the indices of the joints whose parent it is.
    pub child_joints: Vec<Vec<usize>>,
    /// Per link, the index of the joint whose child it is.
    pub parent_joint: Vec<Option<usize>>,
    /// Per joint, the index of its child link.
    pub child_link: Vec<usize>,
}

impl<'a> Tree<'a> {
    /// The links and joints of `robot` (read from `file`), checked for forming one tree.
    pub fn new(robot: &'a urdf_rs::Robot, file: &'a str) -> Result<Tree<'a>, ModelError> {
        let link_index = link_indices(robot, file)?;
        let edges = connect(robot, &link_index, file)?;
        let root = find_root(robot, &edges, file)?;
        check_reached(robot, &edges, root, file)?;
        Ok(Tree {
            robot,
            file,
            root,
            edges,
            link_index,
        })
    }

    /// An error about `element` of the file.
    pub fn error(&self, element: String, message: String) -> ModelError {
        ModelError::new(self.file, element, message)
    }

    /// Per joint, whether it lies on the path from the root link to link `name`; `None` when the
    /// URDF has no such link.
    pub fn on_path_to(&self, name: &str) -> Option<Vec<bool>> {
        let mut link = *self.link_index.get(name)?;
        let mut on_path = vec![false; self.robot.joints.len()];
        while let Some(j) = self.edges.parent_joint[link] {
            on_path[j] = true;
            link = self.link_index[self.robot.joints[j].parent.link.as_str()];
        }
        Some(on_path)
    }
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
