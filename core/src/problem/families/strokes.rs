//! The strokes of the linear actuators that give one (`stroke_m`, docs/model.md, section 17):
//! each such screw's length L(q_k) = gamma_i(q_k) l / 2 pi within [min, max] at every node
//! k < N (q_N is the goal, checked with the design). Its row differentiates as the motor angle
//! does, times l / 2 pi: G_i's entries in q, the Hessian lambda l / 2 pi d^2 gamma_i/dq^2; its
//! design sensitivity is lambda (l / 2 pi d gamma_i/dr_l + gamma_i d(l / 2 pi)/dr_l).

use super::family::{
    segment, At, Blocks, DesignDerivative, Emit, Family, NodeSecondOrder, Place, Shape,
};
use crate::ipopt::Solution;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::transmission::linkage::{Linkage, RowDerivatives};
use std::ops::Range;
use std::sync::Arc;

/// One row per screw with a stroke.
#[derive(Debug)]
struct Strokes {
    /// Each screw's motor (row of G), the joints it spans and its stroke [min, max], m.
    screws: Vec<(usize, Range<usize>, [f64; 2])>,
}

/// Rows where some linkage is a screw with a stroke.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let screws: Vec<_> = (shape.linkages.iter())
        .filter_map(|row| Some((row.motor, row.joints(), row.linkage.stroke()?)))
        .collect();
    (!screws.is_empty()).then(|| Arc::new(Strokes { screws }) as Arc<dyn Family>)
}

/// Motor `motor`'s row derivatives at `node`, with its screw's length per motor radian l / 2 pi
/// at the problem's design (m/rad).
fn screw_row(node: &NodeEval, motor: usize) -> Option<(&RowDerivatives, f64)> {
    let pose = node.pose.as_ref()?;
    let (_, row) = pose.rows.iter().find(|(m, _)| *m == motor)?;
    let (_, scale) = pose.screws.iter().find(|(m, _)| *m == motor)?;
    Some((row, *scale))
}

/// Motor `motor`'s linkage in `p`'s transmission.
fn linkage<'p>(p: &'p DesignData<'_>, motor: usize) -> Option<&'p Linkage> {
    let linkages = p.setting().transmission().linkages();
    Some(&linkages.iter().find(|row| row.motor == motor)?.linkage)
}

impl Family for Strokes {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: self.screws.len(),
            nodes: Nodes::Every,
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
        for (s, (_, _, [min, max])) in self.screws.iter().enumerate() {
            (lower[row + s], upper[row + s]) = (*min, *max);
        }
    }

    fn values(
        &self,
        _p: &DesignData<'_>,
        _x: &[f64],
        node: &NodeEval,
        Place { row, .. }: Place,
        g: &mut [f64],
    ) {
        for (s, (motor, _, _)) in self.screws.iter().enumerate() {
            if let Some((derivatives, scale)) = screw_row(node, *motor) {
                g[row + s] = derivatives.angle * scale;
            }
        }
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        for (s, (motor, joints, _)) in self.screws.iter().enumerate() {
            let found = match at {
                At::Structure(_) => None,
                At::Design(_) => screw_row(node, *motor),
            };
            for j in joints.clone() {
                let value = found.map_or(0.0, |(d, scale)| d.gradient[j] * scale);
                emit(row + s, layout.q(k, j), value);
            }
        }
    }

    fn hessian(&self, node: NodeSecondOrder<'_>, (block, _): Blocks<'_>) {
        for (s, (motor, joints, _)) in self.screws.iter().enumerate() {
            let Some((derivatives, scale)) = screw_row(node.node, *motor) else {
                continue;
            };
            let weight = node.multipliers[s] * scale;
            for i in joints.clone() {
                for j in joints.clone() {
                    block[(i, j)] += weight * derivatives.hessian[(i, j)];
                }
            }
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
        let layout = p.setting().layout();
        let q = segment(&solution.x, layout.q(k, 0), layout.dof);
        let Ok(angles) = p.motor_angles(q.as_slice()) else {
            return;
        };
        let l = derivative.parameter;
        for (s, (motor, _, _)) in self.screws.iter().enumerate() {
            let Some(screw) = linkage(p, *motor) else {
                continue;
            };
            let Some(scale) = screw.length_per_angle(p.ratios()) else {
                continue;
            };
            let scale_derivative = screw.length_per_angle_derivative(l);
            let d = scale * derivative.angle[*motor] + angles[*motor] * scale_derivative;
            *total += solution.lambda[row + s] * d;
        }
    }
}
