//! The integration from node k to node k+1 (docs/model.md, section 6), 2n rows per node k < N:
//! the speeds by explicit Euler, v_{k+1} - v_k - h_k a_k = 0, then the positions by implicit
//! Euler, q_{k+1} - q_k - h_k v_{k+1} = 0, with h_k the interval's step ([`Grid`]: T/N on an
//! unphased grid). Linear where the steps are constants: no Hessian, no design sensitivity. A
//! free horizon or a via point's window makes h_k affine in problem-wide variables w (T is
//! bounded here to [T_min, T_max], a via time by the via family): the rows gain the entries
//! -a_k dh_k/dw and -v_{k+1} dh_k/dw in w's column, and the Lagrangian the cross terms
//! -lambda dh_k/dw between w and a_k, v_{k+1}.
//!
//! [`Grid`]: crate::problem::Grid

use super::family::{At, Emit, Family, Place, Shape};
use crate::model::task::Horizon;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock};
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
            nodes: Nodes::Every,
            relaxed: false,
        })
    }

    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], upper: &mut [f64]) {
        let s = p.setting();
        if let (Some(column), Horizon::Free { min_s, max_s }) =
            (s.layout().horizon(), s.task().motion.horizon)
        {
            lower[column] = min_s;
            upper[column] = max_s;
        }
    }

    fn values(
        &self,
        p: &DesignData<'_>,
        x: &[f64],
        _node: &NodeEval,
        Place { k, row }: Place,
        g: &mut [f64],
    ) {
        let f = p.setting();
        let (layout, h) = (f.layout(), f.step_at(x, k));
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
        let (layout, grid) = (at.setting().layout(), at.setting().grid());
        let (h, x) = match at {
            At::Structure(_) => (0.0, None),
            At::Design(p) => (p.setting().step_at(p.point(), k), Some(p.point())),
        };
        let n = layout.dof;
        // d(row)/dw = -(the variable h multiplies) dh_k/dw, w a problem-wide variable.
        let wide = |row: usize, column: usize, emit: &mut Emit<'_>| {
            for (w, dh) in grid.step_gradient(k) {
                emit(row, w, x.map_or(0.0, |x| -x[column] * dh));
            }
        };
        for i in 0..n {
            emit(row + i, layout.v(k, i), -1.0);
            emit(row + i, layout.a(k, i), -h);
            emit(row + i, layout.v(k + 1, i), 1.0);
            wide(row + i, layout.a(k, i), emit);
        }
        for i in 0..n {
            emit(row + n + i, layout.q(k, i), -1.0);
            emit(row + n + i, layout.q(k + 1, i), 1.0);
            emit(row + n + i, layout.v(k + 1, i), -h);
            wide(row + n + i, layout.v(k + 1, i), emit);
        }
    }

    fn wide_hessian(
        &self,
        at: &At<'_>,
        Place { k, .. }: Place,
        multipliers: &[f64],
        emit: &mut Emit<'_>,
    ) {
        let (layout, grid) = (at.setting().layout(), at.setting().grid());
        let (speeds, positions) = multipliers.split_at(layout.dof);
        for (w, dh) in grid.step_gradient(k) {
            for (i, lambda) in speeds.iter().enumerate() {
                emit(w, layout.a(k, i), -lambda * dh);
            }
            for (i, lambda) in positions.iter().enumerate() {
                emit(w, layout.v(k + 1, i), -lambda * dh);
            }
        }
    }
}
