//! What the trajectory problem minimises, in one place: the cost J (docs/model.md, section 7),
//! its first and second derivatives, and its value term by term ([`CostTerms`]):
//!
//!   J = sum_(k < N) [ w_q |q_k|^2 + w_v |v_k|^2 + sum_i w_u,i u_k,i^2
//!                     + sum_axis rho c_axis(p(q_k))^2 ] + w_T T,
//!
//! with p the TCP's world position and c the soft Cartesian box's violation of one coordinate;
//! the weights are the task's ([`Criterion::Weighted`], w_u,i = w_u) or those of the motors'
//! copper losses ([`Criterion::CopperLoss`]: w_q = w_v = 0, w_u,i = h R_i / k_t,i^2). Its Hessian
//! is diagonal in v and u (2 w_v, 2 w_u,i) and, in q, 2 w_q I plus 2 rho (J^T J + c s H) per
//! violated axis (J = dp_axis/dq, H its Hessian, s = dc/dp = +-1). The duration's term w_T T is
//! linear: a constant for a fixed horizon, a gradient w_T in T for a free one, no Hessian.

use super::layout::Layout;
use super::node::NodeEval;
use super::setting::Setting;
use crate::dynamics::{Dynamics, Workspace};
use crate::model::task::{CartesianBox, Weights};
use crate::solve::Keyed;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// Box penalty of one TCP coordinate p, m: (c, dc/dp) with c = max(0, lo - p) + max(0, p - hi).
fn box_violation(range: [f64; 2], p: f64) -> (f64, f64) {
    if p < range[0] {
        (range[0] - p, -1.0)
    } else if p > range[1] {
        (p - range[1], 1.0)
    } else {
        (0.0, 0.0)
    }
}

/// The constrained world axes of the Cartesian box: (axis 0..3, range in m, weight rho per m^2).
fn box_axes(b: &CartesianBox) -> impl Iterator<Item = (usize, [f64; 2], f64)> + '_ {
    [&b.x, &b.y, &b.z]
        .into_iter()
        .enumerate()
        .filter_map(|(axis, interval)| interval.as_ref().map(|s| (axis, s.range, s.weight)))
}

/// What the trajectory problem minimises besides the soft box (docs/model.md, section 7).
#[derive(Clone, Debug, PartialEq)]
pub enum Criterion {
    /// The task's `weights`: J, the paper's cost.
    Weighted,
    /// The motors' copper losses, J: sum_k h sum_i (R_i / k_t,i^2) u_k,i^2, exact for controls
    /// constant over each interval; the actuation space's controls are the motor torques.
    /// Holds each motor's h R_i / k_t,i^2, J/(N m)^2.
    CopperLoss(Vec<f64>),
}

/// The cost of one formulation: its criterion's weights and the task's `cartesian_box` on its
/// layout.
pub(super) struct Cost<'f> {
    /// w_q per rad^2 and w_v per (rad/s)^2.
    position: f64,
    velocity: f64,
    /// w_u,i of control i, per (N m)^2.
    control: Vec<f64>,
    /// w_T, per s.
    time: f64,
    criterion: &'f Criterion,
    cartesian_box: &'f CartesianBox,
    layout: &'f Layout,
    setting: &'f Setting,
}

impl<'f> Cost<'f> {
    /// The cost `criterion` and the task of `setting` set on its variables.
    pub(super) fn new(criterion: &'f Criterion, setting: &'f Setting) -> Cost<'f> {
        let (task, layout) = (setting.task(), setting.layout());
        let Weights {
            position,
            velocity,
            control,
            time,
        } = task.weights;
        let (position, velocity, control) = match criterion {
            Criterion::Weighted => (position, velocity, vec![control; layout.dof]),
            Criterion::CopperLoss(weights) => (0.0, 0.0, weights.clone()),
        };
        Cost {
            position,
            velocity,
            control,
            time,
            criterion,
            cartesian_box: &task.cartesian_box,
            layout,
            setting,
        }
    }

    /// J at x, with the TCP positions of `nodes` (evaluated at x).
    pub(super) fn value(&self, x: &[f64], nodes: &[NodeEval]) -> f64 {
        let layout = self.layout;
        let mut cost = 0.0;
        for (k, node) in nodes.iter().enumerate() {
            for i in 0..layout.dof {
                let (q, v, u) = (x[layout.q(k, i)], x[layout.v(k, i)], x[layout.u(k, i)]);
                cost += self.position * q * q + self.velocity * v * v + self.control[i] * u * u;
            }
            for (axis, range, weight) in box_axes(self.cartesian_box) {
                let (c, _) = box_violation(range, node.tcp[axis]);
                cost += weight * c * c;
            }
        }
        if self.time != 0.0 {
            cost += self.time * self.setting.horizon_at(x);
        }
        cost
    }

    /// dJ/dx at x into `gradient`, with the TCP positions and Jacobians of `nodes`.
    pub(super) fn gradient(&self, x: &[f64], nodes: &[NodeEval], gradient: &mut [f64]) {
        let layout = self.layout;
        let n = layout.dof;
        gradient.fill(0.0);
        for (k, node) in nodes.iter().enumerate() {
            for i in 0..n {
                let (q, v, u) = (layout.q(k, i), layout.v(k, i), layout.u(k, i));
                gradient[q] = 2.0 * self.position * x[q];
                gradient[v] = 2.0 * self.velocity * x[v];
                gradient[u] = 2.0 * self.control[i] * x[u];
            }
            for (axis, range, weight) in box_axes(self.cartesian_box) {
                let (c, sign) = box_violation(range, node.tcp[axis]);
                if c > 0.0 {
                    for j in 0..n {
                        gradient[layout.q(k, j)] +=
                            2.0 * weight * c * sign * node.tcp_jacobian[(axis, j)];
                    }
                }
            }
        }
        if let Some(column) = layout.horizon() {
            gradient[column] = self.time;
        }
    }

    /// The q-q block of J's Hessian at node `node` (at q_k = `q`) into `hessian` (n x n):
    /// 2 w_q I plus 2 rho (J^T J + c s H) per violated axis. The TCP's Hessians H are computed
    /// into `tcp_hessians` only when an axis is violated.
    pub(super) fn position_hessian(
        &self,
        (dynamics, data): (&Dynamics, &mut Workspace),
        q: &[f64],
        node: &NodeEval,
        tcp_hessians: &mut [DMatrix<f64>; 3],
        hessian: &mut DMatrix<f64>,
    ) {
        hessian.fill_with_identity();
        *hessian *= 2.0 * self.position;
        let mut tcp_hessians_ready = false;
        for (axis, range, weight) in box_axes(self.cartesian_box) {
            let (c, sign) = box_violation(range, node.tcp[axis]);
            if c > 0.0 {
                if !tcp_hessians_ready {
                    dynamics.tcp_hessians(data, q, tcp_hessians);
                    tcp_hessians_ready = true;
                }
                let n = self.layout.dof;
                for i in 0..n {
                    for j in 0..n {
                        let jj = node.tcp_jacobian[(axis, i)] * node.tcp_jacobian[(axis, j)];
                        hessian[(i, j)] +=
                            2.0 * weight * (jj + c * sign * tcp_hessians[axis][(i, j)]);
                    }
                }
            }
        }
    }

    /// The diagonal of the v-v block of J's Hessian: 2 w_v.
    pub(super) fn velocity_hessian(&self) -> f64 {
        2.0 * self.velocity
    }

    /// The u-u block of J's Hessian at control i (diagonal): 2 w_u,i.
    pub(super) fn control_hessian(&self, i: usize) -> f64 {
        2.0 * self.control[i]
    }
}

/// The cost J by term (docs/model.md, section 7), so that a user sees which one dominates; they
/// sum to J.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CostTerms {
    /// w_q sum_(k<N) |q_k|^2.
    pub position: f64,
    /// w_v sum_(k<N) |v_k|^2.
    pub velocity: f64,
    /// w_u sum_(k<N) |u_k|^2 (u: joint torques in joint space, motor torques in actuation
    /// space).
    pub control: f64,
    /// sum_(k<N) sum_axis rho c_axis(p_k)^2: the soft Cartesian box.
    pub cartesian_box: f64,
    /// w_T T, the duration's term (absent when 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub time: f64,
    /// The terms a formulation adds (`Formulation::with_cost`), each under its name.
    #[serde(flatten, skip_serializing_if = "Keyed::is_empty")]
    pub added: Keyed,
}

/// Whether a term is 0: the duration's term is not written then, as before it existed.
fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

impl Cost<'_> {
    /// J at x by term, with the TCP's world position `tcp(k)` at each node k < N and the
    /// added terms' values `added`. Under the copper losses' criterion they are the control
    /// term.
    pub(super) fn terms(
        &self,
        x: &[f64],
        tcp: impl Fn(usize) -> [f64; 3],
        added: Keyed,
    ) -> CostTerms {
        let layout = self.layout;
        let squares = |index: fn(&Layout, usize, usize) -> usize| {
            let mut sum = 0.0;
            for k in 0..layout.steps {
                for i in 0..layout.dof {
                    sum += x[index(layout, k, i)].powi(2);
                }
            }
            sum
        };
        let mut cartesian_box = 0.0;
        for k in 0..layout.steps {
            let p = tcp(k);
            for (axis, [lo, hi], weight) in box_axes(self.cartesian_box) {
                let c = (lo - p[axis]).max(0.0) + (p[axis] - hi).max(0.0);
                cartesian_box += weight * c * c;
            }
        }
        let w = &self.setting.task().weights;
        let (position, velocity, control) = match self.criterion {
            Criterion::Weighted => (
                w.position * squares(Layout::q),
                w.velocity * squares(Layout::v),
                w.control * squares(Layout::u),
            ),
            Criterion::CopperLoss(weights) => {
                let nodes = (0..layout.steps).flat_map(|k| (0..layout.dof).map(move |i| (k, i)));
                let losses = nodes.map(|(k, i)| weights[i] * x[layout.u(k, i)].powi(2));
                (0.0, 0.0, losses.sum())
            }
        };
        CostTerms {
            position,
            velocity,
            control,
            cartesian_box,
            time: self.time * self.setting.horizon_at(x),
            added,
        }
    }
}
