//! A link held upright (`motion.upright`, docs/model.md, section 6): with w = R_b(q) a the
//! link's unit axis in the world, one row at each inner node 0 < k < N,
//!
//!   c = (w_z(q_k) - cos tol) / sin tol >= 0,
//!
//! (nodes 0 and N are the task's start and goal, checked when the formulation is built) with
//! dc/dq_j = (u_j x w)_z / sin tol and d^2 c / dq_i dq_j = (u_min(i,j) x (u_max(i,j) x w))_z /
//! sin tol over the revolute joints up to the link's body. It does not depend on the design.

use super::family::{At, Blocks, Emit, Family, NodeSecondOrder, Place, Shape};
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::problem::targets::UprightTarget;
use nalgebra::DMatrix;
use std::sync::Arc;

/// The upright rows.
#[derive(Debug)]
struct Upright(UprightTarget);

/// Where the task holds a link upright.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let target = shape.targets.upright.clone()?;
    Some(Arc::new(Upright(target)))
}

impl Family for Upright {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: 1,
            nodes: Nodes::Inner,
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
        (lower[row], upper[row]) = (0.0, f64::INFINITY);
    }

    fn values(
        &self,
        _p: &DesignData<'_>,
        _x: &[f64],
        node: &NodeEval,
        Place { row, .. }: Place,
        g: &mut [f64],
    ) {
        let (w_z, _) = node
            .upright
            .as_ref()
            .expect("the node holds the upright axis");
        g[row] = self.0.row(*w_z);
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        let scale = 1.0 / self.0.tol_rad.sin();
        let gradient = node.upright.as_ref().map(|(_, gradient)| gradient);
        for j in 0..layout.dof {
            emit(row, layout.q(k, j), gradient.map_or(0.0, |g| g[j] * scale));
        }
    }

    fn hessian(&self, terms: NodeSecondOrder<'_>, (block, _): Blocks<'_>) {
        let NodeSecondOrder {
            dynamics,
            data,
            state: (q, _, _),
            multipliers,
            ..
        } = terms;
        let scale = multipliers[0] / self.0.tol_rad.sin();
        if scale == 0.0 {
            return;
        }
        let n = q.len();
        let mut hessians = [0, 1, 2].map(|_| DMatrix::zeros(n, n));
        let direction = (self.0.body, &self.0.axis);
        dynamics.direction_hessians(data, q, direction, &mut hessians);
        let mut qq = block.view_mut((0, 0), (n, n));
        qq += &hessians[2] * scale;
    }
}
