//! The transmission G(r) (docs/model.md, sections 3 to 5): motor angles q_u = G(r) q, motor
//! speeds qd_u = G(r) qd, joint torques tau = G(r)^T tau_u, with G affine in the design ratios r.
//!
//! The structure of G and the design space come from the task file's `transmission` section;
//! nothing about the belt arm is hard-coded here. Units: ratios are dimensionless, torques N m,
//! speeds rad/s. Rows of G are motors, columns joints.

use crate::model::task::{LimitMode, MatrixEntry, TransmissionSpec};
use nalgebra::{DMatrix, DVector};
use std::fmt;

/// One entry of G: a constant or plus/minus one design ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Entry {
    Constant(f64),
    /// `sign * r[index]` (index 0-based, sign +-1).
    Ratio {
        index: usize,
        sign: f64,
    },
}

/// An order constraint between two ratios: r_lower <= r_upper, or r_lower < r_upper when strict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OrderConstraint {
    /// 0-based index of the ratio on the left.
    pub lower: usize,
    /// 0-based index of the ratio on the right.
    pub upper: usize,
    /// `<` rather than `<=`.
    pub strict: bool,
}

impl OrderConstraint {
    /// Whether the two values satisfy the constraint.
    pub fn holds(&self, lower_value: f64, upper_value: f64) -> bool {
        if self.strict {
            lower_value < upper_value
        } else {
            lower_value <= upper_value
        }
    }
}

impl fmt::Display for OrderConstraint {
    /// Writes the constraint as the task file does, with 1-based names: `r3 <= r2`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let op = if self.strict { "<" } else { "<=" };
        write!(f, "r{} {op} r{}", self.lower + 1, self.upper + 1)
    }
}

/// The parsed structure of G(r) and the design space (bounds, order constraints, original design).
#[derive(Clone, Debug)]
pub struct Transmission {
    dof: usize,
    /// Row-major entries of G.
    entries: Vec<Entry>,
    original: Vec<f64>,
    bounds: Vec<[f64; 2]>,
    order: Vec<OrderConstraint>,
}

/// Why a design r is not admissible; the message names the ratio or the constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignError {
    message: String,
}

impl DesignError {
    fn new(message: String) -> DesignError {
        DesignError { message }
    }

    /// The message, e.g. `r2 = 9.5 is outside [1, 9]`.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for DesignError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for DesignError {}

/// Parses `r<i>` (1-based) into a 0-based index below `count`.
fn parse_ratio_name(text: &str, count: usize) -> Option<usize> {
    let digits = text.trim().strip_prefix('r')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let number: usize = digits.parse().ok()?;
    (1..=count).contains(&number).then(|| number - 1)
}

/// Parses `r<i>` or `-r<i>`.
fn parse_entry(text: &str, count: usize) -> Option<Entry> {
    let text = text.trim();
    let (sign, name) = match text.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, text),
    };
    let index = parse_ratio_name(name, count)?;
    Some(Entry::Ratio { index, sign })
}

/// Parses `r<i> <= r<j>` or `r<i> < r<j>`.
fn parse_order(text: &str, count: usize) -> Option<OrderConstraint> {
    let (left, right, strict) = match text.split_once("<=") {
        Some((left, right)) => (left, right, false),
        None => {
            let (left, right) = text.split_once('<')?;
            (left, right, true)
        }
    };
    Some(OrderConstraint {
        lower: parse_ratio_name(left, count)?,
        upper: parse_ratio_name(right, count)?,
        strict,
    })
}

impl Transmission {
    /// Parses and checks the spec: a square matrix whose entries are finite numbers or `[-]r<i>`
    /// with 1 <= i <= number of ratios (= number of bounds), as many original values as bounds,
    /// finite bounds with lower <= upper, finite original values, and order strings
    /// `r<i> <= r<j>` or `r<i> < r<j>` with i != j. Errors name the field, e.g.
    /// `transmission.matrix[2][1]` (0-based indices). The original design is not held to the
    /// design space here: [`Transmission::check_design`] does that.
    pub fn from_spec(spec: &TransmissionSpec) -> Result<Transmission, String> {
        let count = spec.bounds.len();
        if spec.original.len() != count {
            return Err(format!(
                "transmission.original has {} values but transmission.bounds has {count}",
                spec.original.len()
            ));
        }
        for (i, &[lo, hi]) in spec.bounds.iter().enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(format!(
                    "transmission.bounds[{i}] = [{lo}, {hi}] must be finite with lower <= upper"
                ));
            }
        }
        if let Some(i) = spec.original.iter().position(|v| !v.is_finite()) {
            return Err(format!("transmission.original[{i}] is not a finite number"));
        }
        let dof = spec.matrix.len();
        if dof == 0 {
            return Err("transmission.matrix is empty".to_owned());
        }
        let mut entries = Vec::with_capacity(dof * dof);
        for (i, row) in spec.matrix.iter().enumerate() {
            if row.len() != dof {
                return Err(format!(
                    "transmission.matrix[{i}] has {} entries but the matrix has {dof} rows (it must be square)",
                    row.len()
                ));
            }
            for (j, entry) in row.iter().enumerate() {
                let parsed = match entry {
                    MatrixEntry::Constant(value) if value.is_finite() => {
                        Some(Entry::Constant(*value))
                    }
                    MatrixEntry::Constant(_) => None,
                    MatrixEntry::Ratio(text) => parse_entry(text, count),
                };
                let Some(parsed) = parsed else {
                    let shown = match entry {
                        MatrixEntry::Constant(value) => value.to_string(),
                        MatrixEntry::Ratio(text) => format!("{text:?}"),
                    };
                    return Err(format!(
                        "transmission.matrix[{i}][{j}] = {shown} must be a finite number or \
                         \"r<i>\" / \"-r<i>\" with 1 <= i <= {count} (the number of bounds)"
                    ));
                };
                entries.push(parsed);
            }
        }
        let mut order = Vec::with_capacity(spec.order.len());
        for (k, text) in spec.order.iter().enumerate() {
            let constraint = parse_order(text, count).ok_or_else(|| {
                format!(
                    "transmission.order[{k}] = {text:?} must read \"r<i> <= r<j>\" or \"r<i> < r<j>\" \
                     with 1 <= i, j <= {count}"
                )
            })?;
            if constraint.lower == constraint.upper {
                return Err(format!(
                    "transmission.order[{k}] = {text:?} compares a ratio with itself"
                ));
            }
            order.push(constraint);
        }
        Ok(Transmission {
            dof,
            entries,
            original: spec.original.clone(),
            bounds: spec.bounds.clone(),
            order,
        })
    }

    /// Number of design ratios.
    pub fn num_ratios(&self) -> usize {
        self.bounds.len()
    }

    /// Size of G: the number of joints (= motors).
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The original design r (dimensionless).
    pub fn original(&self) -> &[f64] {
        &self.original
    }

    /// Bounds [lower, upper] of each ratio (dimensionless).
    pub fn bounds(&self) -> &[[f64; 2]] {
        &self.bounds
    }

    /// The order constraints between ratios.
    pub fn order(&self) -> &[OrderConstraint] {
        &self.order
    }

    /// Ok if r has one finite value per ratio, each inside its bounds, the order constraints hold
    /// and G(r) is invertible. Otherwise the first violation found, in that order, e.g.
    /// `r2 = 9.5 is outside [1, 9]` or `r3 <= r2 violated: r3 = 3, r2 = 2`.
    pub fn check_design(&self, r: &[f64]) -> Result<(), DesignError> {
        if r.len() != self.num_ratios() {
            return Err(DesignError::new(format!(
                "the design has {} ratios but the transmission has {}",
                r.len(),
                self.num_ratios()
            )));
        }
        if let Some(i) = r.iter().position(|v| !v.is_finite()) {
            return Err(DesignError::new(format!(
                "r{} = {} is not a finite number",
                i + 1,
                r[i]
            )));
        }
        for (i, (&value, &[lo, hi])) in r.iter().zip(&self.bounds).enumerate() {
            if !(lo..=hi).contains(&value) {
                return Err(DesignError::new(format!(
                    "r{} = {value} is outside [{lo}, {hi}]",
                    i + 1
                )));
            }
        }
        for constraint in &self.order {
            let (a, b) = (r[constraint.lower], r[constraint.upper]);
            if !constraint.holds(a, b) {
                return Err(DesignError::new(format!(
                    "{constraint} violated: r{} = {a}, r{} = {b}",
                    constraint.lower + 1,
                    constraint.upper + 1
                )));
            }
        }
        let singular_values = self.matrix(r).singular_values();
        let largest = singular_values.max();
        let smallest = singular_values.min();
        let invertible = smallest > self.dof as f64 * f64::EPSILON * largest;
        if !invertible {
            return Err(DesignError::new(format!(
                "G(r) is not invertible: smallest singular value {smallest} against largest {largest}"
            )));
        }
        Ok(())
    }

    /// G(r) (row = motor, column = joint). Does not check the design.
    ///
    /// # Panics
    /// If `r` has fewer values than the transmission has ratios (a programming error: designs
    /// from outside are checked with [`Transmission::check_design`] first).
    pub fn matrix(&self, r: &[f64]) -> DMatrix<f64> {
        assert!(
            r.len() >= self.num_ratios(),
            "Transmission::matrix: {} ratios given, {} needed",
            r.len(),
            self.num_ratios()
        );
        DMatrix::from_row_iterator(
            self.dof,
            self.dof,
            self.entries.iter().map(|entry| match *entry {
                Entry::Constant(value) => value,
                Entry::Ratio { index, sign } => sign * r[index],
            }),
        )
    }

    /// dG/dr_i for the 0-based ratio index i: constant, since G is affine in r (entries +-1 where
    /// r_i appears, 0 elsewhere; all zero for an index past the last ratio).
    pub fn matrix_derivative(&self, i: usize) -> DMatrix<f64> {
        DMatrix::from_row_iterator(
            self.dof,
            self.dof,
            self.entries.iter().map(|entry| match *entry {
                Entry::Ratio { index, sign } if index == i => sign,
                _ => 0.0,
            }),
        )
    }

    /// The coupling at a valid design: G(r) and its inverse, computed once.
    pub fn coupling(&self, r: &[f64]) -> Result<Coupling, DesignError> {
        self.check_design(r)?;
        let matrix = self.matrix(r);
        let inverse = matrix.clone().try_inverse().ok_or_else(|| {
            DesignError::new("G(r) is not invertible: its LU factorisation failed".to_owned())
        })?;
        Ok(Coupling { matrix, inverse })
    }
}

/// G at one design with its inverse: maps torques and speeds between motors and joints.
#[derive(Clone, Debug)]
pub struct Coupling {
    matrix: DMatrix<f64>,
    inverse: DMatrix<f64>,
}

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
    /// G (row = motor, column = joint).
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.matrix
    }

    /// G^-1.
    pub fn inverse(&self) -> &DMatrix<f64> {
        &self.inverse
    }

    /// Joint torques tau = G^T tau_u, N m.
    ///
    /// # Panics
    /// If the length is not the number of motors.
    pub fn joint_torques(&self, motor_torques: &[f64]) -> Vec<f64> {
        let tau_u = DVector::from_column_slice(motor_torques);
        (self.matrix.tr_mul(&tau_u)).as_slice().to_vec()
    }

    /// Motor torques tau_u = G^-T tau, N m.
    ///
    /// # Panics
    /// If the length is not the number of joints.
    pub fn motor_torques(&self, joint_torques: &[f64]) -> Vec<f64> {
        let tau = DVector::from_column_slice(joint_torques);
        (self.inverse.tr_mul(&tau)).as_slice().to_vec()
    }

    /// Motor speeds qd_u = G qd, rad/s.
    ///
    /// # Panics
    /// If the length is not the number of joints.
    pub fn motor_speeds(&self, joint_speeds: &[f64]) -> Vec<f64> {
        let qd = DVector::from_column_slice(joint_speeds);
        (&self.matrix * qd).as_slice().to_vec()
    }

    /// Joint torque limits (N m) of the joint-space problem for motor limits |tau_u| <= torque_limit:
    /// - `Paper`: G^T tau_min .. G^T tau_max elementwise with tau_min/max = -+torque_limit. Where a
    ///   column of G sums to a negative number the two values come out reversed; each element's
    ///   box is then taken from the smaller to the larger.
    /// - `Interval`: |tau_i| <= sum_j |G_ji| torque_limit, the smallest box holding every reachable tau.
    /// - `Exact`: |G^-T tau| <= torque_limit, row by row.
    pub fn torque_limits(&self, mode: LimitMode, torque_limit: f64) -> JointLimits {
        match mode {
            LimitMode::Paper => {
                let ones = DVector::from_element(self.matrix.nrows(), torque_limit);
                let upper = self.matrix.tr_mul(&ones);
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(&self.matrix.transpose(), torque_limit),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.inverse.transpose(),
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
                let ones = DVector::from_element(self.inverse.ncols(), speed_limit);
                let upper = &self.inverse * ones;
                ordered_box(-&upper, upper)
            }
            LimitMode::Interval => symmetric_box(&self.inverse, speed_limit),
            LimitMode::Exact => JointLimits::Linear {
                matrix: self.matrix.clone(),
                limit: speed_limit,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::Task;
    use std::path::Path;

    fn pick_place() -> Task {
        Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json"))
            .unwrap()
    }

    fn belt_arm() -> Transmission {
        Transmission::from_spec(&pick_place().transmission).unwrap()
    }

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

    /// A small deterministic generator of values in [-1, 1) for the brute-force checks.
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    #[test]
    fn structure_follows_the_task_file() {
        let t = belt_arm();
        assert_eq!((t.dof(), t.num_ratios()), (4, 4));
        assert_eq!(t.original(), &[6.0, 3.0, 1.0, 1.0]);
        assert_eq!(t.bounds()[2], [1.0, 3.0]);
        let order: Vec<String> = t.order().iter().map(|c| c.to_string()).collect();
        assert_eq!(order, ["r3 <= r2", "r2 < r1"]);
        let g = t.matrix(&[6.0, 3.0, 1.5, 2.0]);
        let expected = DMatrix::from_row_slice(
            4,
            4,
            &[
                6.0, 0.0, 0.0, 0.0, //
                3.0, 3.0, 0.0, 0.0, //
                1.0, 1.5, 2.0, 2.0, //
                1.0, 1.5, 2.0, -2.0,
            ],
        );
        assert_eq!(g, expected);
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
        let mut rng = Lcg(7);
        for r in [[6.0, 3.0, 1.0, 1.0], [8.2, 4.1, 2.7, 1.3]] {
            let coupling = t.coupling(&r).unwrap();
            let (tl, wl) = (1.7, 100.0);
            let torque = coupling.torque_limits(LimitMode::Exact, tl);
            let torque_box = coupling.torque_limits(LimitMode::Interval, tl);
            let speed = coupling.speed_limits(LimitMode::Exact, wl);
            let speed_box = coupling.speed_limits(LimitMode::Interval, wl);
            for _ in 0..200 {
                // Motor torques inside the box reach joint torques inside the polytope and back.
                let tau_u: Vec<f64> = (0..4).map(|_| tl * rng.next()).collect();
                let tau = coupling.joint_torques(&tau_u);
                assert!(torque.contains(&tau, 1e-12) && torque_box.contains(&tau, 1e-12));
                let back = coupling.motor_torques(&tau);
                assert!(back.iter().zip(&tau_u).all(|(a, b)| (a - b).abs() < 1e-12));
                // Pushing one motor past its limit leaves the polytope.
                let mut outside = tau_u.clone();
                outside[((rng.next() + 1.0) * 2.0) as usize % 4] = 1.01 * tl;
                assert!(!torque.contains(&coupling.joint_torques(&outside), 1e-12));
                // Likewise for speeds: qd = G^-1 qd_u.
                let w: Vec<f64> = (0..4).map(|_| wl * rng.next()).collect();
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
    fn coupling_inverse_and_linear_matrices() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let identity = coupling.matrix() * coupling.inverse();
        assert!((identity - DMatrix::identity(4, 4)).norm() < 1e-14);
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

    #[test]
    fn design_checks_name_the_ratio_or_constraint() {
        let t = belt_arm();
        assert_eq!(t.check_design(&[6.0, 3.0, 1.0, 1.0]), Ok(()));
        assert_eq!(t.check_design(&[9.0, 3.0, 3.0, 3.0]), Ok(()));
        let message = |r: &[f64]| t.check_design(r).unwrap_err().to_string();
        assert_eq!(message(&[9.0, 9.5, 1.0, 1.0]), "r2 = 9.5 is outside [1, 9]");
        assert_eq!(message(&[6.0, 3.0, 1.0, 0.5]), "r4 = 0.5 is outside [1, 3]");
        assert_eq!(
            message(&[6.0, 2.0, 3.0, 1.0]),
            "r3 <= r2 violated: r3 = 3, r2 = 2"
        );
        assert_eq!(
            message(&[6.0, 6.0, 1.0, 1.0]),
            "r2 < r1 violated: r2 = 6, r1 = 6"
        );
        assert_eq!(t.check_design(&[6.0, 3.0, 3.0, 1.0]), Ok(()));
        assert_eq!(
            message(&[f64::NAN, 3.0, 1.0, 1.0]),
            "r1 = NaN is not a finite number"
        );
        assert_eq!(
            message(&[6.0, 3.0, f64::INFINITY, 1.0]),
            "r3 = inf is not a finite number"
        );
        assert_eq!(
            message(&[6.0, 3.0, 1.0]),
            "the design has 3 ratios but the transmission has 4"
        );
        assert!(t.coupling(&[6.0, 9.5, 1.0, 1.0]).is_err());

        let singular = TransmissionSpec {
            matrix: vec![
                vec![MatrixEntry::Ratio("r1".into()), MatrixEntry::Constant(1.0)],
                vec![MatrixEntry::Constant(1.0), MatrixEntry::Constant(1.0)],
            ],
            original: vec![2.0],
            bounds: vec![[0.5, 2.0]],
            order: vec![],
        };
        let t = Transmission::from_spec(&singular).unwrap();
        assert_eq!(t.check_design(&[2.0]), Ok(()));
        let error = t.coupling(&[1.0]).unwrap_err().to_string();
        assert!(error.starts_with("G(r) is not invertible"), "{error}");
    }

    #[test]
    fn matrix_derivative_matches_finite_differences() {
        let t = belt_arm();
        let r = [7.3, 4.4, 2.1, 1.7];
        let h = 1e-6;
        for i in 0..t.num_ratios() {
            let (mut plus, mut minus) = (r, r);
            plus[i] += h;
            minus[i] -= h;
            let fd = (t.matrix(&plus) - t.matrix(&minus)) / (2.0 * h);
            assert!((fd - t.matrix_derivative(i)).amax() < 1e-8, "ratio {i}");
        }
        assert_eq!(t.matrix_derivative(3)[(3, 3)], -1.0);
        assert_eq!(t.matrix_derivative(4), DMatrix::zeros(4, 4));
    }

    #[test]
    fn spec_errors_name_the_field() {
        let good = pick_place().transmission;
        type Change = Box<dyn Fn(&mut TransmissionSpec)>;
        let cases: Vec<(Change, &str)> = vec![
            (
                Box::new(|s| s.matrix[2][1] = MatrixEntry::Ratio("r5".into())),
                "transmission.matrix[2][1]",
            ),
            (
                Box::new(|s| s.matrix[0][0] = MatrixEntry::Ratio("x1".into())),
                "transmission.matrix[0][0]",
            ),
            (
                Box::new(|s| s.matrix[3][3] = MatrixEntry::Ratio("-r0".into())),
                "transmission.matrix[3][3]",
            ),
            (
                Box::new(|s| s.matrix[1][0] = MatrixEntry::Constant(f64::NAN)),
                "transmission.matrix[1][0]",
            ),
            (
                Box::new(|s| {
                    s.matrix[1].pop();
                }),
                "transmission.matrix[1]",
            ),
            (
                Box::new(|s| s.matrix.clear()),
                "transmission.matrix is empty",
            ),
            (Box::new(|s| s.original.push(1.0)), "transmission.original"),
            (
                Box::new(|s| s.original[2] = f64::NAN),
                "transmission.original[2]",
            ),
            (
                Box::new(|s| s.bounds[1] = [9.0, 1.0]),
                "transmission.bounds[1]",
            ),
            (
                Box::new(|s| s.order[1] = "r2 >= r1".into()),
                "transmission.order[1]",
            ),
            (
                Box::new(|s| s.order[0] = "r3 <= r5".into()),
                "transmission.order[0]",
            ),
            (
                Box::new(|s| s.order[0] = "r3 <= r2 <= r1".into()),
                "transmission.order[0]",
            ),
            (Box::new(|s| s.order[0] = "r3 < r3".into()), "itself"),
        ];
        for (change, field) in cases {
            let mut spec = good.clone();
            change(&mut spec);
            let error = Transmission::from_spec(&spec).unwrap_err();
            assert!(error.contains(field), "{error} should name {field}");
        }
        let mut spaced = good.clone();
        spaced.matrix[3][3] = MatrixEntry::Ratio(" -r4 ".into());
        spaced.order = vec![" r3<=r2".into(), "r2<r1 ".into()];
        let t = Transmission::from_spec(&spaced).unwrap();
        assert_eq!(
            t.matrix(&[6.0, 3.0, 1.0, 1.0]),
            belt_arm().matrix(&[6.0, 3.0, 1.0, 1.0])
        );
        assert_eq!(t.order(), belt_arm().order());
    }
}
