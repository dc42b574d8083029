//! What the derivatives need at one trajectory node k < N, evaluated once per primal point.

use crate::dynamics::{Dynamics, Workspace};
use crate::transmission::NodeLoss;
use nalgebra::{DMatrix, Vector3};

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
