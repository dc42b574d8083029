//! A serial kinematic chain of rigid bodies joined by revolute and prismatic joints: the model the
//! dynamics use.
//!
//! Body 0 hangs from the fixed base (the URDF's root link, whose frame is the world frame); body
//! i + 1 hangs from body i. A body is the child link of a moving joint together with every link
//! fixed to it; its frame is that child link's frame, which URDF places on the joint axis. Units: m,
//! kg, kg m^2; a revolute joint's coordinate in rad, a prismatic joint's in m.

use nalgebra::{Matrix3, Vector3};

/// A rigid transform from a child frame to a parent frame: `x_parent = rotation * x_child + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The child frame's axes in the parent frame (a rotation matrix).
    pub rotation: Matrix3<f64>,
    /// The child frame's origin in the parent frame, m.
    pub translation: Vector3<f64>,
}

impl Placement {
    /// The identity transform.
    pub fn identity() -> Placement {
        Placement {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// `self * child`: the transform from `child`'s child frame to `self`'s parent frame.
    pub fn then(&self, child: &Placement) -> Placement {
        Placement {
            rotation: self.rotation * child.rotation,
            translation: self.rotation * child.translation + self.translation,
        }
    }

    /// A point given in the child frame, expressed in the parent frame.
    pub fn apply(&self, point: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * point + self.translation
    }
}

impl Default for Placement {
    /// The identity transform.
    fn default() -> Placement {
        Placement::identity()
    }
}

/// Mass properties of a rigid body (or of nothing: mass 0), in some frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, m.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, along the frame's axes, kg m^2 (symmetric).
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// No mass at all.
    pub fn zero() -> MassProperties {
        MassProperties {
            mass: 0.0,
            com: Vector3::zeros(),
            inertia: Matrix3::zeros(),
        }
    }

    /// The same body seen from a parent frame, `placement` being the body frame's pose in it.
    pub fn transformed(&self, placement: &Placement) -> MassProperties {
        let r = placement.rotation;
        MassProperties {
            mass: self.mass,
            com: placement.apply(&self.com),
            inertia: r * self.inertia * r.transpose(),
        }
    }

    /// The rigid union of two bodies given in the same frame (parallel-axis theorem).
    pub fn combined(&self, other: &MassProperties) -> MassProperties {
        let mass = self.mass + other.mass;
        if mass == 0.0 {
            return MassProperties::zero();
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shifted = |part: &MassProperties| {
            let d = part.com - com;
            part.inertia + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * part.mass
        };
        MassProperties {
            mass,
            com,
            inertia: shifted(self) + shifted(other),
        }
    }
}

/// How a joint moves its body along its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// A turn about the axis through the joint frame's origin: q in rad, its effort in N m
    /// (URDF `revolute` and `continuous`).
    Revolute,
    /// A slide along the axis: q in m, its effort in N (URDF `prismatic`).
    Prismatic,
}

impl JointKind {
    /// The unit of the joint's coordinate: "rad" or "m".
    pub fn unit(self) -> &'static str {
        match self {
            JointKind::Revolute => "rad",
            JointKind::Prismatic => "m",
        }
    }

    /// The unit of the joint's effort: "N m" or "N".
    pub fn effort_unit(self) -> &'static str {
        match self {
            JointKind::Revolute => "N m",
            JointKind::Prismatic => "N",
        }
    }
}

/// One moving body of the chain with the joint that moves it.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The joint frame (= this body's frame at q = 0) in the parent body's frame (body i - 1, or
    /// the world for body 0).
    pub joint_placement: Placement,
    /// How the joint moves the body.
    pub kind: JointKind,
    /// The joint's unit axis in this body's frame; positive q turns the body about it (revolute)
    /// or slides it along it (prismatic).
    pub axis: Vector3<f64>,
    /// The body's mass properties (all its links) in its own frame, without any payload.
    pub mass: MassProperties,
}

/// Where a link sits: the body it is fixed to and its pose in that body's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkFrame {
    /// The link's name in the URDF.
    pub name: String,
    /// The moving body it belongs to; `None` for the fixed base.
    pub body: Option<usize>,
    /// The link frame's pose in the body frame (in the world frame for the base).
    pub placement: Placement,
}

/// A point fixed to a body of the chain (or to the base).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointOnBody {
    /// The body; `None` for the fixed base, where the point is in the world frame.
    pub body: Option<usize>,
    /// The point in the body's frame, m.
    pub point: Vector3<f64>,
}

/// A serial chain read from a URDF.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// The moving bodies, from the base outward.
    pub bodies: Vec<Body>,
    /// The name of each body's joint.
    pub joint_names: Vec<String>,
    /// Position limits (lower, upper) of each joint, rad or m; infinite for continuous joints.
    pub limits: Vec<(f64, f64)>,
    /// Every link of the URDF.
    pub links: Vec<LinkFrame>,
    /// What reading the URDF changed, one sentence each naming the joint or link: joints locked
    /// (treated as fixed), inertias ignored.
    pub notes: Vec<String>,
}

impl Chain {
    /// The point `point` (m, in the frame of link `link`) as a point on its body, or `None` if the
    /// chain has no such link.
    pub fn point_on_link(&self, link: &str, point: &Vector3<f64>) -> Option<PointOnBody> {
        let frame = self.links.iter().find(|frame| frame.name == link)?;
        Some(PointOnBody {
            body: frame.body,
            point: frame.placement.apply(point),
        })
    }
}
