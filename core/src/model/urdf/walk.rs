//! Walking the tree from the root into a chain: which joints move, which are locked, and the
//! bodies they make.

use super::checks::{mass_properties, not_finite, pose};
use super::tree::Tree;
use super::xml::Element;
use crate::model::chain::{Body, Chain, JointKind, LinkFrame, MassProperties, Placement};
use crate::model::error::ModelError;
use nalgebra::{Rotation3, Unit, Vector3};
use std::collections::HashSet;
use urdf_rs::JointType;

/// What a joint does in the chain.
enum Role {
    /// It moves: a body of the chain.
    Moving,
    /// It is fixed (or locked) with its child at `at` in the joint frame; `note` says why when
    /// the URDF does not declare it fixed.
    Fixed { at: Placement, note: Option<String> },
}

/// The chain of `tree` from its root to `tcp_link` (see [`super::read_chain`]); `elements` are
/// the URDF's joints and links as its text has them.
pub(super) fn chain(
    tree: &Tree,
    tcp_link: Option<&str>,
    elements: &[Element],
) -> Result<Chain, ModelError> {
    let joints = &tree.robot.joints;
    let may_move = match tcp_link {
        Some(link) => tree.on_path_to(link).ok_or_else(|| {
            tree.error(
                "task tcp.link".into(),
                format!("'{link}' is not a link of this URDF"),
            )
        })?,
        None => vec![true; joints.len()],
    };
    let walk = Walk {
        tree,
        tcp_link,
        may_move,
        unlimited: elements
            .iter()
            .filter(|e| e.kind == "joint" && !e.children.iter().any(|c| c == "limit"))
            .map(|e| e.name.as_str())
            .collect(),
    };
    walk.chain()
}

/// The tree with what the walk needs to know about its joints.
struct Walk<'a> {
    tree: &'a Tree<'a>,
    tcp_link: Option<&'a str>,
    /// Per joint, whether it lies on the chain to the TCP link (all, without one).
    may_move: Vec<bool>,
    /// The joints that the text shows without a `<limit>` element.
    unlimited: HashSet<&'a str>,
}

impl Walk<'_> {
    /// Walks the tree from the root, merging fixed and locked joints, and builds the chain.
    fn chain(&self) -> Result<Chain, ModelError> {
        let tree = self.tree;
        let mut chain = Chain {
            bodies: Vec::new(),
            joint_names: Vec::new(),
            limits: Vec::new(),
            links: Vec::new(),
            notes: Vec::new(),
        };
        let mut stack = vec![(tree.root, None, Placement::identity())];
        while let Some((link, body, placement)) = stack.pop() {
            self.add_link(&mut chain, link, body, placement)?;
            for &j in &tree.edges.child_joints[link] {
                let joint = &tree.robot.joints[j];
                let origin = pose(&joint.origin).ok_or_else(|| {
                    tree.error(format!("joint '{}' <origin>", joint.name), not_finite())
                })?;
                let at_joint = placement.then(&origin);
                let child = tree.edges.child_link[j];
                match self.role(j)? {
                    Role::Fixed { at, note } => {
                        chain.notes.extend(note);
                        stack.push((child, body, at_joint.then(&at)));
                    }
                    Role::Moving => {
                        self.check_serial(&chain, joint, link, body)?;
                        self.add_body(&mut chain, joint, at_joint)?;
                        stack.push((child, Some(chain.bodies.len() - 1), Placement::identity()));
                    }
                }
            }
        }
        self.check_bodies(&chain)?;
        Ok(chain)
    }

    /// What joint `j` does: fixed, locked at `lower == upper`, locked at zero off the chain to
    /// the TCP link, or moving; an error for a type that cannot move in the chain.
    fn role(&self, j: usize) -> Result<Role, ModelError> {
        let joint = &self.tree.robot.joints[j];
        let name = &joint.name;
        let kind = format!("{:?}", joint.joint_type).to_lowercase();
        let (lower, upper) = (joint.limit.lower, joint.limit.upper);
        let locked_at_limit =
            matches!(joint.joint_type, JointType::Revolute | JointType::Prismatic)
                && !self.unlimited.contains(name.as_str())
                && lower.is_finite()
                && lower == upper;
        if joint.joint_type == JointType::Fixed {
            Ok(Role::Fixed {
                at: Placement::identity(),
                note: None,
            })
        } else if locked_at_limit {
            let axis = self.axis(joint)?;
            let kind = joint_kind(&joint.joint_type);
            let at = match kind {
                JointKind::Revolute => Placement {
                    rotation: Rotation3::from_axis_angle(&Unit::new_normalize(axis), lower)
                        .into_inner(),
                    translation: Vector3::zeros(),
                },
                JointKind::Prismatic => Placement {
                    rotation: nalgebra::Matrix3::identity(),
                    translation: axis * lower,
                },
            };
            Ok(Role::Fixed {
                at,
                note: Some(format!(
                    "joint '{name}' has lower = upper = {lower}: locked at {lower} {} (treated \
                     as fixed)",
                    kind.unit()
                )),
            })
        } else if !self.may_move[j] {
            let tcp = self.tcp_link.unwrap_or_default();
            Ok(Role::Fixed {
                at: Placement::identity(),
                note: Some(format!(
                    "joint '{name}' ({kind}) is not on the chain to the TCP link '{tcp}': \
                     locked at q = 0 (treated as fixed)"
                )),
            })
        } else if matches!(
            joint.joint_type,
            JointType::Revolute | JointType::Continuous | JointType::Prismatic
        ) {
            Ok(Role::Moving)
        } else {
            let on = self
                .tcp_link
                .map(|tcp| format!(" (it is on the chain to the TCP link '{tcp}')"))
                .unwrap_or_default();
            Err(self.tree.error(
                format!("joint '{name}'"),
                format!(
                    "is {kind}: only revolute, continuous and prismatic joints move in codesign's \
                     chains{on}"
                ),
            ))
        }
    }

    /// Joint's unit axis; an error when it is zero or not finite.
    fn axis(&self, joint: &urdf_rs::Joint) -> Result<Vector3<f64>, ModelError> {
        let axis = Vector3::from(joint.axis.xyz.0);
        let norm = axis.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(self.tree.error(
                format!("joint '{}' <axis>", joint.name),
                format!("xyz = {:?} is not a direction", joint.axis.xyz.0),
            ));
        }
        Ok(axis / norm)
    }

    /// An error when moving `joint` (on `link`, part of `body`) would hang a second moving joint
    /// on one body: a branching chain.
    fn check_serial(
        &self,
        chain: &Chain,
        joint: &urdf_rs::Joint,
        link: usize,
        body: Option<usize>,
    ) -> Result<(), ModelError> {
        if body == chain.bodies.len().checked_sub(1) {
            return Ok(());
        }
        let taken = &chain.joint_names[body.map_or(0, |b| b + 1)];
        Err(self.tree.error(
            format!("joint '{}'", joint.name),
            format!(
                "is a second moving joint on the body of link '{}', which already carries joint \
                 '{taken}': only serial chains are supported (name the TCP link to lock the \
                 other branches)",
                self.tree.robot.links[link].name
            ),
        ))
    }

    /// An error when the chain has no moving body or one without mass.
    fn check_bodies(&self, chain: &Chain) -> Result<(), ModelError> {
        if chain.bodies.is_empty() {
            let to = self
                .tcp_link
                .map(|tcp| format!(" on the chain to the TCP link '{tcp}'"))
                .unwrap_or_default();
            return Err(self.tree.error(
                "robot".into(),
                format!("has no revolute, continuous or prismatic joint{to}"),
            ));
        }
        for (i, body) in chain.bodies.iter().enumerate() {
            if body.mass.mass <= 0.0 {
                return Err(self.tree.error(
                    format!("joint '{}'", chain.joint_names[i]),
                    "moves links without mass: every moving body needs a positive mass".into(),
                ));
            }
        }
        Ok(())
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
            return Err(self.tree.error(
                format!("{element} <mimic>"),
                "mimic joints are not supported on the chain to the TCP link".into(),
            ));
        }
        let axis = self.axis(joint)?;
        let limits = if joint.joint_type == JointType::Continuous {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let (lower, upper) = (joint.limit.lower, joint.limit.upper);
            let limited = !self.unlimited.contains(joint.name.as_str());
            if !(limited && lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(self.tree.error(
                    format!("{element} <limit>"),
                    format!(
                        "lower = {lower} must be below upper = {upper}, both finite (a revolute \
                         or prismatic joint needs both; a joint without limits is of type \
                         continuous, one with lower = upper is locked)"
                    ),
                ));
            }
            (lower, upper)
        };
        chain.bodies.push(Body {
            joint_placement: at_joint,
            kind: joint_kind(&joint.joint_type),
            axis,
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
        let link_data = &self.tree.robot.links[link];
        let mass = mass_properties(link_data, self.tree.file, &mut chain.notes)?;
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
}

/// How a joint of a type that moves in the chain moves its body.
fn joint_kind(joint_type: &JointType) -> JointKind {
    match joint_type {
        JointType::Prismatic => JointKind::Prismatic,
        _ => JointKind::Revolute,
    }
}
