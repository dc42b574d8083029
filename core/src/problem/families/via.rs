//! The via points of the motion (`motion.via`, docs/model.md, section 6), each at its node k:
//!
//! - joint angles: bounds q* - tol <= q_k <= q* + tol on the node's positions, within the
//!   joint limits (no row);
//! - a TCP position: one row c = (|p(q_k) - p*|^2 - tol^2) / (2 tol) <= 0 at its node alone
//!   (a block of [`Nodes::Listed`] nodes), with dc/dq = d^T J / tol and
//!   d^2 c / dq^2 = (J^T J + sum_c d_c H_c) / tol, d = p - p*, J = dp/dq, H_c the Hessian of p_c.
//!
//! A via point with a window [t_a, t_b] has its time t_v as a problem-wide variable, which this
//! family bounds to the window (the steps it enters are the integration family's).
//!
//! Neither depends on the design, so neither has a term of dJ*/dr.

use super::family::{At, Blocks, Emit, Family, NodeSecondOrder, Place, Shape};
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock, WideVariable};
use crate::problem::node::NodeEval;
use crate::problem::targets::{JointTarget, TcpTarget};
use nalgebra::DMatrix;
use std::sync::Arc;

/// The via points' bounds and rows.
#[derive(Debug)]
struct Via {
    joints: Vec<JointTarget>,
    /// By node ascending, one per node.
    tcp: Vec<TcpTarget>,
    /// The windows [t_a, t_b] of the via points with one, s, by position in `motion.via`.
    windows: Vec<(usize, [f64; 2])>,
}

/// Where the task has via points.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let (joints, tcp) = (&shape.targets.joints, &shape.targets.tcp);
    (!joints.is_empty() || !tcp.is_empty()).then(|| {
        Arc::new(Via {
            joints: joints.clone(),
            tcp: tcp.clone(),
            windows: shape.targets.windows().collect(),
        }) as Arc<dyn Family>
    })
}

impl Via {
    /// The TCP via point at node k (the block is present only at theirs).
    fn at(&self, k: usize) -> &TcpTarget {
        let i = self.tcp.binary_search_by_key(&k, |t| t.node);
        &self.tcp[i.expect("the via rows sit at their points' nodes")]
    }
}

impl Family for Via {
    fn rows(&self) -> Option<RowBlock> {
        (!self.tcp.is_empty()).then(|| RowBlock {
            per_node: 1,
            nodes: Nodes::Listed(self.tcp.iter().map(|t| t.node).collect()),
            relaxed: false,
        })
    }

    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], upper: &mut [f64]) {
        let layout = p.setting().layout();
        for target in &self.joints {
            for (i, want) in target.q.iter().enumerate() {
                let column = layout.q(target.node, i);
                lower[column] = lower[column].max(want - target.tol_rad);
                upper[column] = upper[column].min(want + target.tol_rad);
            }
        }
        for &(via, [t_a, t_b]) in &self.windows {
            if let Some(column) = layout.wide(WideVariable::ViaTime(via)) {
                (lower[column], upper[column]) = (t_a, t_b);
            }
        }
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
        _p: &DesignData<'_>,
        _x: &[f64],
        node: &NodeEval,
        Place { k, row }: Place,
        g: &mut [f64],
    ) {
        g[row] = self.at(k).row(&node.tcp);
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        let target = self.at(k);
        let d = (node.tcp - target.point) / target.tol_m;
        for j in 0..layout.dof {
            emit(row, layout.q(k, j), d.dot(&node.tcp_jacobian.column(j)));
        }
    }

    fn hessian(&self, terms: NodeSecondOrder<'_>, (block, _): Blocks<'_>) {
        let NodeSecondOrder {
            k,
            dynamics,
            node,
            data,
            state: (q, _, _),
            multipliers,
            ..
        } = terms;
        let target = self.at(k);
        let scale = multipliers[0] / target.tol_m;
        if scale == 0.0 {
            return;
        }
        let n = q.len();
        let mut hessians = [0, 1, 2].map(|_| DMatrix::zeros(n, n));
        dynamics.tcp_hessians(data, q, &mut hessians);
        let d = node.tcp - target.point;
        let j = &node.tcp_jacobian;
        let mut second = j.transpose() * j;
        for (c, hessian) in hessians.iter().enumerate() {
            second += hessian * d[c];
        }
        let mut qq = block.view_mut((0, 0), (n, n));
        qq += second * scale;
    }
}
