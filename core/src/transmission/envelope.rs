//! The motors' linear torque-speed envelope (docs/model.md, section 5): motor i gives at most
//!
//!   |tau_u,i| <= tau_max,i (1 - |w_i| / w_0,i)
//!
//! at motor speed w_i = (G qd)_i, tau_max,i its torque limit and w_0,i its no-load speed (the
//! task's `motors.no_load_speed_rad_s`). As a smooth model this is the pair of linear rows
//!
//!   P_i = tau_u,i + c_i w_i  and  M_i = tau_u,i - c_i w_i,  each in [-tau_max,i, tau_max,i],
//!
//! with slope c_i = tau_max,i / w_0,i (N m s/rad): P bounds the quadrants where torque and speed
//! share their sign, M the others, and together they hold max(|P_i|, |M_i|) = |tau_u,i| +
//! c_i |w_i| <= tau_max,i, the envelope itself. At rest (w = 0) both reduce to the torque limit.

use crate::model::task::Motors;

/// Which of a motor's two envelope rows: tau_u + c w or tau_u - c w.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// P = tau_u + c w.
    Plus,
    /// M = tau_u - c w.
    Minus,
}

impl Side {
    /// Both rows, in the order a node holds them.
    pub const BOTH: [Side; 2] = [Side::Plus, Side::Minus];

    /// The sign of the speed term: +1 or -1.
    pub fn sign(self) -> f64 {
        match self {
            Side::Plus => 1.0,
            Side::Minus => -1.0,
        }
    }
}

/// The torque-speed envelope of every motor (motor i = row i of G).
#[derive(Clone, Debug, PartialEq)]
pub struct Envelope {
    /// tau_max,i, N m.
    torque_limits: Vec<f64>,
    /// c_i = tau_max,i / w_0,i, N m s/rad.
    slopes: Vec<f64>,
    /// w_0,i, rad/s.
    no_load_speeds: Vec<f64>,
}

impl Envelope {
    /// The envelope the task's `motors` give `count` motors (checked by [`Motors::validate`]),
    /// None without `no_load_speed_rad_s`.
    pub fn of(motors: &Motors, count: usize) -> Option<Envelope> {
        let no_load = motors.no_load_speed_rad_s.as_ref()?.values(count);
        let torque_limits = motors.torque_limit_nm.values(count);
        let slopes = torque_limits
            .iter()
            .zip(&no_load)
            .map(|(tau, w0)| tau / w0)
            .collect();
        Some(Envelope {
            torque_limits,
            slopes,
            no_load_speeds: no_load,
        })
    }

    /// Number of motors.
    pub fn motors(&self) -> usize {
        self.slopes.len()
    }

    /// Motor i's slope c_i = tau_max,i / w_0,i, N m s/rad.
    pub fn slope(&self, motor: usize) -> f64 {
        self.slopes[motor]
    }

    /// Motor i's torque limit tau_max,i, N m: both rows lie in [-tau_max,i, tau_max,i].
    pub fn torque_limit(&self, motor: usize) -> f64 {
        self.torque_limits[motor]
    }

    /// Motor i's no-load speed w_0,i, rad/s: the speed at which it has no torque left.
    pub fn no_load_speed(&self, motor: usize) -> f64 {
        self.no_load_speeds[motor]
    }

    /// Row `side` of motor i at motor torque `torque` (N m) and motor speed `speed` (rad/s):
    /// torque +- c_i speed, N m.
    pub fn row(&self, motor: usize, side: Side, torque: f64, speed: f64) -> f64 {
        torque + side.sign() * self.slopes[motor] * speed
    }

    /// How far motor i at `torque` and `speed` lies inside its envelope, N m:
    /// tau_max,i - |torque| - c_i |speed|, negative by what the larger of its rows exceeds.
    pub fn margin(&self, motor: usize, torque: f64, speed: f64) -> f64 {
        self.torque_limits[motor] - torque.abs() - self.slopes[motor] * speed.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::PerMotor;

    #[test]
    fn only_a_task_with_no_load_speeds_has_an_envelope() {
        let mut motors = Motors::ideal(PerMotor::Each(vec![1.7, 1.0]), PerMotor::All(100.0));
        assert_eq!(Envelope::of(&motors, 2), None);
        motors.no_load_speed_rad_s = Some(PerMotor::All(50.0));
        let envelope = Envelope::of(&motors, 2).unwrap();
        assert_eq!(envelope.motors(), 2);
        assert_eq!((envelope.slope(0), envelope.slope(1)), (1.7 / 50.0, 0.02));
        assert_eq!(envelope.torque_limit(1), 1.0);
        assert_eq!(envelope.no_load_speed(0), 50.0);
    }

    /// The rows' larger magnitude is |tau| + c |w| in every quadrant, so both rows in
    /// [-tau_max, tau_max] is the envelope, and the margin is tau_max less it.
    #[test]
    fn the_two_rows_hold_the_envelope_in_every_quadrant() {
        let mut motors = Motors::ideal(PerMotor::All(2.0), PerMotor::All(100.0));
        motors.no_load_speed_rad_s = Some(PerMotor::All(40.0));
        let envelope = Envelope::of(&motors, 1).unwrap();
        for (torque, speed) in [(0.5, 10.0), (-0.5, 10.0), (0.5, -10.0), (-0.5, -10.0)] {
            let rows = Side::BOTH.map(|side| envelope.row(0, side, torque, speed));
            let largest = rows[0].abs().max(rows[1].abs());
            assert!((largest - 1.0).abs() < 1e-15, "{rows:?}");
            assert!((envelope.margin(0, torque, speed) - (2.0 - largest)).abs() < 1e-15);
            // At the envelope's edge (here 1 N m at 20 rad/s) the margin is 0.
            assert!(envelope.margin(0, 2.0 * torque, 2.0 * speed).abs() < 1e-15);
        }
        assert_eq!(envelope.row(0, Side::Minus, 1.0, 0.0), 1.0);
    }
}
