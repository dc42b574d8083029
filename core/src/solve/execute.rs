//! Whether the motors can execute a trajectory: each motor's torques and speeds, recovered
//! through G from the joints' (tau_u = G^-T tau, w = G v, as the result's trajectory holds
//! them), against that motor's own limits. A joint-space problem bounds the joints, not the
//! motors: under the limit modes `paper` and `interval` its optimum can ask more of a motor than
//! it has; under `exact`, as in the actuation space, it cannot beyond the solver's tolerance.

use serde::{Deserialize, Serialize};

/// A peak within this share of its limit counts as within it: the solver's bound relaxation.
const RELATIVE_TOLERANCE: f64 = 1e-6;

/// Whether the motors can execute a trajectory, and by how much each exceeds its limits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotorsExecute {
    /// Whether every motor's peak torque and speed lie within its limits (to 1e-6 relative).
    pub executes: bool,
    /// Per motor: its peak |torque| above its torque limit, N m (0 within it).
    pub torque_excess_nm: Vec<f64>,
    /// Per motor: its peak |speed| above its speed limit, rad/s (0 within it).
    pub speed_excess_rad_s: Vec<f64>,
    /// Per motor: its peak |torque| over the intervals, N m.
    pub torque_peak_nm: Vec<f64>,
    /// Per motor: its peak |speed| over the nodes, rad/s.
    pub speed_peak_rad_s: Vec<f64>,
    /// Per motor: its torque limit less its peak |torque|, N m; negative where it exceeds it.
    pub torque_margin_nm: Vec<f64>,
    /// Per motor: its speed limit less its peak |speed|, rad/s; negative where it exceeds it.
    pub speed_margin_rad_s: Vec<f64>,
}

impl MotorsExecute {
    /// The verdict on a trajectory whose motors' peak |torque| (N m) and |speed| (rad/s) are
    /// `peaks`, against each motor's `limits` of torque (N m) and speed (rad/s), motor i at
    /// index i.
    pub fn of(peaks: (&[f64], &[f64]), limits: (&[f64], &[f64])) -> Self {
        let excess = |peaks: &[f64], limits: &[f64]| -> Vec<f64> {
            peaks
                .iter()
                .zip(limits)
                .map(|(&peak, &limit)| {
                    let over = peak - limit;
                    if over <= RELATIVE_TOLERANCE * limit.abs() {
                        0.0
                    } else {
                        over
                    }
                })
                .collect()
        };
        let torque_excess_nm = excess(peaks.0, limits.0);
        let speed_excess_rad_s = excess(peaks.1, limits.1);
        let margin = |peaks: &[f64], limits: &[f64]| -> Vec<f64> {
            peaks.iter().zip(limits).map(|(p, l)| l - p).collect()
        };
        MotorsExecute {
            torque_margin_nm: margin(peaks.0, limits.0),
            speed_margin_rad_s: margin(peaks.1, limits.1),
            torque_peak_nm: peaks.0.to_vec(),
            speed_peak_rad_s: peaks.1.to_vec(),
            executes: torque_excess_nm
                .iter()
                .chain(&speed_excess_rad_s)
                .all(|e| *e == 0.0),
            torque_excess_nm,
            speed_excess_rad_s,
        }
    }

    /// `the motors can execute it`, or each motor over a limit and by how much, e.g. `motor 2
    /// exceeds its torque limit by 2.83 N m`.
    pub fn text(&self) -> String {
        if self.executes {
            return "the motors can execute it".to_owned();
        }
        let mut over = Vec::new();
        for (what, unit, excess) in [
            ("torque", "N m", &self.torque_excess_nm),
            ("speed", "rad/s", &self.speed_excess_rad_s),
        ] {
            for (motor, e) in excess.iter().enumerate().filter(|(_, e)| **e > 0.0) {
                over.push(format!(
                    "motor {} exceeds its {what} limit by {e:.3} {unit}",
                    motor + 1
                ));
            }
        }
        format!("the motors CANNOT execute it: {}", over.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::MotorsExecute;

    #[test]
    fn each_motor_over_a_limit_is_named_with_its_excess() {
        let within = MotorsExecute::of(
            (&[1.7, 0.5], &[100.0, 20.0]),
            (&[1.7, 1.7], &[100.0, 100.0]),
        );
        assert!(within.executes, "{within:?}");
        assert_eq!(within.text(), "the motors can execute it");
        let over = MotorsExecute::of(
            (&[4.53, 0.5], &[100.0, 140.0]),
            (&[1.7, 1.7], &[100.0, 100.0]),
        );
        assert!(!over.executes);
        assert!((over.torque_excess_nm[0] - 2.83).abs() < 1e-12);
        assert_eq!(over.speed_excess_rad_s, vec![0.0, 40.0]);
        assert_eq!(
            over.text(),
            "the motors CANNOT execute it: motor 1 exceeds its torque limit by 2.830 N m, motor 2 \
             exceeds its speed limit by 40.000 rad/s"
        );
    }
}
