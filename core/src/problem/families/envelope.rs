//! The motors' torque-speed envelope (docs/model.md, section 13) at the inner nodes 0 < k < N,
//! two rows per motor, P then M:
//!
//!   P_i = tau_u,i(u_k) + c_i w_i,  M_i = tau_u,i(u_k) - c_i w_i,  both within +-tau_max,i,
//!
//! with c_i the envelope's slope and w = G v_k + B d_k the motor speeds the rows see: in the
//! elastic kind d_k = e- - e+ is the relaxation of the node's speed rows, and B = G A^-1 maps it
//! to motor speeds (the identity in speed mode `exact`, G in the box modes). At node 0, where
//! v_0 = 0, the rows would be the torque limit itself. The rows are linear: entries
//! d(tau_u)/du in u, +-c_i G_ij in v and -+c_i B_ij, +-c_i B_ij in the node's slacks e+, e-.
//!
//! Where G depends on the pose (docs/model.md, section 17; speed mode `exact`, so B = I), the
//! rows read tau_u and G at the node's G(q_k) and gain q columns: +-c_i (H_i v)^T, and in joint
//! space the motor torque rows' -G^-T W(tau_u). Their Hessian is the motor torque rows' under the
//! multipliers lambda_P + lambda_M and the motor speed rows' under c (lambda_P - lambda_M).

use super::family::{
    segment, slack_shift, At, Blocks, DesignDerivative, Emit, Family, FamilyId, NodeSecondOrder,
    Place, Shape,
};
use super::motor_speed::posed_speed_hessian;
use super::motor_torque::{posed_torque_columns, posed_torque_hessian};
use crate::ipopt::Solution;
use crate::model::task::LimitMode;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Layout, Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::transmission::{Actuation, Side, Space};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// The envelope rows, with the structural non-zeros of their design-dependent blocks.
#[derive(Debug)]
struct Envelope {
    /// Whether B is G (the box speed modes) rather than the identity (mode `exact`).
    slack_through_g: bool,
    /// d(tau_u)/du's: diagonal in actuation space, dense (G^-T) in joint space.
    torque_pattern: DMatrix<f64>,
    /// G's.
    speed_pattern: DMatrix<f64>,
    /// B's: the identity in speed mode `exact`, G's in the box modes.
    slack_pattern: DMatrix<f64>,
    /// The identity, B in speed mode `exact`.
    identity: DMatrix<f64>,
    /// Whether G depends on the pose: the rows are then dense in q.
    posed: bool,
    /// The motors' envelope (its slopes for the Hessian).
    envelope: crate::transmission::Envelope,
}

/// Rows where the motors have an envelope (`motors.no_load_speed_rad_s`).
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let envelope = shape.envelope?.clone();
    let n = shape.dof;
    let slack_through_g = shape.modes.speed != LimitMode::Exact;
    Some(Arc::new(Envelope {
        slack_through_g,
        torque_pattern: match shape.space {
            Space::Actuation => DMatrix::identity(n, n),
            Space::Joint => DMatrix::from_element(n, n, 1.0),
        },
        speed_pattern: shape.g_pattern.clone(),
        slack_pattern: if slack_through_g {
            shape.g_pattern.clone()
        } else {
            DMatrix::identity(n, n)
        },
        identity: DMatrix::identity(n, n),
        posed: !shape.linkages.is_empty(),
        envelope,
    }))
}

/// The elastic kind's relaxation d = e- - e+ of node k's speed rows at x (0 < k < N), the
/// amount by which each row's value is shifted; None in the hard kind.
pub(in crate::problem) fn speed_relaxation(
    layout: &Layout,
    x: &[f64],
    k: usize,
) -> Option<DVector<f64>> {
    let shifts: Option<Vec<f64>> = (0..layout.dof)
        .map(|i| slack_shift(x, layout.slack(FamilyId::MotorSpeed, k, i)))
        .collect();
    shifts.map(DVector::from_vec)
}

impl Envelope {
    /// B at the problem's design.
    fn slack_map<'m>(&'m self, p: &'m DesignData<'_>) -> &'m DMatrix<f64> {
        if self.slack_through_g {
            p.coupling().matrix()
        } else {
            &self.identity
        }
    }

    /// The motor speeds node k's rows see at x: G v_k, and in the elastic kind G v_k + B d_k,
    /// rad/s (G at the node's pose where it depends on the pose).
    fn speeds(&self, p: &DesignData<'_>, x: &[f64], node: &NodeEval, k: usize) -> DVector<f64> {
        let layout = p.setting().layout();
        let g = p.actuation_of(node).coupling().matrix();
        let speeds = g * segment(x, layout.v(k, 0), layout.dof);
        match speed_relaxation(layout, x, k) {
            Some(d) => speeds + self.slack_map(p) * d,
            None => speeds,
        }
    }

    /// Where G depends on the pose, the rows' q columns at the node: d(tau_u)/dq (joint space:
    /// -G^-T W(tau_u); None in actuation space) and d(G v)/dq = D(v); None for the structure.
    fn position_columns(
        &self,
        actuation: Option<&Actuation>,
        node: &NodeEval,
    ) -> (Option<DMatrix<f64>>, Option<DMatrix<f64>>) {
        let (Some(actuation), Some(pose)) = (actuation, &node.pose) else {
            return (None, None);
        };
        let torque =
            (actuation.space() == Space::Joint).then(|| posed_torque_columns(pose, actuation));
        (torque, Some(pose.derivative_along(&pose.speeds)))
    }
}

/// Row `side` of motor i at a node whose envelope rows start at `row`, for n motors.
fn side_row(row: usize, n: usize, i: usize, side: Side) -> usize {
    match side {
        Side::Plus => row + i,
        Side::Minus => row + n + i,
    }
}

impl Family for Envelope {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: 2 * self.identity.nrows(),
            nodes: Nodes::Inner,
            relaxed: false,
        })
    }

    fn row_bounds(
        &self,
        p: &DesignData<'_>,
        Place { row, .. }: Place,
        lower: &mut [f64],
        upper: &mut [f64],
    ) {
        let limits = p.setting().motor_torque_limits();
        for (i, limit) in limits.iter().enumerate() {
            for side in Side::BOTH {
                let r = side_row(row, limits.len(), i, side);
                (lower[r], upper[r]) = (-limit, *limit);
            }
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
        let f = p.setting();
        let (layout, Some(envelope)) = (f.layout(), f.envelope()) else {
            return;
        };
        let torques = p.actuation_of(node).motor_torques(layout.controls(x, k));
        let speeds = self.speeds(p, x, node, k);
        for i in 0..layout.dof {
            for side in Side::BOTH {
                g[side_row(row, layout.dof, i, side)] =
                    envelope.row(i, side, torques[i], speeds[i]);
            }
        }
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let f = at.setting();
        let (layout, Some(envelope)) = (f.layout(), f.envelope()) else {
            return;
        };
        let actuation = at.actuation(node);
        let torque = actuation.map_or(&self.torque_pattern, |a| a.motor_of_control());
        let g = actuation.map_or(&self.speed_pattern, |a| a.coupling().matrix());
        let slack = at.pick(|p| self.slack_map(p), &self.slack_pattern);
        let (torque_q, speed_q) = self.position_columns(actuation, node);
        let n = layout.dof;
        for side in Side::BOTH {
            for i in 0..n {
                let r = side_row(row, n, i, side);
                let slope = side.sign() * envelope.slope(i);
                if self.posed {
                    for j in 0..n {
                        let torque = torque_q.as_ref().map_or(0.0, |d| d[(i, j)]);
                        let speed = speed_q.as_ref().map_or(0.0, |d| d[(i, j)]);
                        emit(r, layout.q(k, j), torque + slope * speed);
                    }
                }
                for j in (0..n).filter(|&j| self.torque_pattern[(i, j)] != 0.0) {
                    emit(r, layout.u(k, j), torque[(i, j)]);
                }
                for j in (0..n).filter(|&j| self.speed_pattern[(i, j)] != 0.0) {
                    emit(r, layout.v(k, j), slope * g[(i, j)]);
                }
                for j in (0..n).filter(|&j| self.slack_pattern[(i, j)] != 0.0) {
                    if let Some([plus, minus]) = layout.slack(FamilyId::MotorSpeed, k, j) {
                        let entry = slope * slack[(i, j)];
                        emit(r, plus, -entry);
                        emit(r, minus, entry);
                    }
                }
            }
        }
    }

    /// Where G depends on the pose: the motor torque rows' Hessian under lambda_P + lambda_M
    /// (joint space) and the motor speed rows' under c (lambda_P - lambda_M).
    fn hessian(&self, node: NodeSecondOrder<'_>, (block, mixed): Blocks<'_>) {
        let (Some(pose), envelope) = (&node.node.pose, &self.envelope) else {
            return;
        };
        let n = pose.speeds.len();
        let (plus, minus) = node.multipliers.split_at(n);
        if node.actuation.space() == Space::Joint {
            let both: Vec<f64> = plus.iter().zip(minus).map(|(p, m)| p + m).collect();
            posed_torque_hessian(pose, node.actuation, &both, (&mut *block, mixed));
        }
        let sloped: Vec<f64> = (0..n)
            .map(|i| envelope.slope(i) * (plus[i] - minus[i]))
            .collect();
        posed_speed_hessian(pose, &sloped, block);
    }

    /// With lambda_P and lambda_M the rows' multipliers:
    /// (lambda_P + lambda_M) . d(tau_u)/dr_l + (lambda_P - lambda_M) . c (dG_l v + dB_l d).
    fn sensitivity(
        &self,
        p: &DesignData<'_>,
        solution: &Solution,
        derivative: &DesignDerivative,
        Place { k, row }: Place,
        total: &mut f64,
    ) {
        let f = p.setting();
        let (layout, Some(envelope)) = (f.layout(), f.envelope()) else {
            return;
        };
        let n = layout.dof;
        let (x, lambda) = (&solution.x, &solution.lambda);
        let (plus, minus) = (
            &lambda[side_row(row, n, 0, Side::Plus)..][..n],
            &lambda[side_row(row, n, 0, Side::Minus)..][..n],
        );
        let dg = &derivative.dg;
        let mut speed_derivative = dg * segment(x, layout.v(k, 0), n);
        // B = G in the elastic kind's box speed modes (dB = dG), the identity in mode `exact`.
        if let (Some(d), true) = (speed_relaxation(layout, x, k), self.slack_through_g) {
            speed_derivative += dg * d;
        }
        // d(G^-T u)/dr_l = dG_inv^T u in joint space (at the node's G where it depends on the
        // pose); u itself in actuation space.
        let u = segment(x, layout.u(k, 0), n);
        let torque_derivative = match f.space() {
            Space::Joint => Some(derivative.dg_inv.tr_mul(&u)),
            Space::Actuation => None,
        };
        *total += (0..n)
            .map(|i| {
                let torque = torque_derivative.as_ref().map_or(0.0, |d| d[i]);
                (plus[i] + minus[i]) * torque
                    + (plus[i] - minus[i]) * envelope.slope(i) * speed_derivative[i]
            })
            .sum::<f64>();
    }
}
