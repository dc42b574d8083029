//! Transmission losses (docs/model.md, section 3): a Coulomb-like friction in each motor's
//! transmission, proportional to the torque it transmits and opposing the motion.
//!
//! Motor i's transmission passes t_i = (G^-T tau)_i, the joint torques tau the links take seen
//! at motor i (N m), at the motor speed w_i = (G v)_i (rad/s). With efficiency eta_i it asks of
//! the motor the loss torque
//!
//!   L_i(t_i, w_i) = k_i s_i(t_i) sigma_i(w_i),   k_i = (1 - eta_i) / eta_i,
//!   s_i(t) = sqrt(t^2 + eps_i^2),   sigma_i(w) = tanh(w / omega_i),
//!
//! the smooth form of k_i |t_i| sign(w_i): where the motor drives the load (t w > 0) it gives
//! t + L = t / eta, the efficiency itself; where the load drives the motor, t (2 - 1 / eta).
//! eps_i and omega_i are [`TORQUE_SMOOTHING`] and [`SPEED_SMOOTHING`] of the motor's torque
//! and speed limits. The motor torque the motion asks for gains L, and the dynamics rows
//! G^T L(G^-T RNEA(q, v, a), G v): [`NodeLoss`] holds it at one node with its first and second
//! derivatives in (q, v, a) and its derivative in r.

use super::Coupling;
use crate::model::task::Motors;
use nalgebra::{DMatrix, DVector};

/// eps_i, the torque below which |t| is rounded, as a share of motor i's torque limit.
pub const TORQUE_SMOOTHING: f64 = 1e-2;
/// omega_i, the speed over which the loss turns with the motion, as a share of motor i's speed
/// limit.
pub const SPEED_SMOOTHING: f64 = 5e-2;

/// The transmissions' losses of every motor (motor i = row i of G).
#[derive(Clone, Debug, PartialEq)]
pub struct TransmissionLoss {
    /// k_i = (1 - eta_i) / eta_i, dimensionless.
    factors: Vec<f64>,
    /// eps_i, N m.
    torque_scales: Vec<f64>,
    /// omega_i, rad/s.
    speed_scales: Vec<f64>,
}

/// One motor's loss torque L(t, w) (N m) with its derivatives in t (N m) and w (rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotorLoss {
    /// L, N m.
    pub value: f64,
    /// dL/dt, dimensionless.
    pub t: f64,
    /// dL/dw, N m s/rad.
    pub w: f64,
    /// d^2L/dt^2, 1/(N m).
    pub tt: f64,
    /// d^2L/dt dw, s/rad.
    pub tw: f64,
    /// d^2L/dw^2, N m s^2/rad^2.
    pub ww: f64,
}

impl TransmissionLoss {
    /// The losses the task's `motors` give `count` motors (checked by [`Motors::validate`]),
    /// None without `efficiency` (lossless transmissions).
    pub fn of(motors: &Motors, count: usize) -> Option<TransmissionLoss> {
        let efficiency = motors.efficiency.as_ref()?.values(count);
        let scaled = |limits: Vec<f64>, share: f64| limits.iter().map(|l| share * l).collect();
        Some(TransmissionLoss {
            factors: efficiency.iter().map(|eta| (1.0 - eta) / eta).collect(),
            torque_scales: scaled(motors.torque_limit_nm.values(count), TORQUE_SMOOTHING),
            speed_scales: scaled(motors.speed_limit_rad_s.values(count), SPEED_SMOOTHING),
        })
    }

    /// Number of motors.
    pub fn motors(&self) -> usize {
        self.factors.len()
    }

    /// Motor i's loss at transmitted torque `t` (N m) and motor speed `w` (rad/s).
    pub fn at(&self, i: usize, t: f64, w: f64) -> MotorLoss {
        let (k, eps, omega) = (self.factors[i], self.torque_scales[i], self.speed_scales[i]);
        let s = (t * t + eps * eps).sqrt();
        let (ds, dds) = (t / s, eps * eps / (s * s * s));
        let sigma = (w / omega).tanh();
        let dsigma = (1.0 - sigma * sigma) / omega;
        let ddsigma = -2.0 * sigma * dsigma / omega;
        MotorLoss {
            value: k * s * sigma,
            t: k * ds * sigma,
            w: k * s * dsigma,
            tt: k * dds * sigma,
            tw: k * ds * dsigma,
            ww: k * s * ddsigma,
        }
    }
}

/// The losses at one node: each motor's [`MotorLoss`] at t = G^-T tau and w = G v, and what
/// they add to the dynamics rows.
#[derive(Clone, Debug)]
pub struct NodeLoss {
    motors: Vec<MotorLoss>,
    /// t = G^-T tau, the torques the transmissions pass, N m per motor.
    transmitted: DVector<f64>,
    /// G^T L, N m (row = joint).
    joint: DVector<f64>,
    /// G^T diag(dL/dt) G^-T, dimensionless: the rows' derivative through tau.
    torque_map: DMatrix<f64>,
    /// G^T diag(dL/dw) G, N m s/rad: the rows' derivative through v at fixed tau.
    damping: DMatrix<f64>,
}

impl NodeLoss {
    /// The losses of `loss` under `coupling` at joint torques `tau` (N m) and speeds `v` (rad/s).
    pub fn new(loss: &TransmissionLoss, coupling: &Coupling, tau: &[f64], v: &[f64]) -> NodeLoss {
        let (g, g_inv) = (coupling.matrix(), coupling.inverse());
        let t = g_inv.tr_mul(&DVector::from_column_slice(tau));
        let w = g * DVector::from_column_slice(v);
        let motors: Vec<MotorLoss> = (0..loss.motors()).map(|i| loss.at(i, t[i], w[i])).collect();
        let column =
            |of: fn(&MotorLoss) -> f64| DVector::from_iterator(motors.len(), motors.iter().map(of));
        let joint = g.tr_mul(&column(|m| m.value));
        let torque_map = g.tr_mul(&(DMatrix::from_diagonal(&column(|m| m.t)) * g_inv.transpose()));
        let damping = g.tr_mul(&(DMatrix::from_diagonal(&column(|m| m.w)) * g));
        NodeLoss {
            motors,
            transmitted: t,
            joint,
            torque_map,
            damping,
        }
    }

    /// Each motor's loss torque L_i, N m.
    pub fn motor_torques(&self) -> Vec<f64> {
        self.motors.iter().map(|m| m.value).collect()
    }

    /// Motor i's loss and its derivatives at this node.
    pub fn motor(&self, i: usize) -> &MotorLoss {
        &self.motors[i]
    }

    /// t = G^-T tau, the torques the transmissions pass, N m per motor.
    pub fn transmitted(&self) -> &DVector<f64> {
        &self.transmitted
    }

    /// G^T L, the losses' share of the joint torques, N m (row = joint).
    pub fn joint_torques(&self) -> &DVector<f64> {
        &self.joint
    }

    /// The rows' Jacobian blocks in (q, v, a) from the RNEA's (`dq`, `dv`, `mass`): G^T
    /// diag(dL/dt) G^-T times each, plus G^T diag(dL/dw) G in v.
    pub fn jacobian_blocks(
        &self,
        (dq, dv, mass): (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>),
    ) -> [DMatrix<f64>; 3] {
        let map = &self.torque_map;
        [map * dq, map * dv + &self.damping, map * mass]
    }

    /// The multipliers under which the RNEA's Hessian carries the rows' second derivatives
    /// through tau: lambda + G^-1 (mu o dL/dt), mu = G lambda the multipliers seen at the motors.
    pub fn rnea_multipliers(&self, coupling: &Coupling, lambda: &[f64]) -> Vec<f64> {
        let mu = coupling.matrix() * DVector::from_column_slice(lambda);
        let scaled = DVector::from_fn(mu.len(), |i, _| mu[i] * self.motors[i].t);
        let through = coupling.inverse() * scaled;
        lambda
            .iter()
            .zip(through.iter())
            .map(|(l, t)| l + t)
            .collect()
    }

    /// Adds the rest of lambda . the rows' Hessian in (q, v, a) to `block` (3n x 3n), with the
    /// RNEA's derivatives (`dq`, `dv`, `mass`): [`NodeLoss::add_second_order`] with T and W of a
    /// constant G ([`transmitted_derivatives`], [`speed_derivatives`]).
    pub fn add_hessian(
        &self,
        coupling: &Coupling,
        lambda: &[f64],
        rnea: (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>),
        block: &mut DMatrix<f64>,
    ) {
        let (t, w) = (
            transmitted_derivatives(coupling, rnea),
            speed_derivatives(coupling, None),
        );
        let mu = coupling.matrix() * DVector::from_column_slice(lambda);
        self.add_second_order(&mu, (&t, &w), block);
    }

    /// Adds sum_i mu_i (L_tt T_i^T T_i + L_tw (T_i^T W_i + W_i^T T_i) + L_ww W_i^T W_i) to
    /// `block` (3n x 3n): the losses' second derivatives in (t, w) under the multipliers `mu`
    /// seen at the motors, with T and W (n x 3n, row = motor) the derivatives of t and w in
    /// (q, v, a).
    pub fn add_second_order(
        &self,
        mu: &DVector<f64>,
        (t, w): (&DMatrix<f64>, &DMatrix<f64>),
        block: &mut DMatrix<f64>,
    ) {
        let n = mu.len();
        let weights = |of: fn(&MotorLoss) -> f64| {
            DMatrix::from_diagonal(&DVector::from_fn(n, |i, _| mu[i] * of(&self.motors[i])))
        };
        let cross = t.tr_mul(&(weights(|m| m.tw) * w));
        *block += t.tr_mul(&(weights(|m| m.tt) * t))
            + &cross
            + cross.transpose()
            + w.tr_mul(&(weights(|m| m.ww) * w));
    }

    /// d/dr_l of the rows' term G^T L at fixed (tau, v), for `dg` = dG/dr_l and `dg_inv` =
    /// d(G^-1)/dr_l: dG_l^T L + G^T (dL/dt o (dG_l^-1)^T tau + dL/dw o dG_l v), N m.
    pub fn design_derivative(
        &self,
        coupling: &Coupling,
        (dg, dg_inv): (&DMatrix<f64>, &DMatrix<f64>),
        tau: &[f64],
        v: &[f64],
    ) -> DVector<f64> {
        let dt = dg_inv.tr_mul(&DVector::from_column_slice(tau));
        let dw = dg * DVector::from_column_slice(v);
        let value = DVector::from_iterator(self.motors.len(), self.motors.iter().map(|m| m.value));
        let inner = DVector::from_fn(self.motors.len(), |i, _| {
            self.motors[i].t * dt[i] + self.motors[i].w * dw[i]
        });
        dg.tr_mul(&value) + coupling.matrix().tr_mul(&inner)
    }
}

/// T = G^-T [dq dv mass], the derivatives of the transmitted torques t = G^-T tau in (q, v, a)
/// from tau's (`dq`, `dv`, `mass`, n x n each), n x 3n (row = motor).
pub fn transmitted_derivatives(
    coupling: &Coupling,
    (dq, dv, mass): (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>),
) -> DMatrix<f64> {
    let n = dq.nrows();
    let mut derivatives = DMatrix::zeros(n, 3 * n);
    derivatives.columns_mut(0, n).copy_from(dq);
    derivatives.columns_mut(n, n).copy_from(dv);
    derivatives.columns_mut(2 * n, n).copy_from(mass);
    coupling.inverse().tr_mul(&derivatives)
}

/// W = [by_q G 0], the derivatives of the motor speeds w = G v in (q, v, a), n x 3n (row =
/// motor): `by_q` = d(G v)/dq where G depends on the pose, zero without.
pub fn speed_derivatives(coupling: &Coupling, by_q: Option<&DMatrix<f64>>) -> DMatrix<f64> {
    let g = coupling.matrix();
    let n = g.nrows();
    let mut w = DMatrix::zeros(n, 3 * n);
    if let Some(by_q) = by_q {
        w.columns_mut(0, n).copy_from(by_q);
    }
    w.columns_mut(n, n).copy_from(g);
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::PerMotor;
    use crate::transmission::fixtures::belt_arm;

    fn loss() -> TransmissionLoss {
        let mut motors = Motors::ideal(
            PerMotor::All(1.7),
            PerMotor::Each(vec![100.0, 80.0, 60.0, 50.0]),
        );
        motors.efficiency = Some(PerMotor::Each(vec![0.95, 0.9, 0.8, 0.97]));
        TransmissionLoss::of(&motors, 4).unwrap()
    }

    /// Each motor's derivatives against central differences, near the kinks that the smoothing
    /// rounds and away from them.
    #[test]
    fn motor_loss_derivatives_match_finite_differences() {
        let loss = loss();
        let h = 1e-6;
        for (t, w) in [
            (0.3, 2.0),
            (-0.01, 0.4),
            (1.2, -0.7),
            (0.0, 0.0),
            (-2.0, 30.0),
        ] {
            for i in 0..4 {
                let at = |t: f64, w: f64| loss.at(i, t, w);
                let exact = at(t, w);
                let (tp, tm, wp, wm) = (at(t + h, w), at(t - h, w), at(t, w + h), at(t, w - h));
                let close = |fd: f64, value: f64, what: &str| {
                    assert!(
                        (fd - value).abs() < 1e-6 * (1.0 + fd.abs()),
                        "{what} at {t}, {w}: {value} vs {fd}"
                    );
                };
                close((tp.value - tm.value) / (2.0 * h), exact.t, "dL/dt");
                close((wp.value - wm.value) / (2.0 * h), exact.w, "dL/dw");
                close((tp.t - tm.t) / (2.0 * h), exact.tt, "d2L/dt2");
                close((wp.t - wm.t) / (2.0 * h), exact.tw, "d2L/dtdw");
                close((wp.w - wm.w) / (2.0 * h), exact.ww, "d2L/dw2");
            }
        }
    }

    /// Far from the smoothing's scales a motor driving its load gives t / eta, one braking it
    /// t (2 - 1/eta); at rest there is no loss at all.
    #[test]
    fn the_loss_is_the_efficiency_when_driving() {
        let loss = loss();
        let eta = 0.9;
        let (t, w) = (1.5, 50.0);
        let driving = t + loss.at(1, t, w).value;
        assert!((driving - t / eta).abs() < 1e-4 * t, "{driving}");
        let braking = -t + loss.at(1, -t, w).value;
        assert!(
            (braking + t * (2.0 - 1.0 / eta)).abs() < 1e-4 * t,
            "{braking}"
        );
        assert_eq!(loss.at(1, t, 0.0).value, 0.0);
    }

    /// The rows' term's r-derivative against central differences of the coupling.
    #[test]
    fn design_derivative_matches_finite_differences() {
        let (t, loss) = (belt_arm(), loss());
        let r = [7.3, 4.4, 2.1, 1.7];
        let (tau, v) = ([0.3, -1.2, 0.7, 1.5], [0.5, -2.0, 1.5, 3.0]);
        let h = 1e-6;
        let coupling = t.coupling(&r).unwrap();
        let node = NodeLoss::new(&loss, &coupling, &tau, &v);
        for l in 0..t.num_ratios() {
            let (mut plus, mut minus) = (r, r);
            plus[l] += h;
            minus[l] -= h;
            let at = |r: &[f64]| NodeLoss::new(&loss, &t.coupling(r).unwrap(), &tau, &v).joint;
            let fd = (at(&plus) - at(&minus)) / (2.0 * h);
            let dg = t.matrix_derivative(l);
            let dg_inv = -(coupling.inverse() * &dg * coupling.inverse());
            let exact = node.design_derivative(&coupling, (&dg, &dg_inv), &tau, &v);
            assert!((&fd - &exact).amax() < 1e-7, "r{l}: {exact} vs {fd}");
        }
    }
}
