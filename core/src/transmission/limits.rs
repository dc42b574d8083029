//! Joint torque and speed limits (docs/model.md, section 5): the motor limits
//! abs(tau_u,i) <= tau_max,i and abs((G qd)_i) <= w_max,i of each motor i carried over to the
//! joints by each [`LimitMode`].

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
    /// |(matrix * x)_i| <= limits[i] for every row i (matrix = G^-T for torques, G for speeds).
    Linear {
        /// One row per motor.
        matrix: DMatrix<f64>,
        /// Each motor's own limit, one per row.
        limits: Vec<f64>,
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
            JointLimits::Linear { matrix, limits } => (matrix * DVector::from_column_slice(x))
                .iter()
                .zip(limits)
                .all(|(v, limit)| v.abs() <= limit + tolerance),
        }
    }
}

/// The motors' limits l as a common factor and weights: (max_j l_j, l_j / max_j l_j). Sums over
/// the motors weighted by their limits are formed as max l * sum_j w_j x_j, so that motors with
/// equal limits give exactly l * sum_j x_j, the numbers of one limit for every motor.
pub fn limit_weights(limits: &[f64]) -> (f64, Vec<f64>) {
    let scale = limits.iter().copied().fold(0.0, f64::max);
    (scale, limits.iter().map(|l| l / scale).collect())
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

/// The symmetric box +-sum_j |m_ij| limits_j per row i.
fn symmetric_box(m: &DMatrix<f64>, limits: &[f64]) -> JointLimits {
    let (scale, weights) = limit_weights(limits);
    let upper: Vec<f64> = m
        .row_iter()
        .map(|row| {
            scale
                * row
                    .iter()
                    .zip(&weights)
                    .map(|(v, w)| v.abs() * w)
                    .sum::<f64>()
        })
        .collect();
    let lower = upper.iter().map(|v| -v).collect();
    JointLimits::Box { lower, upper }
}

impl Coupling {
    /// Joint torque limits (N m) of the joint-space problem for motor limits
    /// |tau_u,i| <= torque_limits[i] (one per motor, the rows of G):
    /// - `Paper`: G^T tau_min .. G^T tau_max elementwise with tau_min/max = -+torque_limits. Where
    ///   an element comes out negative the two values are reversed; each element's box is then
    ///   taken from the smaller to the larger.
    /// - `Interval`: |tau_i| <= sum_j |G_ji| torque_limits[j], the smallest box holding every
    ///   reachable tau.
    /// - `Exact`: |(G^-T tau)_i| <= torque_limits[i], row by row.
    ///
    /// # Panics
    /// If `torque_limits` does not have one value per motor.
    pub fn torque_limits(&self, mode: LimitMode, torque_limits: &[f64]) -> JointLimits {
        match mode {
            LimitMode::Paper => {
                let upper = self
                    .matrix()
                    .tr_mul(&DVector::from_column_slice(torque_limits));
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(&self.matrix().transpose(), torque_limits),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.inverse().transpose(),
                limits: torque_limits.to_vec(),
            },
        }
    }

    /// Joint speed limits (rad/s) for motor limits |qd_u,i| <= speed_limits[i] (one per motor):
    /// - `Paper`: G^-1 w_min .. G^-1 w_max elementwise with w_min/max = -+speed_limits (reversed
    ///   elements are ordered as for torques; a joint whose row of G^-1 weighs the limits to 0
    ///   gets 0).
    /// - `Interval`: |qd_i| <= sum_j |(G^-1)_ij| speed_limits[j].
    /// - `Exact`: |(G qd)_i| <= speed_limits[i], row by row.
    ///
    /// # Panics
    /// If `speed_limits` does not have one value per motor.
    pub fn speed_limits(&self, mode: LimitMode, speed_limits: &[f64]) -> JointLimits {
        match mode {
            LimitMode::Paper => {
                let upper = self.inverse() * DVector::from_column_slice(speed_limits);
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(self.inverse(), speed_limits),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.matrix().clone(),
                limits: speed_limits.to_vec(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::{MatrixEntry, MatrixRow, TransmissionSpec};
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

    /// Every corner of the box [-limits_j, limits_j] over the motors j.
    fn corners(limits: &[f64]) -> Vec<Vec<f64>> {
        (0..1usize << limits.len())
            .map(|mask| {
                (0..limits.len())
                    .map(|j| {
                        if mask >> j & 1 == 1 {
                            limits[j]
                        } else {
                            -limits[j]
                        }
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn paper_torque_limits_reproduce_the_papers_figures() {
        let task = pick_place();
        let coupling = belt_arm().coupling(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        let limits =
            coupling.torque_limits(LimitMode::Paper, &task.motors.torque_limit_nm.values(4));
        assert_box(&limits, &[18.7, 8.5, 3.4, 0.0]);
        let interval = coupling.torque_limits(LimitMode::Interval, &[1.7; 4]);
        assert_box(&interval, &[18.7, 8.5, 3.4, 3.4]);
    }

    #[test]
    fn speed_limits_at_the_original_design() {
        let coupling = belt_arm().coupling(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        // qd1 = w1/6, qd2 = w2/3 - w1/6, qd3 = (w3 + w4)/2 - w2/3, qd4 = (w3 - w4)/2.
        let paper = coupling.speed_limits(LimitMode::Paper, &[100.0; 4]);
        assert_box(&paper, &[100.0 / 6.0, 100.0 / 6.0, 200.0 / 3.0, 0.0]);
        let interval = coupling.speed_limits(LimitMode::Interval, &[100.0; 4]);
        assert_box(&interval, &[100.0 / 6.0, 50.0, 400.0 / 3.0, 100.0]);
    }

    /// Each motor's own limit enters the bounds of the joints it drives (its row of G), weighted
    /// by its entries: motor 1 only joint 1's, motor 2 joint 1's and 2's, motors 3 and 4 all.
    #[test]
    fn each_motors_limit_moves_the_bounds_of_its_joints() {
        let coupling = belt_arm().coupling(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        let torques = [1.7, 1.0, 1.7, 0.5];
        // tau = G^T tau_u: tau1 = 6 t1 + 3 t2 + t3 + t4, tau2 = 3 t2 + t3 + t4, tau3 = t3 + t4,
        // tau4 = t3 - t4.
        let paper = coupling.torque_limits(LimitMode::Paper, &torques);
        assert_box(&paper, &[10.2 + 3.0 + 2.2, 3.0 + 2.2, 2.2, 1.2]);
        let interval = coupling.torque_limits(LimitMode::Interval, &torques);
        assert_box(&interval, &[10.2 + 3.0 + 2.2, 3.0 + 2.2, 2.2, 2.2]);
        let speeds = [100.0, 60.0, 100.0, 40.0];
        let paper = coupling.speed_limits(LimitMode::Paper, &speeds);
        assert_box(
            &paper,
            &[100.0 / 6.0, 20.0 - 100.0 / 6.0, 70.0 - 20.0, 30.0],
        );
        let interval = coupling.speed_limits(LimitMode::Interval, &speeds);
        assert_box(
            &interval,
            &[100.0 / 6.0, 20.0 + 100.0 / 6.0, 70.0 + 20.0, 70.0],
        );
        for (limits, speed) in [(&torques, false), (&speeds, true)] {
            let exact = if speed {
                coupling.speed_limits(LimitMode::Exact, limits)
            } else {
                coupling.torque_limits(LimitMode::Exact, limits)
            };
            let JointLimits::Linear { limits: rows, .. } = exact else {
                panic!("exact limits are linear");
            };
            assert_eq!(rows, limits.to_vec());
        }
    }

    /// Motors with equal limits give exactly (to the bit) the bounds of one limit for all
    /// motors: G^T or G^-1 applied to that limit's vector (`paper`), the limit times the rows'
    /// absolute sums (`interval`), that limit on every row (`exact`).
    #[test]
    fn equal_limits_are_one_limit_to_the_bit() {
        let coupling = belt_arm().coupling(&[8.2, 4.1, 2.7, 1.3]).unwrap();
        let one_limit = |m: &DMatrix<f64>, limit: f64| -> Vec<f64> {
            m.row_iter()
                .map(|row| limit * row.iter().map(|v| v.abs()).sum::<f64>())
                .collect()
        };
        for limit in [1.7, 100.0, 0.3] {
            let JointLimits::Box { upper, .. } =
                coupling.torque_limits(LimitMode::Interval, &[limit; 4])
            else {
                unreachable!()
            };
            assert_eq!(upper, one_limit(&coupling.matrix().transpose(), limit));
            let JointLimits::Box { upper, .. } =
                coupling.speed_limits(LimitMode::Interval, &[limit; 4])
            else {
                unreachable!()
            };
            assert_eq!(upper, one_limit(coupling.inverse(), limit));
            let ones = DVector::from_element(4, limit);
            let JointLimits::Box { upper, .. } =
                coupling.torque_limits(LimitMode::Paper, &[limit; 4])
            else {
                unreachable!()
            };
            let expected = coupling.matrix().tr_mul(&ones);
            assert!(upper.iter().zip(&expected).all(|(u, e)| *u == e.abs()));
        }
    }

    #[test]
    fn paper_limits_order_reversed_elements() {
        let spec = TransmissionSpec {
            matrix: vec![
                MatrixRow::Entries(vec![
                    MatrixEntry::Ratio("-r1".into()),
                    MatrixEntry::Constant(0.0),
                ]),
                MatrixRow::Entries(vec![MatrixEntry::Constant(0.0), MatrixEntry::Constant(2.0)]),
            ],
            original: vec![3.0],
            bounds: vec![[1.0, 4.0]],
            order: vec![],
        };
        let coupling = Transmission::from_spec(&spec)
            .unwrap()
            .coupling(&[3.0])
            .unwrap();
        assert_box(
            &coupling.torque_limits(LimitMode::Paper, &[1.0, 1.0]),
            &[3.0, 2.0],
        );
        assert_box(
            &coupling.speed_limits(LimitMode::Paper, &[6.0, 6.0]),
            &[2.0, 3.0],
        );
    }

    /// The limits of every mode against motor vectors drawn inside each motor's own limit, and
    /// pushed past one motor's: `exact` is the true set, `interval` the tightest box holding it,
    /// with different limits per motor.
    #[test]
    fn exact_limits_agree_with_brute_force() {
        let t = belt_arm();
        let mut rng = Random::new(7);
        let (tl, wl) = ([1.7, 2.5, 0.9, 1.2], [100.0, 80.0, 120.0, 60.0]);
        for r in [[6.0, 3.0, 1.0, 1.0], [8.2, 4.1, 2.7, 1.3]] {
            let coupling = t.coupling(&r).unwrap();
            let torque = coupling.torque_limits(LimitMode::Exact, &tl);
            let torque_box = coupling.torque_limits(LimitMode::Interval, &tl);
            let speed = coupling.speed_limits(LimitMode::Exact, &wl);
            let speed_box = coupling.speed_limits(LimitMode::Interval, &wl);
            for _ in 0..200 {
                // Motor torques inside the box reach joint torques inside the polytope and back.
                let tau_u: Vec<f64> = tl.iter().map(|l| l * rng.real(-1.0..1.0)).collect();
                let tau = coupling.joint_torques(&tau_u);
                assert!(torque.contains(&tau, 1e-12) && torque_box.contains(&tau, 1e-12));
                let back = coupling.motor_torques(&tau);
                assert!(back.iter().zip(&tau_u).all(|(a, b)| (a - b).abs() < 1e-12));
                // Pushing one motor past its own limit leaves the polytope.
                let mut outside = tau_u.clone();
                let motor = ((rng.real(-1.0..1.0) + 1.0) * 2.0) as usize % 4;
                outside[motor] = 1.01 * tl[motor];
                assert!(!torque.contains(&coupling.joint_torques(&outside), 1e-12));
                // Likewise for speeds: qd = G^-1 qd_u.
                let w: Vec<f64> = wl.iter().map(|l| l * rng.real(-1.0..1.0)).collect();
                let qd = (coupling.inverse() * DVector::from_vec(w.clone()))
                    .as_slice()
                    .to_vec();
                assert!(speed.contains(&qd, 1e-9) && speed_box.contains(&qd, 1e-9));
                let back = coupling.motor_speeds(&qd);
                assert!(back.iter().zip(&w).all(|(a, b)| (a - b).abs() < 1e-9));
                let mut outside = w.clone();
                outside[motor] = -1.01 * wl[motor];
                let qd = coupling.inverse() * DVector::from_vec(outside);
                assert!(!speed.contains(qd.as_slice(), 1e-9));
            }
            // The interval box is the tightest: its bounds are reached at corners of the motor box.
            let JointLimits::Box { upper, .. } = &torque_box else {
                unreachable!()
            };
            for (i, bound) in upper.iter().enumerate() {
                let reached = corners(&tl)
                    .iter()
                    .map(|c| coupling.joint_torques(c)[i].abs())
                    .fold(0.0, f64::max);
                assert!((reached - bound).abs() < 1e-12);
            }
            let JointLimits::Box { upper, .. } = &speed_box else {
                unreachable!()
            };
            for (i, bound) in upper.iter().enumerate() {
                let reached = corners(&wl)
                    .iter()
                    .map(|c| (coupling.inverse() * DVector::from_vec(c.clone()))[i].abs())
                    .fold(0.0, f64::max);
                assert!((reached - bound).abs() < 1e-9);
            }
            // The paper box is the image of the upper corner: G^T tau_max, G^-1 w_max.
            let all_upper = |limits: JointLimits| match limits {
                JointLimits::Box { upper, .. } => upper,
                JointLimits::Linear { .. } => unreachable!(),
            };
            let paper = all_upper(coupling.torque_limits(LimitMode::Paper, &tl));
            let image = coupling.joint_torques(&tl);
            assert!(paper
                .iter()
                .zip(&image)
                .all(|(p, i)| (p - i.abs()).abs() < 1e-12));
            let paper = all_upper(coupling.speed_limits(LimitMode::Paper, &wl));
            let image = coupling.inverse() * DVector::from_column_slice(&wl);
            assert!(paper
                .iter()
                .zip(&image)
                .all(|(p, i)| (p - i.abs()).abs() < 1e-9));
        }
    }

    #[test]
    fn exact_limits_are_rows_of_g_inverse_transposed_and_g() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let JointLimits::Linear { matrix, limits } =
            coupling.torque_limits(LimitMode::Exact, &[1.7; 4])
        else {
            panic!("exact torque limits are linear")
        };
        assert_eq!(
            (matrix, limits),
            (coupling.inverse().transpose(), vec![1.7; 4])
        );
        let JointLimits::Linear { matrix, limits } =
            coupling.speed_limits(LimitMode::Exact, &[100.0; 4])
        else {
            panic!("exact speed limits are linear")
        };
        assert_eq!((&matrix, limits), (coupling.matrix(), vec![100.0; 4]));
    }

    #[test]
    fn limit_weights_factor_out_the_largest_limit() {
        assert_eq!(limit_weights(&[1.7; 3]), (1.7, vec![1.0; 3]));
        assert_eq!(limit_weights(&[1.0, 4.0, 2.0]), (4.0, vec![0.25, 1.0, 0.5]));
    }
}
