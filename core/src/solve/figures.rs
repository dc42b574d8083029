//! Physical figures of a trajectory, per motor and in total: what a designer judges a gear ratio
//! by, beside the weighted sum J (docs/model.md, section 16).
//!
//! The motor torques are constant over each interval k (the controls), and the joint speeds
//! change linearly in it (the acceleration is constant), so each motor's speed w and power
//! p = tau w are linear between the nodes k and k + 1. Every integral below is therefore exact on
//! the discretised trajectory: int tau^2 dt = sum h tau_k^2, the work int p dt = sum h (p_k^- +
//! p_k^+) / 2, with p_k^- = tau_k w_k and p_k^+ = tau_k w_{k+1}, and the peaks of |p| lie at the
//! nodes. The transmissions' loss torques are constant over each interval too, so their energy
//! is exact as the work is.

use super::trajectory::Trajectory;
use serde::{Deserialize, Serialize};

/// One motor's figures along a trajectory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotorFigures {
    /// int tau_u^2 dt, N^2 m^2 s: the control effort J's control term counts per node.
    pub torque_squared_integral: f64,
    /// Root mean square torque over the motion, N m: sqrt(int tau_u^2 dt / T), what heats a
    /// motor's windings.
    pub rms_torque_nm: f64,
    /// Peak |torque|, N m.
    pub peak_torque_nm: f64,
    /// Peak |speed|, rad/s.
    pub peak_speed_rad_s: f64,
    /// Peak |mechanical power| tau_u w, W.
    pub peak_power_w: f64,
    /// Net mechanical work int tau_u w dt, J (negative: the motor brakes more than it drives).
    pub work_j: f64,
    /// Work delivered while driving, int max(tau_u w, 0) dt, J: the energy a motor supplies
    /// when braking recovers nothing.
    pub positive_work_j: f64,
    /// Currents, copper losses and electrical energy, where the task gives the motor's torque
    /// constant and winding resistance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub electrical: Option<ElectricalFigures>,
    /// Energy lost in the transmission, int L w dt with L its loss torque, J: a share of
    /// `work_j`, where the task gives an efficiency (`motors.efficiency`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmission_loss_j: Option<f64>,
}

/// One motor's electrical figures, from its torque constant k_t (N m/A) and winding resistance
/// R (ohm): current i = tau_u / k_t, copper losses R i^2, electrical power tau_u w + R i^2.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ElectricalFigures {
    /// Root mean square current over the motion, A.
    pub rms_current_a: f64,
    /// Peak |current|, A.
    pub peak_current_a: f64,
    /// Copper losses int R i^2 dt, J: R / k_t^2 times int tau_u^2 dt.
    pub copper_loss_j: f64,
    /// Net electrical energy int (tau_u w + R i^2) dt, J: the mechanical work plus the copper
    /// losses, braking energy returned to the supply.
    pub energy_j: f64,
    /// Electrical energy drawn, int max(tau_u w + R i^2, 0) dt, J: what the supply gives when
    /// braking returns nothing to it.
    pub drawn_energy_j: f64,
}

/// The figures of every motor, and their sums.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalFigures {
    /// Per motor, motor i at index i.
    pub motors: Vec<MotorFigures>,
    /// Sum over the motors of int tau_u^2 dt, N^2 m^2 s.
    pub torque_squared_integral: f64,
    /// Peak |sum over the motors of tau_u w| at one instant, W.
    pub peak_power_w: f64,
    /// Net mechanical work of all motors, J.
    pub work_j: f64,
    /// Sum of the motors' positive work, J.
    pub positive_work_j: f64,
    /// Sums of the motors' copper losses, net and drawn electrical energy, J, where the task
    /// gives every motor's torque constant and resistance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub electrical: Option<ElectricalTotals>,
    /// Energy lost in all transmissions, J, where the task gives an efficiency.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmission_loss_j: Option<f64>,
}

/// The motors' electrical figures summed, J.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ElectricalTotals {
    /// Copper losses of all motors, J.
    pub copper_loss_j: f64,
    /// Net electrical energy of all motors, J.
    pub energy_j: f64,
    /// Electrical energy the motors draw, each returning nothing when braking, J.
    pub drawn_energy_j: f64,
}

/// int_0^h max(p, 0) dt for p linear from `start` to `end` over a step `h`.
fn positive_part(start: f64, end: f64, h: f64) -> f64 {
    match (start >= 0.0, end >= 0.0) {
        (true, true) => h * (start + end) / 2.0,
        (false, false) => 0.0,
        _ => {
            let (high, low) = (start.max(end), start.min(end));
            h * high * high / (2.0 * (high - low))
        }
    }
}

/// The length of the motion `t`, s.
fn duration(t: &Trajectory) -> f64 {
    t.time.last().copied().unwrap_or(0.0) - t.time.first().copied().unwrap_or(0.0)
}

/// Motor `i`'s electrical figures over the intervals of `t`, with torque constant `k_t` (N m/A)
/// and resistance `r` (ohm).
fn electrical(t: &Trajectory, i: usize, (k_t, r): (f64, f64)) -> ElectricalFigures {
    let mut figures = ElectricalFigures {
        rms_current_a: 0.0,
        peak_current_a: 0.0,
        copper_loss_j: 0.0,
        energy_j: 0.0,
        drawn_energy_j: 0.0,
    };
    let mut current_squared_integral = 0.0;
    for (k, torques) in t.motor_torque.iter().enumerate() {
        let h = t.time[k + 1] - t.time[k];
        let current = torques[i] / k_t;
        let copper = r * current * current;
        let (p0, p1) = (
            torques[i] * t.motor_speed[k][i] + copper,
            torques[i] * t.motor_speed[k + 1][i] + copper,
        );
        current_squared_integral += h * current * current;
        figures.peak_current_a = figures.peak_current_a.max(current.abs());
        figures.copper_loss_j += h * copper;
        figures.energy_j += h * (p0 + p1) / 2.0;
        figures.drawn_energy_j += positive_part(p0, p1, h);
    }
    let duration = duration(t);
    if duration > 0.0 {
        figures.rms_current_a = (current_squared_integral / duration).sqrt();
    }
    figures
}

/// Motor `i`'s transmission loss over the intervals of `t`, J: its loss torque L_k is constant
/// over interval k and the speed linear, so int L w dt = sum h L_k (w_k + w_{k+1}) / 2. None
/// where `t` records no loss.
fn transmission_loss(t: &Trajectory, i: usize) -> Option<f64> {
    if t.transmission_loss.len() != t.motor_torque.len() {
        return None;
    }
    let intervals = t.transmission_loss.iter().enumerate();
    Some(intervals.fold(0.0, |sum, (k, losses)| {
        let h = t.time[k + 1] - t.time[k];
        sum + h * losses[i] * (t.motor_speed[k][i] + t.motor_speed[k + 1][i]) / 2.0
    }))
}

/// Motor `i`'s figures over the intervals of `t`.
fn motor(t: &Trajectory, i: usize) -> MotorFigures {
    let mut figures = MotorFigures {
        torque_squared_integral: 0.0,
        rms_torque_nm: 0.0,
        peak_torque_nm: 0.0,
        peak_speed_rad_s: 0.0,
        peak_power_w: 0.0,
        work_j: 0.0,
        positive_work_j: 0.0,
        electrical: None,
        transmission_loss_j: transmission_loss(t, i),
    };
    for (k, torques) in t.motor_torque.iter().enumerate() {
        let h = t.time[k + 1] - t.time[k];
        let tau = torques[i];
        let (w0, w1) = (t.motor_speed[k][i], t.motor_speed[k + 1][i]);
        let (p0, p1) = (tau * w0, tau * w1);
        figures.torque_squared_integral += h * tau * tau;
        figures.peak_torque_nm = figures.peak_torque_nm.max(tau.abs());
        figures.peak_power_w = figures.peak_power_w.max(p0.abs()).max(p1.abs());
        figures.work_j += h * (p0 + p1) / 2.0;
        figures.positive_work_j += positive_part(p0, p1, h);
    }
    for speeds in &t.motor_speed {
        figures.peak_speed_rad_s = figures.peak_speed_rad_s.max(speeds[i].abs());
    }
    let duration = duration(t);
    if duration > 0.0 {
        figures.rms_torque_nm = (figures.torque_squared_integral / duration).sqrt();
    }
    figures
}

impl PhysicalFigures {
    /// The figures of trajectory `t` (None when it has no interval or no motor), with each
    /// motor's torque constant (N m/A) and resistance (ohm) where `constants` gives them.
    pub fn of(t: &Trajectory, constants: Option<&[(f64, f64)]>) -> Option<PhysicalFigures> {
        let motors = t.motor_torque.first()?.len();
        if t.time.len() != t.motor_torque.len() + 1 || t.motor_speed.len() != t.time.len() {
            return None;
        }
        let constants = constants.filter(|c| c.len() == motors);
        let each: Vec<MotorFigures> = (0..motors)
            .map(|i| MotorFigures {
                electrical: constants.map(|c| electrical(t, i, c[i])),
                ..motor(t, i)
            })
            .collect();
        let electrical = constants.map(|_| {
            let sum = |of: fn(&ElectricalFigures) -> f64| {
                each.iter()
                    .filter_map(|m| m.electrical.as_ref())
                    .map(of)
                    .sum()
            };
            ElectricalTotals {
                copper_loss_j: sum(|e| e.copper_loss_j),
                energy_j: sum(|e| e.energy_j),
                drawn_energy_j: sum(|e| e.drawn_energy_j),
            }
        });
        let mut peak_power_w: f64 = 0.0;
        for (k, torques) in t.motor_torque.iter().enumerate() {
            for speeds in [&t.motor_speed[k], &t.motor_speed[k + 1]] {
                let power: f64 = torques.iter().zip(speeds).map(|(tau, w)| tau * w).sum();
                peak_power_w = peak_power_w.max(power.abs());
            }
        }
        Some(PhysicalFigures {
            torque_squared_integral: each.iter().map(|m| m.torque_squared_integral).sum(),
            work_j: each.iter().map(|m| m.work_j).sum(),
            positive_work_j: each.iter().map(|m| m.positive_work_j).sum(),
            transmission_loss_j: (each.iter())
                .map(|m| m.transmission_loss_j)
                .sum::<Option<f64>>(),
            peak_power_w,
            motors: each,
            electrical,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One motor, two intervals of 0.5 s: torque 2 then -1 N m, speeds 0, 4, 2 rad/s at the
    /// nodes; every figure by hand.
    #[test]
    fn figures_match_a_hand_computation() {
        let t = Trajectory {
            time: vec![0.0, 0.5, 1.0],
            motor_torque: vec![vec![2.0], vec![-1.0]],
            motor_speed: vec![vec![0.0], vec![4.0], vec![2.0]],
            ..Trajectory::default()
        };
        let f = PhysicalFigures::of(&t, None).unwrap();
        let m = &f.motors[0];
        assert_eq!(m.torque_squared_integral, 0.5 * 4.0 + 0.5 * 1.0);
        assert_eq!(m.rms_torque_nm, 2.5f64.sqrt());
        assert_eq!((m.peak_torque_nm, m.peak_speed_rad_s), (2.0, 4.0));
        // Power: 0 -> 8 W over the first interval, -4 -> -2 W over the second.
        assert_eq!(m.peak_power_w, 8.0);
        assert_eq!(m.work_j, 0.5 * 8.0 / 2.0 + 0.5 * (-6.0) / 2.0);
        assert_eq!(m.positive_work_j, 2.0);
        assert_eq!((f.work_j, f.peak_power_w), (m.work_j, 8.0));
    }

    /// The same motor with k_t = 0.5 N m/A and R = 2 ohm: currents 4 and -2 A, copper losses
    /// 32 and 8 W, electrical power 32 -> 40 W, then 4 -> 6 W.
    #[test]
    fn electrical_figures_match_a_hand_computation() {
        let t = Trajectory {
            time: vec![0.0, 0.5, 1.0],
            motor_torque: vec![vec![2.0], vec![-1.0]],
            motor_speed: vec![vec![0.0], vec![4.0], vec![2.0]],
            ..Trajectory::default()
        };
        let f = PhysicalFigures::of(&t, Some(&[(0.5, 2.0)])).unwrap();
        let e = f.motors[0].electrical.as_ref().unwrap();
        assert_eq!(e.peak_current_a, 4.0);
        assert_eq!(e.rms_current_a, (0.5f64 * 16.0 + 0.5 * 4.0).sqrt());
        assert_eq!(e.copper_loss_j, 0.5 * 32.0 + 0.5 * 8.0);
        // Net: the work (0.5) plus the copper losses (20).
        assert_eq!(
            e.energy_j,
            0.5 * (32.0 + 40.0) / 2.0 + 0.5 * (4.0 + 6.0) / 2.0
        );
        assert_eq!(e.energy_j, f.motors[0].work_j + e.copper_loss_j);
        assert_eq!(
            e.drawn_energy_j, e.energy_j,
            "the copper losses outweigh the braking"
        );
        let totals = f.electrical.as_ref().unwrap();
        assert_eq!(totals.copper_loss_j, e.copper_loss_j);
        // A motor braking harder than its losses returns energy, which the drawn energy does
        // not count.
        let braking = Trajectory {
            motor_torque: vec![vec![2.0], vec![-2.0]],
            motor_speed: vec![vec![0.0], vec![40.0], vec![40.0]],
            ..t
        };
        let f = PhysicalFigures::of(&braking, Some(&[(0.5, 2.0)])).unwrap();
        let e = f.motors[0].electrical.as_ref().unwrap();
        // Second interval: -80 + 32 = -48 W throughout, returned.
        assert_eq!(e.drawn_energy_j - e.energy_j, 0.5 * 48.0);
        assert!(PhysicalFigures::of(&braking, None)
            .unwrap()
            .electrical
            .is_none());
    }

    /// Loss torques of 0.2 and 0.1 N m over the two intervals, at speeds 0 -> 4 and 4 -> 2 rad/s:
    /// 0.5 * 0.2 * 2 + 0.5 * 0.1 * 3 J; none where the trajectory records no loss.
    #[test]
    fn transmission_loss_matches_a_hand_computation() {
        let t = Trajectory {
            time: vec![0.0, 0.5, 1.0],
            motor_torque: vec![vec![2.0], vec![-1.0]],
            motor_speed: vec![vec![0.0], vec![4.0], vec![2.0]],
            transmission_loss: vec![vec![0.2], vec![0.1]],
            ..Trajectory::default()
        };
        let f = PhysicalFigures::of(&t, None).unwrap();
        let expected = 0.5 * 0.2 * 2.0 + 0.5 * 0.1 * 3.0;
        assert!((f.motors[0].transmission_loss_j.unwrap() - expected).abs() < 1e-15);
        assert_eq!(f.transmission_loss_j, f.motors[0].transmission_loss_j);
        let lossless = Trajectory {
            transmission_loss: Vec::new(),
            ..t
        };
        let f = PhysicalFigures::of(&lossless, None).unwrap();
        assert_eq!(
            (f.motors[0].transmission_loss_j, f.transmission_loss_j),
            (None, None)
        );
    }

    /// Power that changes sign within an interval: only the positive triangle counts.
    #[test]
    fn positive_work_counts_the_driving_part_of_an_interval() {
        // p from -2 to 6 W over 1 s: it crosses 0 at 0.25 s; the positive part is 0.75 * 6 / 2.
        assert_eq!(positive_part(-2.0, 6.0, 1.0), 2.25);
        assert_eq!(positive_part(6.0, -2.0, 1.0), 2.25);
        assert_eq!(positive_part(-1.0, -3.0, 1.0), 0.0);
    }
}
