//! The transmissions' losses where G depends on the pose (docs/model.md, sections 3 and 17).
//! The dynamics rows carry G(q)^T L(t, w) with t = G(q)^-T RNEA(q, v, a) and w = G(q) v, so
//! the pose enters three times: through G^T, through G^-T in t and through G in w. With
//! H_i = d^2 gamma_i/dq^2 (zero for a constant row), C_t = sum_i t_i H_i and D_x = d(G x)/dq
//! (row i: (H_i x)^T), the derivatives of t and w in (q, v, a) are
//!
//!   T = G^-T [dRNEA/dq - C_t, dRNEA/dv, M],    W = [D_v, G, 0],
//!
//! and the rows' Jacobian is G^T diag(L_t) T + G^T diag(L_w) W plus sum_i L_i H_i in q. Under
//! the rows' multipliers lambda, with mu = G lambda and rho = G^-1 (mu o L_t), the Hessian of
//! lambda . G^T L is RNEA's under lambda + rho (as for a constant G), the second derivatives of
//! L in (t, w) through T and W, and what the pose adds:
//!
//!   q-q:   sum_i (L_i d^3 gamma_i[lambda] + mu_i L_w,i d^3 gamma_i[v] - t_i d^3 gamma_i[rho]),
//!   q-v:   sum_i mu_i L_w,i H_i,
//!   q-all: D_lambda^T (diag(L_t) T + diag(L_w) W) - D_rho^T T, with its transpose,
//!
//! from mu's derivative D_lambda, w's second derivatives, and t's second derivatives read off
//! G^T t = RNEA twice differentiated.

use crate::problem::node::NodePose;
use crate::transmission::{speed_derivatives, transmitted_derivatives, MotorLoss, NodeLoss};
use nalgebra::{DMatrix, DVector};

/// The losses at one node whose G depends on the pose.
pub(super) struct PosedLoss<'a> {
    pose: &'a NodePose,
    loss: &'a NodeLoss,
}

/// RNEA's derivatives at a node: dRNEA/dq, dRNEA/dv and M, n x n each (row = joint).
pub(super) type RneaDerivatives<'d> = (&'d DMatrix<f64>, &'d DMatrix<f64>, &'d DMatrix<f64>);

impl<'a> PosedLoss<'a> {
    /// The losses `loss` at the node `pose` (evaluated at its G(q_k)).
    pub(super) fn new(pose: &'a NodePose, loss: &'a NodeLoss) -> PosedLoss<'a> {
        PosedLoss { pose, loss }
    }

    /// One entry per motor of the losses' `of`.
    fn column(&self, of: fn(&MotorLoss) -> f64) -> DVector<f64> {
        let n = self.loss.transmitted().len();
        DVector::from_fn(n, |i, _| of(self.loss.motor(i)))
    }

    /// dRNEA/dq - C_t, n x n: what G^-T maps to dt/dq.
    fn position_derivative(&self, dq: &DMatrix<f64>) -> DMatrix<f64> {
        dq - self.pose.curvature(self.loss.transmitted().as_slice())
    }

    /// The rows' Jacobian blocks in (q, v, a), n x n each (row = joint).
    pub(super) fn jacobian(&self, (dq, dv, mass): RneaDerivatives<'_>) -> [DMatrix<f64>; 3] {
        let by_q = self.position_derivative(dq);
        let [mut q, v, a] = self.loss.jacobian_blocks((&by_q, dv, mass));
        let g = self.pose.actuation.coupling().matrix();
        let values = self.column(|m| m.value);
        let speed = DMatrix::from_diagonal(&self.column(|m| m.w));
        q += self.pose.curvature(values.as_slice())
            + g.tr_mul(&(speed * self.pose.derivative_along(&self.pose.speeds)));
        [q, v, a]
    }

    /// Adds the Hessian of lambda . G(q)^T L beyond RNEA's (which the caller takes under
    /// [`NodeLoss::rnea_multipliers`]) to `block`, (q, v, a) x (q, v, a), both triangles.
    pub(super) fn add_hessian(
        &self,
        lambda: &[f64],
        (dq, dv, mass): RneaDerivatives<'_>,
        block: &mut DMatrix<f64>,
    ) {
        let n = lambda.len();
        let coupling = self.pose.actuation.coupling();
        let g = coupling.matrix();
        let mu = g * DVector::from_column_slice(lambda);
        let (by_t, by_w) = (self.column(|m| m.t), self.column(|m| m.w));
        let rho = coupling.inverse() * mu.component_mul(&by_t);
        let speed_weights = mu.component_mul(&by_w);
        let v = &self.pose.speeds[..];
        let t = transmitted_derivatives(coupling, (&self.position_derivative(dq), dv, mass));
        let w = speed_derivatives(coupling, Some(&self.pose.derivative_along(v)));
        let values = self.column(|m| m.value);
        let qq = self.pose.third_along(values.as_slice(), lambda)
            + self.pose.third_along(speed_weights.as_slice(), v)
            - self
                .pose
                .third_along(self.loss.transmitted().as_slice(), rho.as_slice());
        let mut view = block.view_mut((0, 0), (n, n));
        view += qq;
        let qv = self.pose.curvature(speed_weights.as_slice());
        let mut view = block.view_mut((0, n), (n, n));
        view += &qv;
        let mut view = block.view_mut((n, 0), (n, n));
        view += qv.transpose();
        let by_loss = DMatrix::from_diagonal(&by_t) * &t + DMatrix::from_diagonal(&by_w) * &w;
        let cross = self.pose.derivative_along(lambda).tr_mul(&by_loss)
            - self.pose.derivative_along(rho.as_slice()).tr_mul(&t);
        let mut rows = block.rows_mut(0, n);
        rows += &cross;
        let mut columns = block.columns_mut(0, n);
        columns += cross.transpose();
        self.loss.add_second_order(&mu, (&t, &w), block);
    }
}
