//! The speed rows at the inner nodes 0 < k < N (v_0 = v_N = 0), one per motor:
//!
//! - speed mode `exact`: the motor speeds G v_k within each motor's own limit, |(G v_k)_i| <= w_i;
//! - the elastic kind in the box modes `paper` and `interval`: the joint speeds v_k within the
//!   mode's box, as rows instead of variable bounds, so that a slack can relax them.
//!
//! The elastic kind shifts each row by its speed excess e-_k - e+_k. Linear in v: no Hessian,
//! except where G depends on the pose (docs/model.md, section 17): a linkage row's G_i(q) v has
//! the q columns (d^2 gamma_i/dq^2 v)^T, and the Hessian's q-q block
//! sum_i lambda_i d^3 gamma_i/dq^3 [v] and v-q block sum_i lambda_i d^2 gamma_i/dq^2.
//! The design enters through G (mode `exact`: lambda . dG_l v) or through the box's bounds (the
//! active bound's term -|lambda| . db/dr_l).

use super::family::{
    emit_slacks, segment, slack_shift, At, Blocks, DesignDerivative, Emit, Family, FamilyId,
    NodeSecondOrder, Place, Shape,
};
use super::joint_limits::box_bound_derivative;
use crate::ipopt::Solution;
use crate::model::task::LimitMode;
use crate::problem::design_data::DesignData;
use crate::problem::kind::ProblemKind;
use crate::problem::layout::{Nodes, RowBlock};
use crate::problem::node::{NodeEval, NodePose};
use crate::transmission::JointLimits;
use nalgebra::{DMatrix, DVector};
use std::ops::Range;
use std::sync::Arc;

/// The speed rows A v_k: A = G (mode `exact`) or the identity (the elastic kind's box rows).
#[derive(Debug)]
struct MotorSpeed {
    /// Whether the rows are the box modes' joint speeds (A = I) rather than the motor speeds.
    boxed: bool,
    /// A's structural non-zeros: G's, or the identity's.
    pattern: DMatrix<f64>,
    /// The linkage rows of G(q) (mode `exact`): each motor and the joints it spans.
    linkages: Vec<(usize, Range<usize>)>,
}

/// Rows in speed mode `exact`, and in every mode of the elastic kind.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let boxed = shape.modes.speed != LimitMode::Exact;
    if boxed && shape.kind == ProblemKind::Hard {
        return None;
    }
    let (pattern, linkages) = if boxed {
        (DMatrix::identity(shape.dof, shape.dof), Vec::new())
    } else {
        let linkages = shape.linkages.iter();
        let spans = linkages.map(|row| (row.motor, row.joints())).collect();
        (shape.g_pattern.clone(), spans)
    };
    Some(Arc::new(MotorSpeed {
        boxed,
        pattern,
        linkages,
    }))
}

impl MotorSpeed {
    /// A at the problem's design and `node`'s pose.
    fn matrix<'m>(&'m self, p: &'m DesignData<'_>, node: &'m NodeEval) -> &'m DMatrix<f64> {
        if self.boxed {
            &self.pattern
        } else {
            p.actuation_of(node).coupling().matrix()
        }
    }

    /// The joints whose q columns row i has: those its linkage spans, if it is one.
    fn posed_columns(&self, i: usize) -> Range<usize> {
        (self.linkages.iter())
            .find(|(motor, _)| *motor == i)
            .map_or(0..0, |(_, joints)| joints.clone())
    }
}

impl Family for MotorSpeed {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: self.pattern.nrows(),
            nodes: Nodes::Inner,
            relaxed: true,
        })
    }

    fn row_bounds(
        &self,
        p: &DesignData<'_>,
        Place { row, .. }: Place,
        lower: &mut [f64],
        upper: &mut [f64],
    ) {
        let speed = p.speed_limits();
        for i in 0..self.pattern.nrows() {
            (lower[row + i], upper[row + i]) = match &speed {
                JointLimits::Linear { limits, .. } => (-limits[i], limits[i]),
                JointLimits::Box { lower, upper } => (lower[i], upper[i]),
            };
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
        let a = self.matrix(p, node);
        let n = layout.dof;
        for i in 0..n {
            g[row + i] = (0..n).map(|j| a[(i, j)] * x[layout.v(k, j)]).sum();
            if let Some(e) = slack_shift(x, layout.slack(FamilyId::MotorSpeed, k, i)) {
                g[row + i] += e;
            }
        }
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        let a = match at {
            At::Structure(_) => &self.pattern,
            At::Design(p) => self.matrix(p, node),
        };
        // d(G(q) v)/dq at the node, for the linkage rows.
        let along = match (at, &node.pose) {
            (At::Design(_), Some(pose)) => Some(pose.derivative_along(&pose.speeds)),
            _ => None,
        };
        let n = layout.dof;
        for i in 0..n {
            for j in 0..n {
                if self.pattern[(i, j)] != 0.0 {
                    emit(row + i, layout.v(k, j), a[(i, j)]);
                }
            }
            for j in self.posed_columns(i) {
                emit(
                    row + i,
                    layout.q(k, j),
                    along.as_ref().map_or(0.0, |d| d[(i, j)]),
                );
            }
            emit_slacks(row + i, layout.slack(FamilyId::MotorSpeed, k, i), emit);
        }
    }

    fn hessian(&self, node: NodeSecondOrder<'_>, (block, _): Blocks<'_>) {
        if let Some(pose) = node.node.pose.as_ref().filter(|_| !self.boxed) {
            posed_speed_hessian(pose, node.multipliers, block);
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
        let f = p.setting();
        let layout = f.layout();
        let n = layout.dof;
        let multipliers = segment(&solution.lambda, row, n);
        let g_inv = p.coupling().inverse();
        let limits = f.motor_speed_limits();
        match box_bound_derivative(f.modes().speed, g_inv, &derivative.dg_inv, limits) {
            // Rows G v within fixed bounds (mode `exact`).
            None => {
                *total +=
                    multipliers.dot(&(&derivative.dg * segment(&solution.x, layout.v(k, 0), n)))
            }
            // Rows v within [-b(r), b(r)] (the elastic kind's box modes): the active bound's
            // term -lambda . d(bound)/dr is -|lambda| . db/dr.
            Some(db) => *total += -multipliers.abs().dot(&DVector::from_column_slice(&db)),
        }
    }
}

/// Adds the Hessian of `multipliers` . G(q) v at a node whose G depends on the pose to its
/// (q, v, a) block: sum_i lambda_i T_i[v] in q-q, W(lambda) in v-q.
pub(super) fn posed_speed_hessian(pose: &NodePose, multipliers: &[f64], block: &mut DMatrix<f64>) {
    let n = pose.speeds.len();
    let third = pose.third_along(multipliers, &pose.speeds);
    let curvature = pose.curvature(multipliers);
    for j in 0..n {
        for i in 0..n {
            block[(i, j)] += third[(i, j)];
            block[(n + i, j)] += curvature[(i, j)];
        }
    }
}
