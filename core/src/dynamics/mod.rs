//! Rigid-body dynamics of a serial chain and their analytic first and second derivatives.
//!
//! All recursions work in the world frame (the URDF's root link) with spatial vectors at the
//! world origin. With the joint motion vectors S_i(q) in that frame, a joint rotation q_j turns every
//! S_i, i >= j, about S_j: dS_i/dq_j = S_j x S_i. This gives the closed forms used here for the
//! derivatives of inverse dynamics (in the spirit of Carpentier and Mansard, "Analytical
//! derivatives of rigid body dynamics algorithms", RSS 2018) and, differentiating once more by
//! hand, for the Hessian of lambda . RNEA(q, v, a); see `derivatives.rs` and `hessian.rs`.
//!
//! As in Pinocchio, the model is apart from the data: a [`Dynamics`] holds what does not change
//! (the robot, its per-body constants, gravity, the TCP) and is shared; a [`Workspace`], made by
//! [`Dynamics::workspace`], holds the per-state caches and is passed `&mut` to every evaluation.
//!
//! A prismatic joint's motion vector is a pure translation S_j = (0, u_j); the same rule holds for
//! it (its S_j x S_i is the translation of S_i's axis), so every recursion serves both kinds.
//!
//! Units: q in rad, v in rad/s, a in rad/s^2, torques in N m, positions in m (for a prismatic
//! joint: q in m, v in m/s, a in m/s^2, its effort in N). Joint vectors are in
//! the chain's joint order (base outward). Every method takes slices of length `dof()` and writes
//! into caller-owned outputs; nothing is allocated per call once the outputs have their shapes.
//! Results at the same q (and v, a) are reused between calls on one workspace, so evaluating
//! everything one trajectory node needs costs one set of forward and backward passes.

mod derivatives;
mod hessian;
mod inverse;
mod inverse_kinematics;
mod kinematics;
mod point_jet;
mod spatial;

pub use point_jet::Fixed;

use crate::model::chain::{JointKind, MassProperties, Placement, PointOnBody};
use crate::model::Robot;
use nalgebra::{DMatrix, Matrix3, Vector3};
use spatial::{Force, Inertia, Motion};
use std::sync::atomic::{AtomicU64, Ordering};

/// The dynamics model of a [`Robot`]: everything that does not change with the state. Immutable;
/// evaluations write their intermediate results into a [`Workspace`] made by
/// [`Dynamics::workspace`].
///
/// # Panics
/// Every method panics if a joint slice (q, v, a, lambda, tau, ...) does not have `dof()`
/// entries, or if the workspace was made by another model: that is a bug of the caller (the
/// command line checks user input before calling).
#[derive(Clone, Debug)]
pub struct Dynamics {
    robot: Robot,
    /// Constant data per body.
    bodies: Vec<BodyModel>,
    /// The spatial acceleration of the base that stands for gravity: (0, -g).
    base_acceleration: Motion,
    /// The tool centre point.
    tcp: PointOnBody,
    /// Tells this model's workspaces from those of other models (clones share it).
    id: u64,
}

/// The per-state caches of evaluations of one [`Dynamics`]: world frames at some q, velocity-level
/// quantities at some (q, v, a), the Hessian's lambda-dependent terms, RNEA forces and the mass
/// matrix's factor. Preallocated, so that evaluations do not allocate.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// The id of the model that made it.
    model: u64,
    /// The q of `frames`, when valid.
    frames_at: Option<Vec<f64>>,
    frames: Vec<BodyFrame>,
    /// The (q, v, a) of `motion`, concatenated, when valid.
    motion_at: Option<Vec<f64>>,
    motion: Vec<BodyMotion>,
    adjoint: Vec<BodyAdjoint>,
    /// Per-body forces of a plain RNEA.
    forces: Vec<Force>,
    /// Cholesky factor of the mass matrix (forward dynamics).
    factor: DMatrix<f64>,
}

/// What does not change with the state.
#[derive(Clone, Debug)]
struct BodyModel {
    joint_placement: Placement,
    /// How the joint moves the body.
    kind: JointKind,
    /// The joint's unit axis, with [axis x] and [axis x]^2 (Rodrigues' formula), in the body frame.
    axis: Vector3<f64>,
    axis_cross: Matrix3<f64>,
    axis_cross_squared: Matrix3<f64>,
    /// The body's spatial inertia with the payload, in its own frame.
    inertia: Inertia,
}

/// The world pose, joint motion vector and inertia of a body at some q.
#[derive(Clone, Copy, Debug, Default)]
struct BodyFrame {
    pose: Placement,
    /// Joint motion vector S_i in the world frame.
    s: Motion,
    inertia: Inertia,
}

/// Velocity-level quantities of a body and the composites of the bodies it carries (index >= i).
#[derive(Clone, Copy, Debug, Default)]
struct BodyMotion {
    /// Body velocity v_i and acceleration a_i (gravity included: a_base = -g).
    v: Motion,
    a: Motion,
    /// dS_i/dt = v_(i-1) x S_i and d^2S_i/dt^2 = a_(i-1) x S_i + v_(i-1) x dS_i/dt.
    sd: Motion,
    sdd: Motion,
    /// Momentum I_i v_i.
    h: Force,
    /// Composites over bodies k >= i: force F_i, momentum H_i, inertia IC_i, its rate dIC_i.
    f: Force,
    momentum: Force,
    ic: Inertia,
    ic_rate: Inertia,
    /// IC_i and dIC_i applied to S_i, dS_i, d^2S_i.
    ic_s: Force,
    ic_sd: Force,
    ic_sdd: Force,
    ic_rate_s: Force,
    ic_rate_sd: Force,
}

/// The lambda-dependent quantities of the Hessian.
#[derive(Clone, Copy, Debug, Default)]
struct BodyAdjoint {
    /// Lambda_i = sum_(k <= i) lambda_k S_k, and sigma_i = Lambda_(i-1) x S_i.
    lambda: Motion,
    sigma: Motion,
    /// Composites over k >= i: P_i = sum I_k Lambda_k and psi_i.
    p: Force,
    psi: Force,
    /// IC_i, dIC_i and J_i = sum_(k >= i) rate(I_k, Lambda_k) applied to the body's own vectors.
    ic_sigma: Force,
    ic_rate_sigma: Force,
    j_s: Force,
    j_sd: Force,
    /// d psi_i / dq_i and d P_i / dq_i.
    dpsi: Force,
    dp: Force,
}

impl Dynamics {
    /// The dynamics of `robot` (with its payload).
    pub fn new(robot: Robot) -> Dynamics {
        let payload = *robot.payload_point();
        let bodies = robot
            .chain()
            .bodies
            .iter()
            .enumerate()
            .map(|(i, body)| {
                let mut inertia = Inertia::of_body(&body.mass);
                if payload.body == Some(i) {
                    inertia += Inertia::point_mass(robot.payload_kg(), &payload.point);
                }
                let axis_cross = body.axis.cross_matrix();
                BodyModel {
                    joint_placement: body.joint_placement,
                    kind: body.kind,
                    axis: body.axis,
                    axis_cross,
                    axis_cross_squared: axis_cross * axis_cross,
                    inertia,
                }
            })
            .collect::<Vec<_>>();
        Dynamics {
            base_acceleration: Motion::new(Vector3::zeros(), -robot.gravity()),
            tcp: *robot.tcp(),
            robot,
            bodies,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// This model with `parts` added to their bodies (mass properties in the body's frame):
    /// the robot carrying the task's parts at one design (docs/model.md, section 18). A model
    /// of its own, whose workspaces are not this one's.
    pub fn with_carried(&self, parts: &[(usize, MassProperties)]) -> Dynamics {
        let mut carrying = self.clone();
        for (body, part) in parts {
            carrying.bodies[*body].inertia += Inertia::of_body(part);
        }
        carrying.id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        carrying
    }

    /// A fresh workspace for evaluations of this model (the only allocation evaluations need).
    pub fn workspace(&self) -> Workspace {
        let n = self.dof();
        Workspace {
            model: self.id,
            frames_at: None,
            frames: vec![BodyFrame::default(); n],
            motion_at: None,
            motion: vec![BodyMotion::default(); n],
            adjoint: vec![BodyAdjoint::default(); n],
            forces: vec![Force::default(); n],
            factor: DMatrix::zeros(n, n),
        }
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The number of joints n.
    pub fn dof(&self) -> usize {
        self.bodies.len()
    }

    /// Panics unless `values` has one entry per joint: a caller's bug, not bad input.
    fn expect_joints(&self, name: &str, values: &[f64]) {
        assert_eq!(
            values.len(),
            self.dof(),
            "Dynamics: {name} has {} entries for a robot of {} joints",
            values.len(),
            self.dof()
        );
    }

    /// Panics unless `data` was made by this model: a caller's bug.
    fn expect_own(&self, data: &Workspace) {
        assert_eq!(
            data.model, self.id,
            "Dynamics: a workspace was used with a model that did not make it"
        );
    }
}

/// The id of the next model made.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// Gives `matrix` the shape rows x cols (allocating only if it has another shape).
fn shape(matrix: &mut DMatrix<f64>, rows: usize, cols: usize) {
    if matrix.shape() != (rows, cols) {
        *matrix = DMatrix::zeros(rows, cols);
    }
}

/// Whether `key` holds exactly the concatenation of `parts`.
fn same_state(key: &Option<Vec<f64>>, parts: &[&[f64]]) -> bool {
    key.as_ref().is_some_and(|key| {
        key.len() == parts.iter().map(|part| part.len()).sum::<usize>()
            && key.iter().eq(parts.iter().flat_map(|part| part.iter()))
    })
}

/// Stores the concatenation of `parts` in `key`, reusing its allocation.
fn remember(key: &mut Option<Vec<f64>>, parts: &[&[f64]]) {
    let key = key.get_or_insert_with(Vec::new);
    key.clear();
    for part in parts {
        key.extend_from_slice(part);
    }
}

#[cfg(test)]
mod tests;
