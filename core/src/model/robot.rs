//! The robot of a task: the URDF's serial chain with the task's gravity, tool point and payload.

use super::chain::{Chain, JointKind, PointOnBody};
use super::error::ModelError;
use super::task::{Payload, PointOnLink, Task};
use super::urdf::{read_chain, tip_link};
use crate::input::{read_text, MAX_URDF_BYTES};
use nalgebra::Vector3;
use std::path::Path;

/// A serial-chain robot ready for the dynamics: kinematics and mass properties from a URDF,
/// gravity, tool centre point (TCP) and a point-mass payload from a task. The world frame is the
/// URDF's root link; units are SI (m, kg, rad).
#[derive(Clone, Debug)]
pub struct Robot {
    chain: Chain,
    gravity: Vector3<f64>,
    tcp: PointOnBody,
    tcp_link: String,
    payload_at: PointOnBody,
    payload_kg: f64,
    urdf_hash: String,
}

/// The built-in robot: the text of `robots/belt_arm.urdf`, compiled in.
pub const BUILT_IN_URDF: &str = include_str!("../../../robots/belt_arm.urdf");

/// How errors name the built-in robot.
const BUILT_IN_NAME: &str = "built-in robot (robots/belt_arm.urdf)";

impl Robot {
    /// Loads the URDF named by `task.robot` (already resolved to a path), or the built-in robot
    /// when it names none, with `task.gravity`, `task.tcp` and `task.payload`.
    pub fn load(task: &Task) -> Result<Robot, ModelError> {
        let Some(path) = &task.robot else {
            return Robot::from_urdf_str(BUILT_IN_URDF, BUILT_IN_NAME, task);
        };
        let file = path.display().to_string();
        let text = read_text(path, MAX_URDF_BYTES)
            .map_err(|e| ModelError::new(&file, "file", e.to_string()))?;
        Robot::from_urdf_str(&text, &file, task)
    }

    /// The link at the end of the longest chain of revolute and continuous joints of the URDF
    /// at `path` (see `urdf::tip_link`): the TCP's link when no task names one.
    pub fn tip_link(path: &Path) -> Result<String, ModelError> {
        let file = path.display().to_string();
        let text = read_text(path, MAX_URDF_BYTES)
            .map_err(|e| ModelError::new(&file, "file", e.to_string()))?;
        tip_link(&text, &file)
    }

    /// Loads the URDF at `path` alone: gravity 9.81 m/s^2 down world z, the TCP at the origin
    /// of the chain's tip link ([`Robot::tip_link`]), no payload.
    ///
    /// ```
    /// use codesign_core::model::Robot;
    ///
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/belt_arm.urdf");
    /// let robot = Robot::from_urdf(std::path::Path::new(path))?;
    /// assert_eq!(robot.dof(), 4);
    /// assert_eq!(robot.joint_names()[0], "joint_arm_1");
    /// let (lower, upper) = robot.position_limits()[1];
    /// assert!(lower < 0.0 && upper > 0.0);
    /// # Ok::<(), codesign_core::model::ModelError>(())
    /// ```
    pub fn from_urdf(path: &Path) -> Result<Robot, ModelError> {
        let file = path.display().to_string();
        let text = read_text(path, MAX_URDF_BYTES)
            .map_err(|e| ModelError::new(&file, "file", e.to_string()))?;
        let tip = PointOnLink {
            link: tip_link(&text, &file)?,
            point: [0.0; 3],
        };
        let payload = Payload {
            mass_kg: 0.0,
            at: tip.clone(),
        };
        Robot::from_parts(&text, &file, [0.0, 0.0, -9.81], &tip, &payload)
    }

    /// Reads the URDF text `urdf` with the gravity, TCP and payload of `task`; `source` names the
    /// URDF in errors (its file name).
    pub fn from_urdf_str(urdf: &str, source: &str, task: &Task) -> Result<Robot, ModelError> {
        Robot::from_parts(urdf, source, task.gravity, &task.tcp, &task.payload)
    }

    /// Reads the URDF text `urdf` with `gravity` (m/s^2, world frame), the TCP `tcp` and the
    /// payload `payload`, named as a task's fields in errors.
    fn from_parts(
        urdf: &str,
        source: &str,
        gravity: [f64; 3],
        tcp: &PointOnLink,
        payload: &Payload,
    ) -> Result<Robot, ModelError> {
        let chain = read_chain(urdf, source, Some(&tcp.link))?;
        if !gravity.iter().all(|g| g.is_finite()) {
            return Err(ModelError::new(
                source,
                "task gravity",
                format!("{gravity:?} is not a finite vector"),
            ));
        }
        let payload_kg = payload.mass_kg;
        if !(payload_kg.is_finite() && payload_kg >= 0.0) {
            return Err(ModelError::new(
                source,
                "task payload.mass_kg",
                format!("{payload_kg} must be a finite mass >= 0 kg"),
            ));
        }
        Ok(Robot {
            tcp: point_on_chain(&chain, tcp, source, "task tcp")?,
            tcp_link: tcp.link.clone(),
            payload_at: point_on_chain(&chain, &payload.at, source, "task payload.at")?,
            chain,
            gravity: Vector3::from(gravity),
            payload_kg,
            urdf_hash: crate::hash::fnv1a(urdf.as_bytes()),
        })
    }

    /// The same robot carrying a payload of `mass_kg` kg at the task's payload point.
    ///
    /// `mass_kg` must be finite and >= 0 (the task file and the command line check it); any other
    /// value gives a robot whose dynamics are all NaN, so that a mistake cannot pass unnoticed.
    pub fn with_payload(&self, mass_kg: f64) -> Robot {
        let valid = mass_kg.is_finite() && mass_kg >= 0.0;
        Robot {
            payload_kg: if valid { mass_kg } else { f64::NAN },
            ..self.clone()
        }
    }

    /// The payload's mass, kg.
    pub fn payload_kg(&self) -> f64 {
        self.payload_kg
    }

    /// Where the payload sits: a point on a body of the chain.
    pub fn payload_point(&self) -> &PointOnBody {
        &self.payload_at
    }

    /// FNV-1a of the URDF's text, as 16 hex digits: tells a run whether its robot file changed.
    pub fn urdf_hash(&self) -> &str {
        &self.urdf_hash
    }

    /// The number of joints (degrees of freedom).
    pub fn dof(&self) -> usize {
        self.chain.bodies.len()
    }

    /// The joints' names, from the base outward.
    pub fn joint_names(&self) -> &[String] {
        &self.chain.joint_names
    }

    /// Position limits (lower, upper) per joint, rad (m for a prismatic joint); infinite for
    /// continuous joints.
    pub fn position_limits(&self) -> &[(f64, f64)] {
        &self.chain.limits
    }

    /// How joint `j` moves (revolute or prismatic), which gives its units.
    ///
    /// # Panics
    /// If `j` is not a joint of the chain.
    pub fn joint_kind(&self, j: usize) -> JointKind {
        self.chain.bodies[j].kind
    }

    /// What reading the URDF changed, one sentence each naming the joint or link (joints locked,
    /// inertias ignored), for a command to show; empty when the URDF was taken as it is.
    pub fn notes(&self) -> &[String] {
        &self.chain.notes
    }

    /// The serial chain: bodies, joints and links.
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// Gravity in the world frame, m/s^2.
    pub fn gravity(&self) -> &Vector3<f64> {
        &self.gravity
    }

    /// The tool centre point: a point on a body of the chain.
    pub fn tcp(&self) -> &PointOnBody {
        &self.tcp
    }

    /// The URDF link the TCP is given on (the task's `tcp.link`, or the tip link the robot was
    /// read to without a task): one of the links merged into the TCP's body, by name.
    pub fn tcp_link(&self) -> &str {
        &self.tcp_link
    }
}

impl Robot {
    /// A ball that holds every position the TCP reaches: its centre, the first joint's origin
    /// in the world (m), and its radius, m: the distances between the joints' origins and from
    /// the last to the TCP, with each prismatic joint's longest travel, summed (the triangle
    /// inequality). None where a prismatic joint before the TCP slides without limit.
    pub fn reach(&self) -> Option<(Vector3<f64>, f64)> {
        let bodies = &self.chain.bodies;
        let Some(last) = self.tcp.body else {
            return Some((self.tcp.point, 0.0));
        };
        let mut radius = self.tcp.point.norm();
        for (j, body) in bodies.iter().enumerate().take(last + 1) {
            if j > 0 {
                radius += body.joint_placement.translation.norm();
            }
            if body.kind == JointKind::Prismatic {
                let (lo, hi) = self.chain.limits[j];
                radius += lo.abs().max(hi.abs());
            }
        }
        radius
            .is_finite()
            .then_some((bodies[0].joint_placement.translation, radius))
    }
}

/// The task's `point` on `link` as a point on the chain; `field` names the task field in errors.
fn point_on_chain(
    chain: &Chain,
    at: &PointOnLink,
    source: &str,
    field: &str,
) -> Result<PointOnBody, ModelError> {
    let point = Vector3::from(at.point);
    if !point.iter().all(|p| p.is_finite()) {
        return Err(ModelError::new(
            source,
            format!("{field}.point"),
            format!("{:?} is not a finite point", at.point),
        ));
    }
    chain.point_on_link(&at.link, &point).ok_or_else(|| {
        ModelError::new(
            source,
            format!("{field}.link"),
            format!("'{}' is not a link of this URDF", at.link),
        )
    })
}
