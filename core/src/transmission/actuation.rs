//! The actuation at one design (docs/model.md, section 3): after Crocoddyl's actuation models,
//! the motor torques tau_u(q, v, a, tau; r) the motion asks for, and the map from the controls u
//! to them, with their derivatives with respect to the state, the torques, the controls and r.
//!
//! A motor with rotor inertia J_m and viscous friction b_m (per motor, [`MotorDynamics`]) turns
//! at the motor speed G v and gives
//!
//!   tau_u = G^-T tau + J_m G a + B_m G v,
//!
//! tau the joint torque the links take (the inverse dynamics RNEA(q, v, a)), J_m and B_m the
//! diagonal matrices of the motors' values. Ideal motors (no [`MotorDynamics`]) give
//! tau_u = G^-T tau. The controls are the motor torques, u = tau_u ([`Space::Actuation`]), or
//! their image in the joints, u = G^T tau_u ([`Space::Joint`]), so that the joint-space limit
//! modes bound G^-T u = tau_u as before. The trajectory problem's dynamics rows are
//! G^T (tau_u(q, v, a, RNEA) - tau_u(u)) = 0:
//!
//!   RNEA(q, v, a) + G^T J_m G a + G^T B_m G v - C u = 0,   C = G^T or the identity,
//!
//! linear in (v, a, u) for a fixed design: the motors reflect the inertia G^T J_m G and the
//! damping G^T B_m G into the joints, and add no second derivatives in x. Transmissions with an
//! efficiency ([`TransmissionLoss`]) add their loss torque L to tau_u, and G^T L to the rows,
//! evaluated per node as a [`NodeLoss`].

use super::loss::{NodeLoss, TransmissionLoss};
use super::Coupling;
use crate::choice::Choice;
use crate::model::task::{Motors, PerMotor};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Which torques the controls are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Space {
    /// Joint torques tau are the controls; actuator limits are mapped to joint space (baseline).
    Joint,
    /// Motor torques tau_u are the controls, tau = G^T tau_u (the paper's method).
    Actuation,
}

impl Choice for Space {
    const ALL: &'static [Space] = &[Space::Joint, Space::Actuation];

    fn name(self) -> &'static str {
        Space::name(self)
    }
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

/// The motors' own dynamics, one value per motor (row of G).
#[derive(Clone, Debug, PartialEq)]
pub struct MotorDynamics {
    /// Rotor and input-side inertia J_m of each motor, kg m^2.
    pub rotor_inertia: Vec<f64>,
    /// Viscous friction b_m of each motor, N m s/rad.
    pub viscous_friction: Vec<f64>,
}

impl MotorDynamics {
    /// The dynamics the task's `motors` give `count` motors (checked by [`Motors::validate`]):
    /// None when neither `rotor_inertia_kgm2` nor `viscous_friction_nm_s_per_rad` is given
    /// (ideal motors); a quantity not given is 0.
    pub fn of(motors: &Motors, count: usize) -> Option<MotorDynamics> {
        let (inertia, friction) = (
            &motors.rotor_inertia_kgm2,
            &motors.viscous_friction_nm_s_per_rad,
        );
        if inertia.is_none() && friction.is_none() {
            return None;
        }
        let values = |quantity: &Option<PerMotor>| match quantity {
            Some(per_motor) => per_motor.values(count),
            None => vec![0.0; count],
        };
        Some(MotorDynamics {
            rotor_inertia: values(inertia),
            viscous_friction: values(friction),
        })
    }
}

/// The motors' dynamics at one design, reflected into the joints.
#[derive(Clone, Debug)]
struct Reflected {
    /// J_m and B_m, diagonal, kg m^2 and N m s/rad (row = motor).
    rotor: DMatrix<f64>,
    friction: DMatrix<f64>,
    /// G^T J_m G, kg m^2 (row = joint).
    inertia: DMatrix<f64>,
    /// G^T B_m G, N m s/rad (row = joint).
    damping: DMatrix<f64>,
}

/// The actuation of one design: G(r) with its inverse, the space of the controls and the
/// motors' dynamics.
#[derive(Clone, Debug)]
pub struct Actuation {
    space: Space,
    coupling: Coupling,
    /// C = d(joint torque)/du: G^T in actuation space, the identity in joint space.
    control_map: DMatrix<f64>,
    /// G^-T, the motor torques of joint torques.
    motor_of_joint: DMatrix<f64>,
    /// d(tau_u)/du: the identity in actuation space, G^-T in joint space.
    motor_of_control: DMatrix<f64>,
    /// None for ideal motors.
    reflected: Option<Reflected>,
    /// None for lossless transmissions.
    loss: Option<TransmissionLoss>,
}

impl Actuation {
    /// The actuation of `coupling` (G at one design) with controls in `space` and motors of
    /// dynamics `motors` (None: ideal).
    pub fn new(coupling: Coupling, space: Space, motors: Option<&MotorDynamics>) -> Actuation {
        let n = coupling.matrix().nrows();
        let control_map = match space {
            Space::Actuation => coupling.matrix().transpose(),
            Space::Joint => DMatrix::identity(n, n),
        };
        let motor_of_joint = coupling.inverse().transpose();
        let motor_of_control = match space {
            Space::Actuation => DMatrix::identity(n, n),
            Space::Joint => motor_of_joint.clone(),
        };
        let reflected = motors.map(|motors| {
            let diagonal =
                |values: &[f64]| DMatrix::from_diagonal(&DVector::from_column_slice(values));
            let (rotor, friction) = (
                diagonal(&motors.rotor_inertia),
                diagonal(&motors.viscous_friction),
            );
            let g = coupling.matrix();
            Reflected {
                inertia: g.tr_mul(&(&rotor * g)),
                damping: g.tr_mul(&(&friction * g)),
                rotor,
                friction,
            }
        });
        Actuation {
            space,
            coupling,
            control_map,
            motor_of_joint,
            motor_of_control,
            reflected,
            loss: None,
        }
    }

    /// The same actuation with transmissions of losses `loss` (None: lossless).
    pub fn with_loss(mut self, loss: Option<&TransmissionLoss>) -> Actuation {
        self.loss = loss.cloned();
        self
    }

    /// The transmissions' losses, None where they are lossless.
    pub fn loss(&self) -> Option<&TransmissionLoss> {
        self.loss.as_ref()
    }

    /// The losses at a node whose links take the joint torques `tau` (N m) at speeds `v`
    /// (rad/s), None for lossless transmissions.
    pub fn node_loss(&self, tau: &[f64], v: &[f64]) -> Option<NodeLoss> {
        (self.loss.as_ref()).map(|loss| NodeLoss::new(loss, &self.coupling, tau, v))
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

    /// d(tau_u)/du = d(motor torque)/d(control) (row = motor, column = control): the identity
    /// in actuation space, G^-T in joint space.
    pub fn motor_of_control(&self) -> &DMatrix<f64> {
        &self.motor_of_control
    }

    /// d/dr_l of the motor torques tau_u(u) of control u at fixed u, for `dg` = dG/dr_l: 0 in
    /// actuation space (None), d(G^-T)/dr_l u = -G^-T dG_l^T G^-T u in joint space.
    pub fn motor_torque_derivative(&self, dg: &DMatrix<f64>, u: &[f64]) -> Option<DVector<f64>> {
        match self.space {
            Space::Actuation => None,
            Space::Joint => {
                let dg_inv = self.inverse_derivative(dg);
                Some(dg_inv.tr_mul(&DVector::from_column_slice(u)))
            }
        }
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

    /// G^T J_m G and G^T B_m G, the rotor inertia (kg m^2) and the friction (N m s/rad)
    /// reflected into the joints, or None for ideal motors.
    pub fn reflected(&self) -> Option<(&DMatrix<f64>, &DMatrix<f64>)> {
        self.reflected
            .as_ref()
            .map(|reflected| (&reflected.inertia, &reflected.damping))
    }

    /// Joint torques the links take at a node of speeds v (rad/s) and accelerations a
    /// (rad/s^2) under control u, with the transmissions' losses `loss` there (None where
    /// lossless): C u - G^T J_m G a - G^T B_m G v - G^T L, N m (C u for ideal motors and
    /// lossless transmissions).
    pub fn link_torques(
        &self,
        (v, a): (&[f64], &[f64]),
        u: &[f64],
        loss: Option<&NodeLoss>,
    ) -> Vec<f64> {
        let mut links = self.joint_torques(u);
        if let Some(reflected) = &self.reflected {
            let (v, a) = (DVector::from_column_slice(v), DVector::from_column_slice(a));
            let motors = &reflected.inertia * a + &reflected.damping * v;
            links
                .iter_mut()
                .zip(motors.iter())
                .for_each(|(t, m)| *t -= m);
        }
        if let Some(loss) = loss {
            (links.iter_mut())
                .zip(loss.joint_torques().iter())
                .for_each(|(t, l)| *t -= l);
        }
        links
    }

    /// The dynamics residual of joint i at a node, tau_i + (G^T J_m G a + G^T B_m G v)_i minus
    /// (C u)_i, with tau the inverse dynamics' torques (N m), v and a the joint speeds and
    /// accelerations and u the controls.
    pub fn residual(&self, i: usize, tau: &[f64], (v, a): (&[f64], &[f64]), u: &[f64]) -> f64 {
        let applied: f64 = (0..u.len()).map(|j| self.control_map[(i, j)] * u[j]).sum();
        match &self.reflected {
            None => tau[i] - applied,
            Some(reflected) => {
                let motors: f64 = (0..v.len())
                    .map(|j| reflected.inertia[(i, j)] * a[j] + reflected.damping[(i, j)] * v[j])
                    .sum();
                tau[i] + motors - applied
            }
        }
    }

    /// d(G^-1)/dr_l = -G^-1 dG_l G^-1 for `dg` = dG/dr_l.
    pub fn inverse_derivative(&self, dg: &DMatrix<f64>) -> DMatrix<f64> {
        let g_inv = self.coupling.inverse();
        -(g_inv * dg * g_inv)
    }

    /// d/dr_l of the dynamics residuals (one per joint) at fixed (q, v, a, u), for `dg` =
    /// dG/dr_l. With m = J_m G a + B_m G v, the motors' own torque:
    /// dG_l^T (m - u) + G^T (J_m dG_l a + B_m dG_l v) in actuation space, the same without
    /// u in joint space; for ideal motors -dG_l^T u and None (no dependence on r).
    pub fn residual_derivative(
        &self,
        dg: &DMatrix<f64>,
        (v, a): (&[f64], &[f64]),
        u: &[f64],
    ) -> Option<DVector<f64>> {
        let u = DVector::from_column_slice(u);
        let Some(reflected) = &self.reflected else {
            return match self.space {
                Space::Actuation => Some(-dg.tr_mul(&u)),
                Space::Joint => None,
            };
        };
        let (v, a) = (DVector::from_column_slice(v), DVector::from_column_slice(a));
        let (rotor, friction) = (&reflected.rotor, &reflected.friction);
        let g = self.coupling.matrix();
        let mut own = rotor * (g * &a) + friction * (g * &v);
        if self.space == Space::Actuation {
            own -= u;
        }
        let own_derivative = rotor * (dg * &a) + friction * (dg * &v);
        Some(dg.tr_mul(&own) + g.tr_mul(&own_derivative))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transmission::fixtures::belt_arm;

    /// The residual's and the motor torques' r-derivatives against central differences, both
    /// spaces.
    #[test]
    fn residual_derivative_matches_finite_differences() {
        let t = belt_arm();
        let r = [7.3, 4.4, 2.1, 1.7];
        let (tau, u) = ([0.3, -1.2, 0.7, 1.5], [0.4, 0.9, -0.6, 0.2]);
        let state = ([0.5, -2.0, 1.5, 3.0], [4.0, -1.0, 7.0, -3.0]);
        let state = (&state.0[..], &state.1[..]);
        let h = 1e-6;
        for (space, motors) in spaces_and_motors() {
            for l in 0..t.num_ratios() {
                let (mut plus, mut minus) = (r, r);
                plus[l] += h;
                minus[l] -= h;
                let at = |r: &[f64]| Actuation::new(t.coupling(r).unwrap(), space, motors.as_ref());
                let (p, m) = (at(&plus), at(&minus));
                let dg = t.matrix_derivative(l);
                let exact = at(&r).residual_derivative(&dg, state, &u);
                let torque = at(&r).motor_torque_derivative(&dg, &u);
                let (tp, tm) = (p.motor_torques(&u), m.motor_torques(&u));
                for i in 0..4 {
                    let fd = (tp[i] - tm[i]) / (2.0 * h);
                    let value = torque.as_ref().map_or(0.0, |d| d[i]);
                    assert!((fd - value).abs() < 1e-7, "{space} r{l} motor torque {i}");
                }
                for i in 0..4 {
                    let fd = (p.residual(i, &tau, state, &u) - m.residual(i, &tau, state, &u))
                        / (2.0 * h);
                    let value = exact.as_ref().map_or(0.0, |d| d[i]);
                    assert!(
                        (fd - value).abs() < 1e-7,
                        "{space} {motors:?} r{l} joint {i}"
                    );
                }
            }
        }
    }

    /// Both spaces with ideal motors and with rotor inertia and friction set per motor.
    fn spaces_and_motors() -> Vec<(Space, Option<MotorDynamics>)> {
        let motors = MotorDynamics {
            rotor_inertia: vec![2e-4, 1e-4, 5e-5, 0.0],
            viscous_friction: vec![1e-3, 0.0, 2e-3, 5e-4],
        };
        [Space::Actuation, Space::Joint]
            .into_iter()
            .flat_map(|space| [(space, None), (space, Some(motors.clone()))])
            .collect()
    }

    #[test]
    fn controls_map_to_joint_and_motor_torques() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let u = [0.3, -1.2, 0.7, 1.5];
        let actuation = Actuation::new(coupling.clone(), Space::Actuation, None);
        assert_eq!(actuation.joint_torques(&u), coupling.joint_torques(&u));
        assert_eq!(actuation.motor_torques(&u), u);
        assert_eq!(
            actuation.motor_of_control(),
            &DMatrix::<f64>::identity(4, 4)
        );
        let joint = Actuation::new(coupling.clone(), Space::Joint, None);
        assert_eq!(joint.joint_torques(&u), u);
        assert_eq!(joint.motor_of_control(), joint.motor_of_joint());
        let back = joint.motor_torques(&u);
        let expected = coupling.motor_torques(&u);
        assert!(back
            .iter()
            .zip(&expected)
            .all(|(a, b)| (a - b).abs() < 1e-14));
    }

    /// With motor dynamics the links take what the motors give less what turns the rotors and
    /// overcomes the friction: at the links' torques the residual vanishes, and the motor
    /// torque of a control is tau_u = G^-T tau + J_m G a + B_m G v in both spaces.
    #[test]
    fn links_take_the_motor_torque_less_the_rotors_and_the_friction() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let (v, a) = ([0.5, -2.0, 1.5, 3.0], [4.0, -1.0, 7.0, -3.0]);
        let tau_u = [0.3, -1.2, 0.7, 1.5];
        for (space, motors) in spaces_and_motors() {
            let actuation = Actuation::new(coupling.clone(), space, motors.as_ref());
            let u = match space {
                Space::Actuation => tau_u.to_vec(),
                Space::Joint => coupling.joint_torques(&tau_u),
            };
            let links = actuation.link_torques((&v, &a), &u, None);
            for i in 0..4 {
                let residual = actuation.residual(i, &links, (&v, &a), &u);
                assert!(residual.abs() < 1e-12, "{space} {motors:?} joint {i}");
            }
            let g = coupling.matrix();
            let own = motors.as_ref().map_or(DVector::zeros(4), |m| {
                let (speed, acceleration) = (
                    g * DVector::from_row_slice(&v),
                    g * DVector::from_row_slice(&a),
                );
                DVector::from_fn(4, |i, _| {
                    m.rotor_inertia[i] * acceleration[i] + m.viscous_friction[i] * speed[i]
                })
            });
            let motor = DVector::from_vec(coupling.motor_torques(&links)) + own;
            let given = actuation.motor_torques(&u);
            assert!(
                (0..4).all(|i| (motor[i] - given[i]).abs() < 1e-12),
                "{space}"
            );
        }
    }

    #[test]
    fn motor_dynamics_come_from_the_task_when_given() {
        let mut motors = Motors::ideal(PerMotor::All(1.7), PerMotor::All(100.0));
        assert_eq!(MotorDynamics::of(&motors, 4), None);
        motors.rotor_inertia_kgm2 = Some(PerMotor::Each(vec![1e-4, 2e-4, 3e-4, 4e-4]));
        assert_eq!(
            MotorDynamics::of(&motors, 4),
            Some(MotorDynamics {
                rotor_inertia: vec![1e-4, 2e-4, 3e-4, 4e-4],
                viscous_friction: vec![0.0; 4],
            })
        );
        motors.rotor_inertia_kgm2 = None;
        motors.viscous_friction_nm_s_per_rad = Some(PerMotor::All(1e-3));
        let friction_only = MotorDynamics::of(&motors, 2).unwrap();
        assert_eq!(friction_only.rotor_inertia, vec![0.0; 2]);
        assert_eq!(friction_only.viscous_friction, vec![1e-3; 2]);
    }
}
