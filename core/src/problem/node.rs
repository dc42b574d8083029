//! What the derivatives need at one trajectory node k < N, evaluated once per primal point.

use crate::dynamics::{Dynamics, Workspace};
use crate::transmission::linkage::RowDerivatives;
use crate::transmission::{Actuation, NodeLoss};
use nalgebra::{DMatrix, DVector, Vector3};

/// How far the primal point's node data are evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Level {
    /// Nothing valid (a new x).
    Nothing,
    /// Torques and TCP positions: enough for the objective and the constraints.
    Values,
    /// Also their first derivatives: for the gradient, the Jacobian and the Hessian.
    Derivatives,
}

/// The dynamics and TCP terms of one node at the current x.
#[derive(Clone, Debug)]
pub(super) struct NodeEval {
    /// RNEA(q_k, v_k, a_k), N m.
    pub(super) tau: Vec<f64>,
    /// d tau / dq (N m/rad), d tau / dv (N m s/rad), M = d tau / da (kg m^2), row = torque.
    pub(super) dtau_dq: DMatrix<f64>,
    pub(super) dtau_dv: DMatrix<f64>,
    pub(super) mass: DMatrix<f64>,
    /// TCP position in the world, m.
    pub(super) tcp: Vector3<f64>,
    /// d tcp / dq, 3 x n, m/rad.
    pub(super) tcp_jacobian: DMatrix<f64>,
    /// The transmissions' losses at tau and v_k with their derivatives, None where lossless.
    pub(super) loss: Option<NodeLoss>,
    /// G(q_k) and its linkage rows' derivatives, None for a constant G(r).
    pub(super) pose: Option<NodePose>,
    /// The world z of the upright link's axis at q_k and its gradient in q_k (per rad), where
    /// the task holds a link upright (`motion.upright`).
    pub(super) upright: Option<(f64, Vec<f64>)>,
}

/// The transmission at a node whose G depends on the pose (docs/model.md, section 17).
#[derive(Clone, Debug)]
pub(super) struct NodePose {
    /// The actuation at q_k: G(q_k), its inverse, the controls' maps.
    pub(super) actuation: Actuation,
    /// Each linkage row's motor (row of G) and derivatives in q at q_k.
    pub(super) rows: Vec<(usize, RowDerivatives)>,
    /// Each screw's motor and length per motor radian l / 2 pi at the design, m/rad.
    pub(super) screws: Vec<(usize, f64)>,
    /// The node's joint speeds v_k (rad/s), accelerations a_k (rad/s^2) and controls u_k (N m)
    /// at the point evaluated.
    pub(super) speeds: Vec<f64>,
    pub(super) accelerations: Vec<f64>,
    pub(super) controls: Vec<f64>,
}

impl NodePose {
    /// sum_i w_i d^2 gamma_i/dq^2 over the linkage rows, n x n: the derivative in q of G^T w.
    pub(super) fn curvature(&self, w: &[f64]) -> DMatrix<f64> {
        let n = w.len();
        let mut sum = DMatrix::zeros(n, n);
        for (motor, row) in &self.rows {
            sum += &row.hessian * w[*motor];
        }
        sum
    }

    /// sum_i w_i d^3 gamma_i/dq^3 [x] over the linkage rows, n x n.
    pub(super) fn third_along(&self, w: &[f64], x: &[f64]) -> DMatrix<f64> {
        let n = w.len();
        let mut sum = DMatrix::zeros(n, n);
        for (motor, row) in &self.rows {
            if w[*motor] != 0.0 {
                sum += row.third_along(x) * w[*motor];
            }
        }
        sum
    }

    /// d(G x)/dq at fixed x, n x n (row = motor): row i is (d^2 gamma_i/dq^2 x)^T for a
    /// linkage row, zero for a constant one.
    pub(super) fn derivative_along(&self, x: &[f64]) -> DMatrix<f64> {
        let n = x.len();
        let x = DVector::from_column_slice(x);
        let mut derivative = DMatrix::zeros(n, n);
        for (motor, row) in &self.rows {
            derivative.set_row(*motor, &(&row.hessian * &x).transpose());
        }
        derivative
    }
}

impl NodeEval {
    /// All zeros, for `n` joints.
    pub(super) fn zeros(n: usize) -> NodeEval {
        NodeEval {
            tau: vec![0.0; n],
            dtau_dq: DMatrix::zeros(n, n),
            dtau_dv: DMatrix::zeros(n, n),
            mass: DMatrix::zeros(n, n),
            tcp: Vector3::zeros(),
            tcp_jacobian: DMatrix::zeros(3, n),
            loss: None,
            pose: None,
            upright: None,
        }
    }

    /// Evaluates the node at (q, v, a): the torques and the TCP, with their derivatives when
    /// `level` is [`Level::Derivatives`].
    pub(super) fn evaluate(
        &mut self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, v, a): (&[f64], &[f64], &[f64]),
        level: Level,
    ) {
        if level == Level::Derivatives {
            dynamics.rnea_derivatives(
                data,
                q,
                v,
                a,
                &mut self.tau,
                &mut self.dtau_dq,
                &mut self.dtau_dv,
                &mut self.mass,
            );
            dynamics.tcp_jacobian(data, q, &mut self.tcp_jacobian);
        } else {
            dynamics.rnea(data, q, v, a, &mut self.tau);
        }
        self.tcp = dynamics.tcp_position(data, q);
    }
}
