//! The integration from node k to node k+1 (docs/model.md, section 6), 2n rows per node k < N:
//! the speeds by explicit Euler, v_{k+1} - v_k - h a_k = 0, then the positions by implicit
//! Euler, q_{k+1} - q_k - h v_{k+1} = 0. Linear with constant entries: no Hessian, no design
//! sensitivity.

use super::family::{At, Emit, Family, Place, Shape};
use crate::problem::layout::RowBlock;
use crate::problem::nlp::TrajectoryProblem;
use crate::problem::node::NodeEval;
use std::sync::Arc;

/// The integration rows of n joints.
#[derive(Debug)]
struct Integration {
    dof: usize,
}

/// Every formulation has them.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    Some(Arc::new(Integration { dof: shape.dof }))
}

impl Family for Integration {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: 2 * self.dof,
            inner_only: false,
            relaxed: false,
        })
    }

    fn values(
        &self,
        p: &TrajectoryProblem<'_>,
        x: &[f64],
        _node: &NodeEval,
        Place { k, row }: Place,
        g: &mut [f64],
    ) {
        let f = p.formulation();
        let (layout, h) = (f.layout(), f.step_s());
        let n = layout.dof;
        for i in 0..n {
            g[row + i] = x[layout.v(k + 1, i)] - x[layout.v(k, i)] - h * x[layout.a(k, i)];
            g[row + n + i] = x[layout.q(k + 1, i)] - x[layout.q(k, i)] - h * x[layout.v(k + 1, i)];
        }
    }

    fn jacobian(
        &self,
        at: &At<'_>,
        _node: &NodeEval,
        Place { k, row }: Place,
        emit: &mut Emit<'_>,
    ) {
        let layout = at.formulation().layout();
        let h = match at {
            At::Structure(_) => 0.0,
            At::Design(p) => p.formulation().step_s(),
        };
        let n = layout.dof;
        for i in 0..n {
            emit(row + i, layout.v(k, i), -1.0);
            emit(row + i, layout.a(k, i), -h);
            emit(row + i, layout.v(k + 1, i), 1.0);
        }
        for i in 0..n {
            emit(row + n + i, layout.q(k, i), -1.0);
            emit(row + n + i, layout.q(k + 1, i), 1.0);
            emit(row + n + i, layout.v(k + 1, i), -h);
        }
    }
}
