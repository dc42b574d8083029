//! The actuation at one design (docs/model.md, section 3): after Crocoddyl's actuation models,
//! the map from the controls u to the torques the joints receive, with its derivatives with
//! respect to the controls and to the ratios r.
//!
//! The controls are the motor torques, u = tau_u ([`Space::Actuation`]), or their image in the
//! joints, u = G^T tau_u ([`Space::Joint`]); either way the joints receive tau = C u with
//! C = G^T or the identity, and the motors give tau_u = u or G^-T u. The trajectory problem's
//! dynamics rows are tau(q, v, a) - C u = 0 with tau(q, v, a) the inverse dynamics (RNEA).

use super::Coupling;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Which torques the controls are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Space {
    /// Joint torques tau are the controls; actuator limits are mapped to joint space (baseline).
    Joint,
    /// Motor torques tau_u are the controls, tau = G^T tau_u (the paper's method).
    Actuation,
}

impl Space {
    /// The lower-case name used in files and flags.
    pub fn name(self) -> &'static str {
        match self {
            Space::Joint => "joint",
            Space::Actuation => "actuation",
        }
    }
}

impl fmt::Display for Space {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The actuation of one design: G(r) with its inverse, and the space of the controls.
#[derive(Clone, Debug)]
pub struct Actuation {
    space: Space,
    coupling: Coupling,
    /// C = d(joint torque)/du: G^T in actuation space, the identity in joint space.
    control_map: DMatrix<f64>,
    /// G^-T, the motor torques of joint torques.
    motor_of_joint: DMatrix<f64>,
}

impl Actuation {
    /// The actuation of `coupling` (G at one design) with controls in `space`.
    pub fn new(coupling: Coupling, space: Space) -> Actuation {
        let n = coupling.matrix().nrows();
        let control_map = match space {
            Space::Actuation => coupling.matrix().transpose(),
            Space::Joint => DMatrix::identity(n, n),
        };
        let motor_of_joint = coupling.inverse().transpose();
        Actuation {
            space,
            coupling,
            control_map,
            motor_of_joint,
        }
    }

    /// Joint or actuation space.
    pub fn space(&self) -> Space {
        self.space
    }

    /// G(r) and its inverse.
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// C = d(joint torque)/du (row = joint, column = control): G^T or the identity.
    pub fn control_map(&self) -> &DMatrix<f64> {
        &self.control_map
    }

    /// G^-T = d(tau_u)/d(tau) (row = motor, column = joint).
    pub fn motor_of_joint(&self) -> &DMatrix<f64> {
        &self.motor_of_joint
    }

    /// Joint torques C u of control u at a node, N m.
    ///
    /// # Panics
    /// If u does not have one value per motor.
    pub fn joint_torques(&self, u: &[f64]) -> Vec<f64> {
        (&self.control_map * DVector::from_column_slice(u))
            .iter()
            .copied()
            .collect()
    }

    /// Motor torques tau_u of control u at a node: u (actuation space) or G^-T u (joint
    /// space), N m.
    ///
    /// # Panics
    /// If u does not have one value per joint.
    pub fn motor_torques(&self, u: &[f64]) -> Vec<f64> {
        match self.space {
            Space::Actuation => u.to_vec(),
            Space::Joint => (&self.motor_of_joint * DVector::from_column_slice(u))
                .iter()
                .copied()
                .collect(),
        }
    }

    /// The dynamics residual of joint i at a node: tau_i - (C u)_i, with tau the inverse
    /// dynamics' torques (N m) and u the controls.
    pub fn residual(&self, i: usize, tau: &[f64], u: &[f64]) -> f64 {
        let applied: f64 = (0..u.len()).map(|j| self.control_map[(i, j)] * u[j]).sum();
        tau[i] - applied
    }

    /// d(G^-1)/dr_l = -G^-1 dG_l G^-1 for `dg` = dG/dr_l.
    pub fn inverse_derivative(&self, dg: &DMatrix<f64>) -> DMatrix<f64> {
        let g_inv = self.coupling.inverse();
        -(g_inv * dg * g_inv)
    }

    /// d/dr_l of the dynamics residuals (one per joint) at fixed (q, v, a, u), for `dg` =
    /// dG/dr_l: -dG_l^T u in actuation space; None in joint space, where they do not
    /// depend on r.
    pub fn residual_derivative(&self, dg: &DMatrix<f64>, u: &[f64]) -> Option<DVector<f64>> {
        match self.space {
            Space::Actuation => Some(-dg.tr_mul(&DVector::from_column_slice(u))),
            Space::Joint => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transmission::fixtures::belt_arm;

    /// The residual's r-derivative against central differences of the residual, both spaces.
    #[test]
    fn residual_derivative_matches_finite_differences() {
        let t = belt_arm();
        let r = [7.3, 4.4, 2.1, 1.7];
        let (tau, u) = ([0.3, -1.2, 0.7, 1.5], [0.4, 0.9, -0.6, 0.2]);
        let h = 1e-6;
        for space in [Space::Actuation, Space::Joint] {
            for l in 0..t.num_ratios() {
                let (mut plus, mut minus) = (r, r);
                plus[l] += h;
                minus[l] -= h;
                let at = |r: &[f64]| Actuation::new(t.coupling(r).unwrap(), space);
                let (p, m) = (at(&plus), at(&minus));
                let exact = at(&r).residual_derivative(&t.matrix_derivative(l), &u);
                for i in 0..4 {
                    let fd = (p.residual(i, &tau, &u) - m.residual(i, &tau, &u)) / (2.0 * h);
                    let value = exact.as_ref().map_or(0.0, |d| d[i]);
                    assert!((fd - value).abs() < 1e-8, "{space} r{l} joint {i}");
                }
            }
        }
    }

    #[test]
    fn controls_map_to_joint_and_motor_torques() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let u = [0.3, -1.2, 0.7, 1.5];
        let actuation = Actuation::new(coupling.clone(), Space::Actuation);
        assert_eq!(actuation.joint_torques(&u), coupling.joint_torques(&u));
        assert_eq!(actuation.motor_torques(&u), u);
        let joint = Actuation::new(coupling.clone(), Space::Joint);
        assert_eq!(joint.joint_torques(&u), u);
        assert_eq!(joint.motor_torques(&u), coupling.motor_torques(&u));
    }
}
