//! Joint torque and speed limits (docs/model.md, section 5): the motor limits
//! abs(tau_u) <= tau_max and abs(G qd) <= w_max carried over to the joints by each [`LimitMode`].

use super::Coupling;
use crate::model::task::LimitMode;
use nalgebra::{DMatrix, DVector};

/// Limits on a joint-space vector x (torques in N m or speeds in rad/s).
#[derive(Clone, Debug, PartialEq)]
pub enum JointLimits {
    /// lower <= x <= upper elementwise.
    Box {
        /// Lower bound per joint.
        lower: Vec<f64>,
        /// Upper bound per joint.
        upper: Vec<f64>,
    },
    /// |matrix * x| <= limit for every row (matrix = G^-T for torques, G for speeds).
    Linear {
        /// One row per motor.
        matrix: DMatrix<f64>,
        /// The motor limit, same for every row.
        limit: f64,
    },
}

impl JointLimits {
    /// Whether x satisfies the limits with slack `tolerance` (same units as x).
    ///
    /// # Panics
    /// If x does not have one value per joint.
    pub fn contains(&self, x: &[f64], tolerance: f64) -> bool {
        match self {
            JointLimits::Box { lower, upper } => {
                assert_eq!(x.len(), lower.len(), "JointLimits::contains: wrong length");
                x.iter()
                    .zip(lower.iter().zip(upper))
                    .all(|(v, (lo, hi))| *v >= lo - tolerance && *v <= hi + tolerance)
            }
            JointLimits::Linear { matrix, limit } => (matrix * DVector::from_column_slice(x))
                .iter()
                .all(|v| v.abs() <= limit + tolerance),
        }
    }
}

/// The elementwise box between a and b, whichever is larger per element.
fn ordered_box(a: DVector<f64>, b: DVector<f64>) -> JointLimits {
    let (lower, upper) = a
        .iter()
        .zip(b.iter())
        .map(|(x, y)| (x.min(*y), x.max(*y)))
        .unzip();
    JointLimits::Box { lower, upper }
}

/// The symmetric box +-limit * sum_j |m_ij| per row i.
fn symmetric_box(m: &DMatrix<f64>, limit: f64) -> JointLimits {
    let upper: Vec<f64> = m
        .row_iter()
        .map(|row| limit * row.iter().map(|v| v.abs()).sum::<f64>())
        .collect();
    let lower = upper.iter().map(|v| -v).collect();
    JointLimits::Box { lower, upper }
}

impl Coupling {
    /// Joint torque limits (N m) of the joint-space problem for motor limits |tau_u| <= torque_limit:
    /// - `Paper`: G^T tau_min .. G^T tau_max elementwise with tau_min/max = -+torque_limit. Where a
    ///   column of G sums to a negative number the two values come out reversed; each element's
    ///   box is then taken from the smaller to the larger.
    /// - `Interval`: |tau_i| <= sum_j |G_ji| torque_limit, the smallest box holding every reachable tau.
    /// - `Exact`: |G^-T tau| <= torque_limit, row by row.
    pub fn torque_limits(&self, mode: LimitMode, torque_limit: f64) -> JointLimits {
        match mode {
            LimitMode::Paper => {
                let ones = DVector::from_element(self.matrix().nrows(), torque_limit);
                let upper = self.matrix().tr_mul(&ones);
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(&self.matrix().transpose(), torque_limit),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.inverse().transpose(),
                limit: torque_limit,
            },
        }
    }

    /// Joint speed limits (rad/s) for motor limits |qd_u| <= speed_limit:
    /// - `Paper`: G^-1 w_min .. G^-1 w_max elementwise with w_min/max = -+speed_limit (reversed
    ///   elements are ordered as for torques; a joint whose row of G^-1 sums to 0 gets 0).
    /// - `Interval`: |qd_i| <= sum_j |(G^-1)_ij| speed_limit.
    /// - `Exact`: |G qd| <= speed_limit, row by row.
    pub fn speed_limits(&self, mode: LimitMode, speed_limit: f64) -> JointLimits {
        match mode {
            LimitMode::Paper => {
                let ones = DVector::from_element(self.inverse().ncols(), speed_limit);
                let upper = self.inverse() * ones;
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(self.inverse(), speed_limit),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.matrix().clone(),
                limit: speed_limit,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::{MatrixEntry, TransmissionSpec};
    use crate::testing::Random;
    use crate::transmission::fixtures::{belt_arm, pick_place};
    use crate::transmission::Transmission;

    fn assert_box(limits: &JointLimits, expected_upper: &[f64]) {
        let JointLimits::Box { lower, upper } = limits else {
            panic!("expected a box, got {limits:?}");
        };
        for (i, &e) in expected_upper.iter().enumerate() {
            assert!(
                (upper[i] - e).abs() < 1e-12,
                "upper[{i}] = {} not {e}",
                upper[i]
            );
            assert!(
                (lower[i] + e).abs() < 1e-12,
                "lower[{i}] = {} not {}",
                lower[i],
                -e
            );
        }
    }

    /// Every corner of the box [-limit, limit]^n.
    fn corners(n: usize, limit: f64) -> Vec<Vec<f64>> {
        (0..1usize << n)
            .map(|mask| {
                (0..n)
                    .map(|j| if mask >> j & 1 == 1 { limit } else { -limit })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn paper_torque_limits_reproduce_the_papers_figures() {
        let task = pick_place();
        let coupling = belt_arm().coupling(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        let limits = coupling.torque_limits(LimitMode::Paper, task.motors.torque_limit_nm);
        assert_box(&limits, &[18.7, 8.5, 3.4, 0.0]);
        let interval = coupling.torque_limits(LimitMode::Interval, 1.7);
        assert_box(&interval, &[18.7, 8.5, 3.4, 3.4]);
    }

    #[test]
    fn speed_limits_at_the_original_design() {
        let coupling = belt_arm().coupling(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        // qd1 = w1/6, qd2 = w2/3 - w1/6, qd3 = (w3 + w4)/2 - w2/3, qd4 = (w3 - w4)/2.
        let paper = coupling.speed_limits(LimitMode::Paper, 100.0);
        assert_box(&paper, &[100.0 / 6.0, 100.0 / 6.0, 200.0 / 3.0, 0.0]);
        let interval = coupling.speed_limits(LimitMode::Interval, 100.0);
        assert_box(&interval, &[100.0 / 6.0, 50.0, 400.0 / 3.0, 100.0]);
    }

    #[test]
    fn paper_limits_order_reversed_elements() {
        let spec = TransmissionSpec {
            matrix: vec![
                vec![MatrixEntry::Ratio("-r1".into()), MatrixEntry::Constant(0.0)],
                vec![MatrixEntry::Constant(0.0), MatrixEntry::Constant(2.0)],
            ],
            original: vec![3.0],
            bounds: vec![[1.0, 4.0]],
            order: vec![],
        };
        let coupling = Transmission::from_spec(&spec)
            .unwrap()
            .coupling(&[3.0])
            .unwrap();
        assert_box(&coupling.torque_limits(LimitMode::Paper, 1.0), &[3.0, 2.0]);
        assert_box(&coupling.speed_limits(LimitMode::Paper, 6.0), &[2.0, 3.0]);
    }

    #[test]
    fn exact_limits_agree_with_brute_force() {
        let t = belt_arm();
        let mut rng = Random::new(7);
        for r in [[6.0, 3.0, 1.0, 1.0], [8.2, 4.1, 2.7, 1.3]] {
            let coupling = t.coupling(&r).unwrap();
            let (tl, wl) = (1.7, 100.0);
            let torque = coupling.torque_limits(LimitMode::Exact, tl);
            let torque_box = coupling.torque_limits(LimitMode::Interval, tl);
            let speed = coupling.speed_limits(LimitMode::Exact, wl);
            let speed_box = coupling.speed_limits(LimitMode::Interval, wl);
            for _ in 0..200 {
                // Motor torques inside the box reach joint torques inside the polytope and back.
                let tau_u: Vec<f64> = (0..4).map(|_| tl * rng.real(-1.0..1.0)).collect();
                let tau = coupling.joint_torques(&tau_u);
                assert!(torque.contains(&tau, 1e-12) && torque_box.contains(&tau, 1e-12));
                let back = coupling.motor_torques(&tau);
                assert!(back.iter().zip(&tau_u).all(|(a, b)| (a - b).abs() < 1e-12));
                // Pushing one motor past its limit leaves the polytope.
                let mut outside = tau_u.clone();
                outside[((rng.real(-1.0..1.0) + 1.0) * 2.0) as usize % 4] = 1.01 * tl;
                assert!(!torque.contains(&coupling.joint_torques(&outside), 1e-12));
                // Likewise for speeds: qd = G^-1 qd_u.
                let w: Vec<f64> = (0..4).map(|_| wl * rng.real(-1.0..1.0)).collect();
                let qd = (coupling.inverse() * DVector::from_vec(w.clone()))
                    .as_slice()
                    .to_vec();
                assert!(speed.contains(&qd, 1e-9) && speed_box.contains(&qd, 1e-9));
                let back = coupling.motor_speeds(&qd);
                assert!(back.iter().zip(&w).all(|(a, b)| (a - b).abs() < 1e-9));
            }
            // The interval box is the tightest: its bounds are reached at corners of the motor box.
            let JointLimits::Box { upper, .. } = &torque_box else {
                unreachable!()
            };
            for (i, bound) in upper.iter().enumerate() {
                let reached = corners(4, tl)
                    .iter()
                    .map(|c| coupling.joint_torques(c)[i].abs())
                    .fold(0.0, f64::max);
                assert!((reached - bound).abs() < 1e-12);
            }
            let JointLimits::Box { upper, .. } = &speed_box else {
                unreachable!()
            };
            for (i, bound) in upper.iter().enumerate() {
                let reached = corners(4, wl)
                    .iter()
                    .map(|c| (coupling.inverse() * DVector::from_vec(c.clone()))[i].abs())
                    .fold(0.0, f64::max);
                assert!((reached - bound).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn exact_limits_are_rows_of_g_inverse_transposed_and_g() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let JointLimits::Linear { matrix, limit } = coupling.torque_limits(LimitMode::Exact, 1.7)
        else {
            panic!("exact torque limits are linear")
        };
        assert_eq!((matrix, limit), (coupling.inverse().transpose(), 1.7));
        let JointLimits::Linear { matrix, limit } = coupling.speed_limits(LimitMode::Exact, 100.0)
        else {
            panic!("exact speed limits are linear")
        };
        assert_eq!((&matrix, limit), (coupling.matrix(), 100.0));
    }
}
