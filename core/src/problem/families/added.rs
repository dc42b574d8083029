//! The rows of a constraint added from outside the core ([`NodeConstraint`]), as a family: its
//! bounds, values and Jacobian node by node, dense over the node's [q, v, a, u]. Its Hessian
//! goes into the node's full block (`../hessian.rs`); it has no design sensitivity (an added
//! term does not depend on r).

use super::family::{At, Emit, Family, FamilyId, Place};
use crate::problem::design_data::DesignData;
use crate::problem::layout::{BlockId, Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::problem::terms::{at_node, node_columns, NodeConstraint};
use nalgebra::DMatrix;
use std::sync::Arc;

/// The row block of the added constraint `i` (0-based, in the order added): after every
/// built-in family's.
pub(in crate::problem) fn block(i: usize) -> BlockId {
    BlockId(FamilyId::COUNT + i)
}

/// The family of one added constraint.
#[derive(Debug)]
pub(in crate::problem) struct Added(pub(in crate::problem) Arc<dyn NodeConstraint>);

impl Family for Added {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: self.0.rows(),
            nodes: Nodes::Every,
            relaxed: false,
        })
    }

    fn row_bounds(
        &self,
        p: &DesignData<'_>,
        Place { k, row }: Place,
        lower: &mut [f64],
        upper: &mut [f64],
    ) {
        let (rows, steps) = (self.0.rows(), p.setting().layout().steps);
        self.0.bounds(
            k,
            steps,
            &mut lower[row..row + rows],
            &mut upper[row..row + rows],
        );
    }

    fn values(
        &self,
        p: &DesignData<'_>,
        x: &[f64],
        _node: &NodeEval,
        Place { k, row }: Place,
        g: &mut [f64],
    ) {
        let rows = self.0.rows();
        at_node(p, x, k, |node| self.0.values(node, &mut g[row..row + rows]));
    }

    fn jacobian(
        &self,
        at: &At<'_>,
        _node: &NodeEval,
        Place { k, row }: Place,
        emit: &mut Emit<'_>,
    ) {
        let layout = at.setting().layout();
        let mut jacobian = DMatrix::zeros(self.0.rows(), 4 * layout.dof);
        if let At::Design(p) = at {
            at_node(p, p.point(), k, |node| self.0.jacobian(node, &mut jacobian));
        }
        for r in 0..self.0.rows() {
            for (c, column) in node_columns(layout, k).enumerate() {
                emit(row + r, column, jacobian[(r, c)]);
            }
        }
    }
}
