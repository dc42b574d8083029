//! The motors' torque limits, |tau_u,i| <= tau_max,i at every node k < N:
//!
//! - in actuation space the controls are the motor torques: a box on u_k, free of the design;
//! - in joint space under torque mode `exact`, rows G^-T u_k (one per motor) within the limits,
//!   whose design sensitivity is lambda . d(G^-T)/dr_l u = lambda . dG_inv^T u.
//!
//! The joint-space boxes of the modes `paper` and `interval` are joint limits
//! (`joint_limits.rs`).
//!
//! Where G depends on the pose (docs/model.md, section 17), the rows tau_u = G(q)^-T u have the
//! q columns -G^-T W, W = sum_i tau_u,i d^2 gamma_i/dq^2; with w = G^-1 lambda and D the matrix
//! whose row i is (d^2 gamma_i/dq^2 w)^T, lambda . tau_u has the q-q block
//! D^T G^-T W + W G^-1 D - sum_i tau_u,i d^3 gamma_i/dq^3 [w] and the u-q block -G^-1 D.

use super::family::{
    segment, At, Blocks, DesignDerivative, Emit, Family, NodeSecondOrder, Place, Shape,
};
use crate::ipopt::Solution;
use crate::model::task::LimitMode;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock};
use crate::problem::node::{NodeEval, NodePose};
use crate::transmission::{Actuation, JointLimits, Space};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// The motor torque limits of one space.
#[derive(Debug)]
enum MotorTorque {
    /// Actuation space: bounds on u.
    Bounds,
    /// Joint space, mode `exact`: rows G^-T u, whose pattern is dense, and dense in q too
    /// where G depends on the pose (`posed`).
    Rows { pattern: DMatrix<f64>, posed: bool },
}

/// Bounds in actuation space, rows in joint space under torque mode `exact`.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let n = shape.dof;
    match (shape.space, shape.modes.torque) {
        (Space::Actuation, _) => Some(Arc::new(MotorTorque::Bounds)),
        (Space::Joint, LimitMode::Exact) => Some(Arc::new(MotorTorque::Rows {
            pattern: DMatrix::from_element(n, n, 1.0),
            posed: !shape.linkages.is_empty(),
        })),
        (Space::Joint, LimitMode::Paper | LimitMode::Interval) => None,
    }
}

impl Family for MotorTorque {
    fn rows(&self) -> Option<RowBlock> {
        match self {
            MotorTorque::Bounds => None,
            MotorTorque::Rows { pattern, .. } => Some(RowBlock {
                per_node: pattern.nrows(),
                nodes: Nodes::Every,
                relaxed: false,
            }),
        }
    }

    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], upper: &mut [f64]) {
        let layout = p.setting().layout();
        let JointLimits::Box {
            lower: lo,
            upper: hi,
        } = p.control_limits()
        else {
            return;
        };
        for k in 0..layout.steps {
            for i in 0..layout.dof {
                let u = layout.u(k, i);
                (lower[u], upper[u]) = (lo[i], hi[i]);
            }
        }
    }

    fn row_bounds(
        &self,
        p: &DesignData<'_>,
        Place { row, .. }: Place,
        lower: &mut [f64],
        upper: &mut [f64],
    ) {
        for (i, limit) in p.setting().motor_torque_limits().iter().enumerate() {
            (lower[row + i], upper[row + i]) = (-limit, *limit);
        }
    }

    fn values(
        &self,
        p: &DesignData<'_>,
        x: &[f64],
        node: &NodeEval,
        Place { k, row }: Place,
        g: &mut [f64],
    ) {
        let layout = p.setting().layout();
        let u = layout.controls(x, k);
        let motor_of_joint = p.actuation_of(node).motor_of_joint();
        for i in 0..layout.dof {
            g[row + i] = (0..layout.dof).map(|j| motor_of_joint[(i, j)] * u[j]).sum();
        }
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let MotorTorque::Rows { pattern, posed } = self else {
            return;
        };
        let layout = at.setting().layout();
        let actuation = at.actuation(node);
        let motor_of_joint = actuation.map_or(pattern, |a| a.motor_of_joint());
        let position = match (actuation, &node.pose) {
            (Some(actuation), Some(pose)) => Some(posed_torque_columns(pose, actuation)),
            _ => None,
        };
        for i in 0..layout.dof {
            if *posed {
                for j in 0..layout.dof {
                    emit(
                        row + i,
                        layout.q(k, j),
                        position.as_ref().map_or(0.0, |d| d[(i, j)]),
                    );
                }
            }
            for j in 0..layout.dof {
                emit(row + i, layout.u(k, j), motor_of_joint[(i, j)]);
            }
        }
    }

    fn hessian(&self, node: NodeSecondOrder<'_>, blocks: Blocks<'_>) {
        if let Some(pose) = &node.node.pose {
            posed_torque_hessian(pose, node.actuation, node.multipliers, blocks);
        }
    }

    fn sensitivity(
        &self,
        p: &DesignData<'_>,
        solution: &Solution,
        derivative: &DesignDerivative,
        Place { k, row }: Place,
        total: &mut f64,
    ) {
        let n = p.setting().layout().dof;
        let u = segment(&solution.x, p.setting().layout().u(k, 0), n);
        // G^-T u differentiates to -G^-T dG^T G^-T u = dG_inv^T u.
        *total += segment(&solution.lambda, row, n).dot(&derivative.dg_inv.tr_mul(&u));
    }
}

/// d(G(q)^-T u)/dq = -G^-T W(tau_u) at a node whose G depends on the pose (joint space), n x n
/// (row = motor).
pub(super) fn posed_torque_columns(pose: &NodePose, actuation: &Actuation) -> DMatrix<f64> {
    let torques = actuation.motor_torques(&pose.controls);
    -(actuation.motor_of_joint() * pose.curvature(&torques))
}

/// Adds the Hessian of `multipliers` . G(q)^-T u at a node whose G depends on the pose (in
/// joint space; see the module's documentation) to the node's blocks.
pub(super) fn posed_torque_hessian(
    pose: &NodePose,
    actuation: &Actuation,
    multipliers: &[f64],
    (block, mixed): Blocks<'_>,
) {
    let g_inv = actuation.coupling().inverse();
    let torques = actuation.motor_torques(&pose.controls);
    let w = g_inv * DVector::from_column_slice(multipliers);
    let d = pose.derivative_along(w.as_slice());
    let curvature = pose.curvature(&torques);
    let through = d.tr_mul(&g_inv.transpose()) * &curvature;
    let third = pose.third_along(&torques, w.as_slice());
    let n = mixed.nrows();
    for j in 0..n {
        for i in 0..n {
            block[(i, j)] += through[(i, j)] + through[(j, i)] - third[(i, j)];
        }
    }
    *mixed -= g_inv * d;
}
