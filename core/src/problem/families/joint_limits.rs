//! The joints' limits as bounds on the variables (docs/model.md, section 5):
//!
//! - every position q_k within the URDF's joint limits;
//! - under the box speed modes `paper` and `interval`, every speed v_k within the mode's box
//!   b(r) (where the speeds have no rows: the elastic kind holds that box as speed rows);
//! - in joint space under the box torque modes, every control u_k within the mode's box.
//!
//! The boxes depend on the design: b = |A l| in mode `paper` and b_i = sum_j |A_ij| l_j in mode
//! `interval`, with A = G^-1 for speeds and G^T for torques and l each motor's own limit. Their
//! sensitivity is the active bound's, -(z_L + z_U) . db/dr_l.

use super::family::{DesignDerivative, Family, FamilyId, Shape};
use crate::ipopt::Solution;
use crate::model::task::LimitMode;
use crate::problem::design_data::DesignData;
use crate::transmission::{limit_weights, JointLimits, Space};
use nalgebra::{DMatrix, RowDVector};
use std::sync::Arc;

/// The joint limits' bounds.
#[derive(Debug)]
struct JointBoxes;

/// Every formulation has them (the positions' at least).
pub(super) fn of(_shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    Some(Arc::new(JointBoxes))
}

/// d(upper bound)/dr of the box limits |x_i| <= b_i(r) of a mode, for A(r), dA/dr and the
/// motors' own limits l (b = |A l| in mode `paper`, b_i = sum_j |A_ij| l_j in mode
/// `interval`); None in mode `exact`, which has no box. The sums over the motors are formed as
/// the limits' bounds are ([`limit_weights`]). At a kink of an absolute value (a bound that is
/// exactly 0, such as joint 4's torque under the `paper` mode) the one-sided derivatives differ
/// and 0 is used.
pub(super) fn box_bound_derivative(
    mode: LimitMode,
    a: &DMatrix<f64>,
    da: &DMatrix<f64>,
    limits: &[f64],
) -> Option<Vec<f64>> {
    let sign = |value: f64| {
        if value > 0.0 {
            1.0
        } else if value < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    let (scale, weights) = limit_weights(limits);
    let w = RowDVector::from_row_slice(&weights);
    match mode {
        LimitMode::Paper => Some(
            (0..a.nrows())
                .map(|i| {
                    sign(a.row(i).component_mul(&w).sum())
                        * scale
                        * da.row(i).component_mul(&w).sum()
                })
                .collect(),
        ),
        LimitMode::Interval => Some(
            (0..a.nrows())
                .map(|i| {
                    scale
                        * (0..a.ncols())
                            .map(|j| sign(a[(i, j)]) * da[(i, j)] * weights[j])
                            .sum::<f64>()
                })
                .collect(),
        ),
        LimitMode::Exact => None,
    }
}

impl Family for JointBoxes {
    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], upper: &mut [f64]) {
        let f = p.setting();
        let layout = f.layout();
        let positions = f.dynamics().robot().position_limits();
        let speed = match p.speed_limits() {
            JointLimits::Box { lower, upper } if layout.block(FamilyId::MotorSpeed).is_none() => {
                Some((lower, upper))
            }
            _ => None,
        };
        let torque = match (f.space(), p.control_limits()) {
            (Space::Joint, JointLimits::Box { lower, upper }) => Some((lower, upper)),
            _ => None,
        };
        for k in 0..=layout.steps {
            for i in 0..layout.dof {
                let (q, v) = (layout.q(k, i), layout.v(k, i));
                (lower[q], upper[q]) = positions[i];
                if let Some((lo, hi)) = &speed {
                    (lower[v], upper[v]) = (lo[i], hi[i]);
                }
                if let (Some((lo, hi)), true) = (&torque, k < layout.steps) {
                    let u = layout.u(k, i);
                    (lower[u], upper[u]) = (lo[i], hi[i]);
                }
            }
        }
    }

    /// Bounds x_L = -b(r), x_U = b(r): dL/dr = z_L . dx_L/dr - z_U . dx_U/dr
    /// = -(z_L + z_U) . db/dr, over the speeds of the inner nodes, then the controls.
    fn bound_sensitivity(
        &self,
        p: &DesignData<'_>,
        solution: &Solution,
        derivative: &DesignDerivative,
        total: &mut f64,
    ) {
        let f = p.setting();
        let layout = f.layout();
        let mut bound_term =
            |columns: &dyn Fn(usize, usize) -> usize, nodes: std::ops::Range<usize>, db: &[f64]| {
                for k in nodes {
                    for (i, d) in db.iter().enumerate() {
                        let column = columns(k, i);
                        *total -= (solution.z_lower[column] + solution.z_upper[column]) * d;
                    }
                }
            };
        let g_inv = p.coupling().inverse();
        let (speed, limits) = (f.modes().speed, f.motor_speed_limits());
        if let (Some(db), None) = (
            box_bound_derivative(speed, g_inv, &derivative.dg_inv, limits),
            layout.block(FamilyId::MotorSpeed),
        ) {
            bound_term(&|k, i| layout.v(k, i), 1..layout.steps, &db);
        }
        if f.space() == Space::Joint {
            let g = p.coupling().matrix();
            let (gt, dgt) = (g.transpose(), derivative.dg.transpose());
            let torque = f.modes().torque;
            if let Some(db) = box_bound_derivative(torque, &gt, &dgt, f.motor_torque_limits()) {
                bound_term(&|k, i| layout.u(k, i), 0..layout.steps, &db);
            }
        }
    }
}
