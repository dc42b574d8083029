//! The motors' own torques in the dynamics rows where G depends on the pose (docs/model.md,
//! section 17): m = J_m (G(q) a + h) + B_m G(q) v, each motor's rotor inertia times its
//! acceleration and its viscous friction times its speed, with h_i = v^T H_i v the speed term
//! dG_i/dt v of a linkage row (H_i = d^2 gamma_i/dq^2; zero for a constant row). The rows carry
//! G(q)^T m, of which `Actuation::residual` already holds G^T J_m G a + G^T B_m G v at the
//! node's G(q); this adds G^T J_m h, the q columns of G(q)^T m and h's v columns, and the
//! Hessian of lambda . G^T m = sum_i w_i m_i, w = G lambda, which only linkage rows make
//! non-zero.

use crate::problem::node::NodePose;
use crate::transmission::MotorDynamics;
use nalgebra::{DMatrix, DVector};

/// The motors' own torques at one node whose G depends on the pose.
pub(super) struct MotorLoad<'a> {
    pose: &'a NodePose,
    motors: &'a MotorDynamics,
}

impl<'a> MotorLoad<'a> {
    /// The load of `motors` at the node `pose`.
    pub(super) fn new(pose: &'a NodePose, motors: &'a MotorDynamics) -> MotorLoad<'a> {
        MotorLoad { pose, motors }
    }

    /// G(q_k), row = motor.
    fn g(&self) -> &DMatrix<f64> {
        self.pose.actuation.coupling().matrix()
    }

    /// h_i = v^T H_i v per motor, rad/s^2 (zero for constant rows).
    fn speed_terms(&self) -> DVector<f64> {
        let rows = self.pose.rows.iter();
        speed_terms(
            rows.map(|(motor, row)| (*motor, &row.hessian)),
            &self.vector(&self.pose.speeds),
        )
    }

    /// m = J_m (G a + h) + B_m G v per motor, N m.
    fn own_torques(&self) -> DVector<f64> {
        let (v, a) = (
            self.vector(&self.pose.speeds),
            self.vector(&self.pose.accelerations),
        );
        let accelerations = self.g() * a + self.speed_terms();
        own_torques(self.motors, &(self.g() * v), &accelerations)
    }

    fn vector(&self, values: &[f64]) -> DVector<f64> {
        DVector::from_column_slice(values)
    }

    /// What the rows add to `Actuation::residual`'s motor terms: G^T J_m h, N m per joint.
    pub(super) fn values(&self) -> DVector<f64> {
        speed_term_torques(self.g(), self.motors, &self.speed_terms())
    }

    /// d(G^T m)/dq and d(G^T J_m h)/dv, n x n each (row = joint): sum_i m_i H_i + G^T M_q and
    /// G^T M_v, with row i of M_q J_i (H_i a + T_i[v] v) + B_i H_i v and of M_v 2 J_i H_i v
    /// (T_i = d^3 gamma_i/dq^3; zero rows for constant rows).
    pub(super) fn jacobian(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let (v, a) = (
            self.vector(&self.pose.speeds),
            self.vector(&self.pose.accelerations),
        );
        let n = v.len();
        let (mut by_q, mut by_v) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        let (inertia, friction) = (&self.motors.rotor_inertia, &self.motors.viscous_friction);
        for (motor, row) in &self.pose.rows {
            let i = *motor;
            let along_v = &row.hessian * &v;
            let along_a = &row.hessian * &a;
            let third = row.third_along(&self.pose.speeds) * &v;
            let q_row = (along_a + third) * inertia[i] + &along_v * friction[i];
            by_q.set_row(i, &q_row.transpose());
            by_v.set_row(i, &(along_v * (2.0 * inertia[i])).transpose());
        }
        let m = self.own_torques();
        let curvature = self.pose.curvature(m.as_slice());
        (curvature + self.g().tr_mul(&by_q), self.g().tr_mul(&by_v))
    }

    /// Adds the Hessian of lambda . G^T m to `block`, (q, v, a) x (q, v, a), both triangles
    /// (docs/model.md, section 17: per linkage row, its q-q, v-q, a-q and v-v blocks from
    /// w_i = G_i lambda and the gradients of m_i; F_i, the fourth derivatives, along v twice).
    pub(super) fn add_hessian(&self, lambda: &[f64], block: &mut DMatrix<f64>) {
        let (v, a) = (&self.pose.speeds[..], &self.pose.accelerations[..]);
        let (vv, av) = (self.vector(v), self.vector(a));
        let n = v.len();
        let w = self.g() * self.vector(lambda);
        let m = self.own_torques();
        let (inertia, friction) = (&self.motors.rotor_inertia, &self.motors.viscous_friction);
        for (motor, row) in &self.pose.rows {
            let i = *motor;
            let (j_i, b_i) = (inertia[i], friction[i]);
            let h_lambda = &row.hessian * self.vector(lambda);
            let third_v = row.third_along(v);
            let g_q = (&row.hessian * &av + &third_v * &vv) * j_i + &row.hessian * &vv * b_i;
            let g_v = &row.hessian * &vv * (2.0 * j_i) + &row.gradient * b_i;
            let g_a = &row.gradient * j_i;
            let qq = row.third_along(lambda) * m[i]
                + &h_lambda * g_q.transpose()
                + &g_q * h_lambda.transpose()
                + (row.third_along(a) * j_i + row.fourth_along(v, v) * j_i + &third_v * b_i) * w[i];
            let vq =
                &g_v * h_lambda.transpose() + (&third_v * (2.0 * j_i) + &row.hessian * b_i) * w[i];
            let aq = &g_a * h_lambda.transpose() + &row.hessian * (j_i * w[i]);
            let vv_block = &row.hessian * (2.0 * j_i * w[i]);
            add(block, (0, 0), &qq);
            add(block, (n, 0), &vq);
            add(block, (0, n), &vq.transpose());
            add(block, (2 * n, 0), &aq);
            add(block, (0, 2 * n), &aq.transpose());
            add(block, (n, n), &vv_block);
        }
    }
}

/// block[at + (r, c)] += part[(r, c)].
fn add(block: &mut DMatrix<f64>, (row, column): (usize, usize), part: &DMatrix<f64>) {
    let (rows, columns) = part.shape();
    let mut view = block.view_mut((row, column), (rows, columns));
    view += part;
}

/// h_i = v^T H_i v, rad/s^2, for each (motor i, H_i) of `hessians`; zero for the other motors.
pub(in crate::problem) fn speed_terms<'h>(
    hessians: impl IntoIterator<Item = (usize, &'h DMatrix<f64>)>,
    v: &DVector<f64>,
) -> DVector<f64> {
    let mut h = DVector::zeros(v.len());
    for (motor, hessian) in hessians {
        h[motor] = v.dot(&(hessian * v));
    }
    h
}

/// m_i = J_i accelerations_i + B_i speeds_i per motor of `motors`, N m (motor speeds in rad/s,
/// accelerations in rad/s^2).
pub(in crate::problem) fn own_torques(
    motors: &MotorDynamics,
    speeds: &DVector<f64>,
    accelerations: &DVector<f64>,
) -> DVector<f64> {
    let (inertia, friction) = (&motors.rotor_inertia, &motors.viscous_friction);
    DVector::from_fn(speeds.len(), |i, _| {
        inertia[i] * accelerations[i] + friction[i] * speeds[i]
    })
}

/// G^T J_m h: the joint torques the rotors take through the speed terms `h` (rad/s^2), N m.
pub(in crate::problem) fn speed_term_torques(
    g: &DMatrix<f64>,
    motors: &MotorDynamics,
    h: &DVector<f64>,
) -> DVector<f64> {
    let scaled = DVector::from_fn(h.len(), |i, _| motors.rotor_inertia[i] * h[i]);
    g.tr_mul(&scaled)
}
