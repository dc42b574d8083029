//! The design space (docs/model.md, section 4): bounds on each ratio, order constraints between
//! ratios and the original design; the check of a design and the Euclidean projection onto the
//! space that every design method uses.

use super::linkage::LENGTH_RANGE_M;
use super::Transmission;
use crate::text::number;
use nalgebra::{DMatrix, DVector};
use std::fmt;

/// Margin that keeps a strict order constraint r_i < r_j strict in [`DesignSpace::halfspaces`]
/// and in the map from the unit box (`UnitMap`).
pub(super) const STRICT_MARGIN: f64 = 1e-6;

/// Margin that keeps a non-strict order constraint r_i <= r_j true after rounding in
/// [`DesignSpace::halfspaces`].
const ROUNDING_MARGIN: f64 = 1e-12;

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

/// Why a design r is not admissible; the message names the ratio or the constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignError {
    message: String,
}

impl DesignError {
    pub(super) fn new(message: String) -> DesignError {
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

/// A half-space a . r <= b of the design space (a dimensionless, one entry per ratio).
pub type HalfSpace = (Vec<f64>, f64);

/// The designs the task allows: a box of bounds cut by order constraints, with the original
/// design (all dimensionless ratios).
#[derive(Clone, Debug)]
pub struct DesignSpace {
    original: Vec<f64>,
    bounds: Vec<[f64; 2]>,
    order: Vec<OrderConstraint>,
}

impl DesignSpace {
    /// The space of `bounds` and `order` (indices below `bounds.len()`), with `original`.
    pub(super) fn new(
        original: Vec<f64>,
        bounds: Vec<[f64; 2]>,
        order: Vec<OrderConstraint>,
    ) -> DesignSpace {
        DesignSpace {
            original,
            bounds,
            order,
        }
    }

    /// Number of design ratios.
    pub fn num_ratios(&self) -> usize {
        self.bounds.len()
    }

    /// The original design r.
    pub fn original(&self) -> &[f64] {
        &self.original
    }

    /// Bounds [lower, upper] of each ratio.
    pub fn bounds(&self) -> &[[f64; 2]] {
        &self.bounds
    }

    /// The order constraints between ratios.
    pub fn order(&self) -> &[OrderConstraint] {
        &self.order
    }

    /// Ok if r has one finite value per ratio, each inside its bounds, and the order constraints
    /// hold. Otherwise the first violation found, in that order, e.g. `r2 = 9.5 is outside
    /// [1, 9]` or `r3 <= r2 violated: r3 = 3, r2 = 2`.
    pub fn check(&self, r: &[f64]) -> Result<(), DesignError> {
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
                number(r[i])
            )));
        }
        for (i, (&value, &[lo, hi])) in r.iter().zip(&self.bounds).enumerate() {
            if !(lo..=hi).contains(&value) {
                return Err(DesignError::new(format!(
                    "r{} = {} is outside [{}, {}]",
                    i + 1,
                    number(value),
                    number(lo),
                    number(hi)
                )));
            }
        }
        for constraint in &self.order {
            let (a, b) = (r[constraint.lower], r[constraint.upper]);
            if !constraint.holds(a, b) {
                return Err(DesignError::new(format!(
                    "{constraint} violated: r{} = {}, r{} = {}",
                    constraint.lower + 1,
                    number(a),
                    constraint.upper + 1,
                    number(b)
                )));
            }
        }
        Ok(())
    }

    /// The order constraints as half-spaces a . r <= b: r_i - r_j <= -margin, the margin
    /// keeping a strict constraint strict (1e-6) or a non-strict one true after rounding (1e-12).
    pub fn halfspaces(&self) -> Vec<HalfSpace> {
        let n = self.num_ratios();
        self.order
            .iter()
            .map(|c| {
                let mut a = vec![0.0; n];
                a[c.lower] = 1.0;
                a[c.upper] = -1.0;
                let margin = if c.strict {
                    STRICT_MARGIN
                } else {
                    ROUNDING_MARGIN
                };
                (a, -margin)
            })
            .collect()
    }

    /// All constraints as half-spaces a . r <= b: per ratio its upper then its lower bound, then
    /// the order constraints.
    fn constraints(&self) -> Vec<HalfSpace> {
        let n = self.num_ratios();
        let unit = |i: usize, sign: f64| {
            (0..n)
                .map(|j| if i == j { sign } else { 0.0 })
                .collect::<Vec<f64>>()
        };
        let mut all: Vec<HalfSpace> = Vec::new();
        for (i, &[lower, upper]) in self.bounds.iter().enumerate() {
            all.push((unit(i, 1.0), upper));
            all.push((unit(i, -1.0), -lower));
        }
        all.extend(self.halfspaces());
        all
    }

    /// The Euclidean projection of `x` onto the space (bounds and [`DesignSpace::halfspaces`]):
    /// the point satisfying the KKT conditions of min |p - x|^2 subject to the constraints, found
    /// by trying every set of at most n active constraints (a few hundred tiny solves for four
    /// ratios). The result is clamped to the bounds against rounding; `x` itself when it lies in
    /// the space.
    ///
    /// ```
    /// use codesign_core::model::task::Task;
    /// use codesign_core::transmission::Transmission;
    ///
    /// // The belt arm: bounds [1, 9]^2 x [1, 3]^2 and the order r3 <= r2 < r1.
    /// let spec = Task::built_in()?.transmission;
    /// let space = Transmission::from_spec(&spec)?.design_space().clone();
    /// assert!(space.check(&[2.0, 3.0, 1.0, 1.0]).is_err()); // r2 < r1 broken
    /// let p = space.project(&[2.0, 3.0, 1.0, 1.0]);
    /// assert!(space.check(&p).is_ok());
    /// assert!(p[1] <= p[0] && (p[0] + p[1] - 5.0).abs() < 1e-6); // the nearest point of r2 <= r1
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn project(&self, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        let constraints = self.constraints();
        let holds = |p: &[f64]| constraints.iter().all(|(a, b)| dot(a, p) <= b + 1e-12);
        if holds(x) {
            return x.to_vec();
        }
        let m = constraints.len();
        let mut best: Option<(f64, Vec<f64>)> = None;
        for mask in 1u32..(1 << m) {
            let active: Vec<usize> = (0..m).filter(|k| mask & (1 << k) != 0).collect();
            if active.len() > n {
                continue;
            }
            let Some(p) = active_set_point(&constraints, &active, x) else {
                continue;
            };
            if holds(&p) {
                let distance: f64 = p.iter().zip(x).map(|(a, b)| (a - b) * (a - b)).sum();
                if best.as_ref().is_none_or(|(d, _)| distance < *d) {
                    best = Some((distance, p));
                }
            }
        }
        let p = best.map_or_else(|| x.to_vec(), |(_, p)| p);
        p.iter()
            .zip(&self.bounds)
            .map(|(v, [lo, hi])| v.clamp(*lo, *hi))
            .collect()
    }
}

/// The closest point to `x` on the constraints `active` taken as equalities, p = x - A^T mu with
/// A p = b, i.e. (A A^T) mu = A x - b; None unless mu is finite and nonnegative (a KKT point).
fn active_set_point(constraints: &[HalfSpace], active: &[usize], x: &[f64]) -> Option<Vec<f64>> {
    let n = x.len();
    let a = DMatrix::from_fn(active.len(), n, |r, c| constraints[active[r]].0[c]);
    let b = DVector::from_iterator(active.len(), active.iter().map(|&k| constraints[k].1));
    let point = DVector::from_column_slice(x);
    let mu = (&a * a.transpose()).lu().solve(&(&a * &point - b))?;
    if mu.iter().any(|v| *v < -1e-12 || !v.is_finite()) {
        return None;
    }
    Some((point - a.transpose() * mu).iter().copied().collect())
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Transmission {
    /// Ok if r lies in the design space ([`DesignSpace::check`]), every length of a linkage
    /// that depends on r lies in [`LENGTH_RANGE_M`] and G(r) is invertible. Otherwise the first
    /// violation found, in that order, e.g. `r2 = 9.5 is outside [1, 9]`,
    /// `r3 <= r2 violated: r3 = 3, r2 = 2` or
    /// `transmission.matrix[1].linear.lead_m = 0.001*r2 = 1e-9 m is outside [1e-6, 100] m`.
    pub fn check_design(&self, r: &[f64]) -> Result<(), DesignError> {
        self.space.check(r)?;
        for row in &self.linkages {
            if let Some((field, written, value)) = row.linkage.design_length_outside(r) {
                let [low, high] = LENGTH_RANGE_M;
                return Err(DesignError::new(format!(
                    "transmission.matrix[{}].{}.{field} = {written} = {} m is outside [{}, {}] m, \
                     the lengths a linkage may have",
                    row.motor,
                    row.linkage.kind(),
                    number(value),
                    number(low),
                    number(high)
                )));
            }
        }
        if self.is_pose_dependent() {
            // G depends on the pose: `coupling_at` checks it where it is used.
            return Ok(());
        }
        invertible(&self.matrix(r), "G(r)")
    }
}

/// Ok where `matrix` (G, named `name` in the error) is finite and well enough conditioned to
/// invert: its smallest singular value above n eps times its largest. A matrix with an entry
/// that is not finite is refused before its singular values are sought.
pub(super) fn invertible(matrix: &DMatrix<f64>, name: &str) -> Result<(), DesignError> {
    if let Some(index) = matrix.iter().position(|v| !v.is_finite()) {
        let (row, column) = (index % matrix.nrows(), index / matrix.nrows());
        return Err(DesignError::new(format!(
            "{name} is not finite: its entry ({row}, {column}) is {}",
            matrix[(row, column)]
        )));
    }
    let singular_values = matrix.singular_values();
    let largest = singular_values.max();
    let smallest = singular_values.min();
    if smallest > matrix.nrows() as f64 * f64::EPSILON * largest {
        return Ok(());
    }
    Err(DesignError::new(format!(
        "{name} is not invertible: smallest singular value {} against largest {}",
        number(smallest),
        number(largest)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::{MatrixEntry, MatrixRow, TransmissionSpec};
    use crate::transmission::fixtures::belt_arm;
    use crate::transmission::Coupling;

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
                MatrixRow::Entries(vec![
                    MatrixEntry::Ratio("r1".into()),
                    MatrixEntry::Constant(1.0),
                ]),
                MatrixRow::Entries(vec![MatrixEntry::Constant(1.0), MatrixEntry::Constant(1.0)]),
            ],
            original: vec![2.0],
            bounds: vec![[0.5, 2.0]],
            order: vec![],
        };
        let t = Transmission::from_spec(&singular).unwrap();
        assert_eq!(t.check_design(&[2.0]), Ok(()));
        assert_eq!(t.design_space().check(&[1.0]), Ok(()));
        let error = t.coupling(&[1.0]).unwrap_err().to_string();
        assert!(error.starts_with("G(r) is not invertible"), "{error}");
    }

    /// A lead that depends on the design is held to a micrometre to a hundred metres at each
    /// design, naming its field: a design whose lead is 1e-300 m (within the bounds) is invalid,
    /// not a panic of the SVD of an infinite G(q).
    #[test]
    fn a_design_whose_linkage_length_leaves_its_range_is_invalid() {
        let mut task = crate::testing::posed_task(crate::testing::SCREW_ROW);
        task.transmission.bounds[1] = [1e-300, 40.0];
        let dynamics = crate::dynamics::Dynamics::new(
            crate::model::Robot::load(&task).expect("the planar robot loads"),
        );
        let t = Transmission::on_chain(&task.transmission, &dynamics).unwrap();
        let start = task.motion.start.clone();
        assert!(t
            .coupling_at(&[50.0, 12.0], (&dynamics, &start), "the start")
            .is_ok());
        for r2 in [1e-297, 1e-4] {
            let error = t
                .coupling_at(&[50.0, r2], (&dynamics, &start), "the start")
                .unwrap_err()
                .to_string();
            let named = "transmission.matrix[1].linear.lead_m = 0.001*r2 = ";
            assert!(error.starts_with(named), "{error}");
            assert!(error.ends_with(" m is outside [1e-6, 100] m, the lengths a linkage may have"));
        }
    }

    /// A matrix with an entry that is not finite is refused before its SVD, which would panic.
    #[test]
    fn a_matrix_that_is_not_finite_is_not_invertible() {
        let mut matrix = DMatrix::identity(2, 2);
        matrix[(1, 0)] = f64::INFINITY;
        let error = invertible(&matrix, "G(q) at the start")
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "G(q) at the start is not finite: its entry (1, 0) is inf"
        );
        matrix[(1, 0)] = f64::NAN;
        assert!(invertible(&matrix, "G").is_err());
        assert!(Coupling::new(matrix).is_none());
    }

    #[test]
    fn order_constraints_become_halfspaces_with_margins() {
        let space = belt_arm().design_space().clone();
        assert_eq!(
            space.halfspaces(),
            [
                (vec![0.0, -1.0, 1.0, 0.0], -ROUNDING_MARGIN),
                (vec![-1.0, 1.0, 0.0, 0.0], -STRICT_MARGIN)
            ]
        );
    }

    #[test]
    fn projection_lands_in_the_design_space_and_keeps_inner_points() {
        let t = belt_arm();
        let space = t.design_space();
        for point in [
            [12.0, 10.0, 5.0, 0.0],
            [2.0, 8.0, 2.5, 2.0],
            [5.0, 4.0, 3.0, 1.0],
            [0.0, 0.0, 0.0, 0.0],
        ] {
            let projected = space.project(&point);
            assert!(
                t.check_design(&projected).is_ok(),
                "{point:?} -> {projected:?}"
            );
            // Projecting twice changes nothing.
            let again = space.project(&projected);
            assert!(again
                .iter()
                .zip(&projected)
                .all(|(a, b)| (a - b).abs() < 1e-10));
        }
        let inside = [7.0, 4.0, 2.0, 2.0];
        assert_eq!(space.project(&inside), inside.to_vec());
        // (2, 8, ., .) violates r2 < r1: the projection meets at the middle, 5.
        let p = space.project(&[2.0, 8.0, 1.0, 1.0]);
        assert!(
            (p[0] - 5.0).abs() < 1e-5 && (p[1] - 5.0).abs() < 1e-5,
            "{p:?}"
        );
    }
}
