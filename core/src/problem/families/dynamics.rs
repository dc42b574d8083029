//! The equations of motion at every node k < N, one row per joint:
//!
//!   RNEA(q_k, v_k, a_k) + G^T J_m G a_k + G^T B_m G v_k + G^T L - C u_k = 0,
//!
//! with C = G^T in actuation space and the identity in joint space, the motors' rotor inertia
//! J_m and friction B_m reflected into the joints (absent for ideal motors), and the
//! transmissions' loss torques L(G^-T RNEA, G v_k) (absent where lossless). The elastic kind
//! shifts each row by its torque deficit s-_k - s+_k. The rows' Jacobian is dense in (q, v, a)
//! and C's pattern in u; their Hessian is lambda . RNEA's, plus the losses' (docs/model.md,
//! sections 3 and 8); their design sensitivity is the actuation's residual derivative, the
//! losses' and, where the links carry parts that follow the design, RNEA's through their
//! inertia (section 18).
//!
//! Where G depends on the pose (docs/model.md, section 17), C = G(q)^T in actuation space adds
//! -sum_i u_i d^2 gamma_i/dq^2 to the q columns, and the Hessian's q-q block
//! -sum_i u_i d^3 gamma_i/dq^3 [lambda] and u-q block -d^2 gamma_i/dq^2 lambda (row i). The
//! motors' own torques G(q)^T (J_m qdd_u + B_m qd_u), with qdd_u = G a + dG/dt v, add the terms
//! of `motor_load.rs`.

use super::family::{
    emit_slacks, slack_shift, At, Blocks, DesignDerivative, Emit, Family, FamilyId,
    NodeSecondOrder, Place, Shape,
};
use super::motor_load::MotorLoad;
use super::posed_loss::PosedLoss;
use crate::ipopt::Solution;
use crate::problem::design_data::DesignData;
use crate::problem::layout::{Nodes, RowBlock};
use crate::problem::node::NodeEval;
use crate::transmission::{Actuation, MotorDynamics, NodeLoss, Space};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// The dynamics rows, with the structural non-zeros of C.
#[derive(Debug)]
struct Dynamics {
    /// The pattern of d(tau_i)/d(u_j): G^T's in actuation space, the identity's in joint space.
    control_pattern: DMatrix<f64>,
    /// Whether C = G(q)^T depends on the pose (actuation space, a linkage row).
    posed: bool,
    /// The motors' rotor inertia and friction where G depends on the pose (both spaces).
    motors: Option<MotorDynamics>,
}

/// Every formulation has them.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    let control_pattern = match shape.space {
        Space::Actuation => shape.g_pattern.transpose(),
        Space::Joint => DMatrix::identity(shape.dof, shape.dof),
    };
    let posed = shape.space == Space::Actuation && !shape.linkages.is_empty();
    let motors = shape.motors.filter(|_| !shape.linkages.is_empty()).cloned();
    Some(Arc::new(Dynamics {
        control_pattern,
        posed,
        motors,
    }))
}

/// value + m[(i, j)], or value itself without m (no rounding where there is nothing to add).
fn plus(value: f64, m: Option<&DMatrix<f64>>, (i, j): (usize, usize)) -> f64 {
    m.map_or(value, |m| value + m[(i, j)])
}

impl Dynamics {
    /// The motors' own torques at `node` where G depends on the pose and the motors have
    /// inertia or friction.
    fn load<'a>(&'a self, node: &'a NodeEval) -> Option<MotorLoad<'a>> {
        Some(MotorLoad::new(node.pose.as_ref()?, self.motors.as_ref()?))
    }
}

impl Family for Dynamics {
    fn rows(&self) -> Option<RowBlock> {
        Some(RowBlock {
            per_node: self.control_pattern.nrows(),
            nodes: Nodes::Every,
            relaxed: true,
        })
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
        let u = layout.controls(x, k);
        let (_, v, a) = layout.node_state(x, k);
        let actuation = p.actuation_of(node);
        let load = self.load(node).map(|load| load.values());
        for i in 0..layout.dof {
            g[row + i] = actuation.residual(i, &node.tau, (v, a), u);
            if let Some(load) = &load {
                g[row + i] += load[i];
            }
            if let Some(loss) = &node.loss {
                g[row + i] += loss.joint_torques()[i];
            }
            if let Some(s) = slack_shift(x, layout.slack(FamilyId::Dynamics, k, i)) {
                g[row + i] += s;
            }
        }
    }

    fn jacobian(&self, at: &At<'_>, node: &NodeEval, Place { k, row }: Place, emit: &mut Emit<'_>) {
        let layout = at.setting().layout();
        let actuation = at.actuation(node);
        let control = actuation.map_or(&self.control_pattern, |a| a.control_map());
        let reflected = actuation.and_then(|a| a.reflected());
        let (inertia, damping) = (reflected.map(|r| r.0), reflected.map(|r| r.1));
        // d(G(q)^T u)/dq, subtracted from the q columns.
        let curvature = match (&node.pose, actuation) {
            (Some(pose), Some(_)) if self.posed => Some(-pose.curvature(&pose.controls)),
            _ => None,
        };
        // The motors' own torques through G(q): their q columns and their speed term's v ones.
        let (load_q, load_v) = self.load(node).map(|load| load.jacobian()).unzip();
        let losses = node.loss.as_ref().map(|loss| {
            let rnea = (&node.dtau_dq, &node.dtau_dv, &node.mass);
            match &node.pose {
                Some(pose) => PosedLoss::new(pose, loss).jacobian(rnea),
                None => loss.jacobian_blocks(rnea),
            }
        });
        let [dq, dv, da] = [0, 1, 2].map(|b| losses.as_ref().map(|blocks| &blocks[b]));
        let n = layout.dof;
        for i in 0..n {
            let r = row + i;
            for j in 0..n {
                let value = plus(node.dtau_dq[(i, j)], curvature.as_ref(), (i, j));
                let value = plus(value, load_q.as_ref(), (i, j));
                emit(r, layout.q(k, j), plus(value, dq, (i, j)));
            }
            for j in 0..n {
                let value = plus(node.dtau_dv[(i, j)], damping, (i, j));
                let value = plus(value, load_v.as_ref(), (i, j));
                emit(r, layout.v(k, j), plus(value, dv, (i, j)));
            }
            for j in 0..n {
                let value = plus(node.mass[(i, j)], inertia, (i, j));
                emit(r, layout.a(k, j), plus(value, da, (i, j)));
            }
            for j in 0..n {
                if self.control_pattern[(i, j)] != 0.0 {
                    emit(r, layout.u(k, j), -control[(i, j)]);
                }
            }
            emit_slacks(r, layout.slack(FamilyId::Dynamics, k, i), emit);
        }
    }

    /// lambda . RNEA's Hessian; with losses, RNEA's under the multipliers that carry the
    /// losses' first derivative in tau, and the losses' own second derivatives.
    fn hessian(&self, node: NodeSecondOrder<'_>, (block, mixed): Blocks<'_>) {
        if self.posed {
            if let Some(pose) = &node.node.pose {
                let n = mixed.nrows();
                let third = pose.third_along(&pose.controls, node.multipliers);
                for j in 0..n {
                    for i in 0..n {
                        block[(i, j)] -= third[(i, j)];
                    }
                }
                *mixed -= pose.derivative_along(node.multipliers);
            }
        }
        if let Some(load) = self.load(node.node) {
            load.add_hessian(node.multipliers, block);
        }
        let (q, v, a) = node.state;
        let hessian = node.scratch;
        let coupling = node.actuation.coupling();
        let through_losses;
        let multipliers = match &node.node.loss {
            None => node.multipliers,
            Some(loss) => {
                through_losses = loss.rnea_multipliers(coupling, node.multipliers);
                &through_losses[..]
            }
        };
        node.dynamics
            .rnea_hessian(node.data, q, v, a, multipliers, hessian);
        *block += &*hessian;
        if let Some(loss) = &node.node.loss {
            let e = node.node;
            let derivatives = (&e.dtau_dq, &e.dtau_dv, &e.mass);
            match &e.pose {
                Some(pose) => {
                    PosedLoss::new(pose, loss).add_hessian(node.multipliers, derivatives, block)
                }
                None => loss.add_hessian(coupling, node.multipliers, derivatives, block),
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
        let x = &solution.x;
        let (_, v, a) = layout.node_state(x, k);
        let u = layout.controls(x, k);
        let lambda = super::family::segment(&solution.lambda, row, layout.dof);
        if let (Some(load), Some(at)) = (&derivative.load, &derivative.coupling) {
            // d/dr_l of G^T (m - u) (actuation space) or G^T m (joint space) at G(q_k).
            let mut own = load.own.clone();
            if self.posed {
                own -= DVector::from_column_slice(u);
            }
            let d = derivative.dg.tr_mul(&own) + at.matrix().tr_mul(&load.own_derivative);
            *total += lambda.dot(&d);
        } else if let Some(d) = p.actuation().residual_derivative(&derivative.dg, (v, a), u) {
            *total += lambda.dot(&d);
        }
        if p.actuation().loss().is_some() {
            *total += lambda.dot(&loss_derivative(p, x, k, derivative));
        }
        let lambda = &solution.lambda[row..row + layout.dof];
        *total += carried_derivative(p, x, (k, lambda), derivative);
    }
}

/// The design's actuation at node k of x (G(q_k) where G depends on the pose), RNEA there
/// and the transmissions' losses at it, None where lossless: the Lagrangian's partial
/// derivative holds x fixed, so RNEA is evaluated again at the node.
fn lossy_node(
    p: &DesignData<'_>,
    x: &[f64],
    k: usize,
    derivative: &DesignDerivative,
) -> Option<(Actuation, NodeLoss, Vec<f64>)> {
    let f = p.setting();
    let (q, v, a) = f.layout().node_state(x, k);
    let dynamics = p.dynamics();
    let mut tau = vec![0.0; f.layout().dof];
    dynamics.rnea(&mut dynamics.workspace(), q, v, a, &mut tau);
    let actuation = match &derivative.coupling {
        Some(at) => f.actuation(at.clone()),
        None => p.actuation().clone(),
    };
    let loss = actuation.node_loss(&tau, v)?;
    Some((actuation, loss, tau))
}

/// d/dr_l of the losses' term G^T L of node k's rows at x, N m, at G(q_k) where G depends on
/// the pose.
fn loss_derivative(
    p: &DesignData<'_>,
    x: &[f64],
    k: usize,
    derivative: &DesignDerivative,
) -> DVector<f64> {
    let (actuation, loss, tau) = lossy_node(p, x, k, derivative).expect("the actuation has losses");
    let v = p.setting().layout().node_state(x, k).1;
    let d = (&derivative.dg, &derivative.dg_inv);
    loss.design_derivative(actuation.coupling(), d, &tau, v)
}

/// lambda . d/dr_l of node k's rows through the carried parts' inertia (docs/model.md,
/// section 18): RNEA's derivative in the inertial parameters along their change with r_l,
/// under the multipliers that carry the losses' derivative in tau where there are losses; 0
/// where no part follows r_l.
fn carried_derivative(
    p: &DesignData<'_>,
    x: &[f64],
    (k, lambda): (usize, &[f64]),
    derivative: &DesignDerivative,
) -> f64 {
    let state = p.setting().layout().node_state(x, k);
    let Some(d_rnea) = p.rnea_design_derivative(state, derivative.parameter) else {
        return 0.0;
    };
    let through = p.actuation().loss().and_then(|_| {
        let (actuation, loss, _) = lossy_node(p, x, k, derivative)?;
        Some(loss.rnea_multipliers(actuation.coupling(), lambda))
    });
    let multipliers = through.as_deref().unwrap_or(lambda);
    multipliers.iter().zip(&d_rnea).map(|(m, d)| m * d).sum()
}
