//! A TCP goal (`motion.goal` as `{"tcp", "tol_m"}`, docs/model.md, section 6): the last node's
//! positions q_N are free within the joint limits, and one row holds the TCP inside the goal's
//! ball there, c = (|p(q_N) - p*|^2 - tol^2) / (2 tol) <= 0, the TCP via point's row on q_N.
//!
//! Node N has no row block of its own (its variables are [q_N, v_N] alone), so the row sits in
//! node N-1's block and reads q_N: its Jacobian entries are in q_N's columns, and its second
//! derivatives (J^T J + sum_c d_c H_c) lambda / tol, the q_N-q_N block, are entries outside the
//! node blocks ([`Family::wide_hessian`]). It reads the point evaluated last, which a
//! formulation with a TCP goal keeps. It does not depend on the design: no term of dJ*/dr.

use super::family::{At, Emit, Family, Place, Shape};
use crate::dynamics::Dynamics;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Layout, Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::problem::targets::TcpTarget;
use nalgebra::{DMatrix, Vector3};
use std::sync::Arc;

/// The TCP goal's row.
#[derive(Debug)]
struct Goal {
    /// The ball, at the last node N.
    ball: TcpTarget,
}

/// Where the task's goal is a TCP position.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let goal = shape.targets.goal.as_ref()?;
    Some(Arc::new(Goal {
        ball: goal.ball.clone(),
    }))
}

/// The last node's positions q_N in the primal point x.
fn last_pose<'x>(layout: &Layout, x: &'x [f64]) -> &'x [f64] {
    let first = layout.q(layout.steps, 0);
    &x[first..first + layout.dof]
}

/// The TCP at q and its Jacobian dp/dq (3 x n).
fn tcp_and_jacobian(dynamics: &Dynamics, q: &[f64]) -> (Vector3<f64>, DMatrix<f64>) {
    let mut data = dynamics.workspace();
    let mut jacobian = DMatrix::zeros(3, q.len());
    dynamics.tcp_jacobian(&mut data, q, &mut jacobian);
    (dynamics.tcp_position(&mut data, q), jacobian)
}

impl Family for Goal {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: 1,
            nodes: Nodes::Listed(vec![self.ball.node - 1].into()),
            relaxed: false,
        })
    }

    fn row_bounds(
        &self,
        _p: &DesignData<'_>,
        Place { row, .. }: Place,
        lower: &mut [f64],
        upper: &mut [f64],
    ) {
        (lower[row], upper[row]) = (f64::NEG_INFINITY, 0.0);
    }

    fn values(
        &self,
        p: &DesignData<'_>,
        x: &[f64],
        _node: &NodeEval,
        Place { row, .. }: Place,
        g: &mut [f64],
    ) {
        let setting = p.setting();
        let dynamics = setting.dynamics();
        let q = last_pose(setting.layout(), x);
        g[row] = self
            .ball
            .row(&dynamics.tcp_position(&mut dynamics.workspace(), q));
    }

    fn jacobian(
        &self,
        at: &At<'_>,
        _node: &NodeEval,
        Place { row, .. }: Place,
        emit: &mut Emit<'_>,
    ) {
        let layout = at.setting().layout();
        let last = layout.steps;
        let At::Design(p) = at else {
            (0..layout.dof).for_each(|j| emit(row, layout.q(last, j), 0.0));
            return;
        };
        let (tcp, jacobian) =
            tcp_and_jacobian(p.setting().dynamics(), last_pose(layout, p.point()));
        let d = (tcp - self.ball.point) / self.ball.tol_m;
        for j in 0..layout.dof {
            emit(row, layout.q(last, j), d.dot(&jacobian.column(j)));
        }
    }

    fn wide_hessian(&self, at: &At<'_>, _place: Place, multipliers: &[f64], emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        let (n, last) = (layout.dof, layout.steps);
        let second = match at {
            At::Structure(_) => DMatrix::zeros(n, n),
            At::Design(p) => {
                let dynamics = p.setting().dynamics();
                let q = last_pose(layout, p.point());
                let (tcp, jacobian) = tcp_and_jacobian(dynamics, q);
                let mut hessians = [0, 1, 2].map(|_| DMatrix::zeros(n, n));
                dynamics.tcp_hessians(&mut dynamics.workspace(), q, &mut hessians);
                let d = tcp - self.ball.point;
                let mut second = jacobian.transpose() * &jacobian;
                for (c, hessian) in hessians.iter().enumerate() {
                    second += hessian * d[c];
                }
                second * (multipliers[0] / self.ball.tol_m)
            }
        };
        for i in 0..n {
            for j in 0..=i {
                emit(layout.q(last, i), layout.q(last, j), second[(i, j)]);
            }
        }
    }
}
