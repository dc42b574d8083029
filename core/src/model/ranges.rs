//! The ranges a task's numbers must lie in, with their limits and reasons ([`OutOfRange`]), a
//! bounded number's rule ([`Bounds`]), and the error that names a field making no sense
//! ([`FieldError`]). Nothing here reads a task: its checks are `super::validate`.

use crate::text::number;
use std::fmt;

/// Most intervals N of a motion: the problem has about 20 variables per interval and IPOPT's
/// factorisation grows faster than that; 5000 is 100 times the paper's 50.
pub const MAX_STEPS: usize = 5_000;

/// Longest motion, s: an hour, far beyond a pick-and-place of seconds.
pub const MAX_HORIZON_S: f64 = 3_600.0;

/// Shortest motion, s: a hundredth of a second. Shorter motions ask for accelerations no motor
/// gives, and IPOPT's numbers overflow on them.
pub const MIN_HORIZON_S: f64 = 0.01;

/// Largest gravity, m/s^2: a hundred times the Earth's, beyond any place a robot works.
pub const MAX_GRAVITY: f64 = 1_000.0;

/// Farthest a task's point (the TCP, the payload) may lie from its link's origin, m.
pub const MAX_POINT_M: f64 = 100.0;

/// The lightest payload other than none, kg: a milligram (a payload of 1e-320 kg named
/// result files hundreds of bytes long and printed as 320 digits).
pub const MIN_PAYLOAD_KG: f64 = 1e-6;

/// Heaviest payload, kg: a tonne, far beyond what a 4-DOF arm of this class can lift.
pub const MAX_PAYLOAD_KG: f64 = 1_000.0;

/// Largest weight of the cost (`weights.*`, `cartesian_box.*.weight`): a million, a thousand
/// times the largest the examples use; with larger ones J overflows with the motion's numbers.
pub const MAX_WEIGHT: f64 = 1e6;

/// The range of a non-negative quantity of a task: 0 (where `zero`) or from `least` to `most`,
/// in `unit`, for the reason `why`. The least is at least the least normal f64, 2.2e-308: a
/// subnormal number has lost its precision, and what divides by it overflows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Whether 0 is allowed.
    pub zero: bool,
    /// The smallest positive value.
    pub least: f64,
    /// The largest value.
    pub most: f64,
    /// The unit, e.g. `N m` (empty for none).
    pub unit: &'static str,
    /// Why the limits.
    pub why: &'static str,
}

impl Bounds {
    /// The bounds of a cost weight: 0 to [`MAX_WEIGHT`], in `unit`.
    pub const fn weight(unit: &'static str) -> Bounds {
        Bounds {
            zero: true,
            least: f64::MIN_POSITIVE,
            most: MAX_WEIGHT,
            unit,
            why: "a thousand times the largest weight of the examples; with larger ones J \
                  overflows, and positive ones below 2.2e-308 are subnormal",
        }
    }

    /// What is wrong with `value`, as it follows the field's name (` = -1 must be >= 0 and
    /// <= ...`); None where it is within the bounds.
    fn problem(&self, value: f64) -> Option<String> {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        let low = if self.zero { ">= 0" } else { "> 0" };
        let signed = value > 0.0 || (self.zero && value == 0.0);
        if !(value.is_finite() && signed && value <= self.most) {
            let most = number(self.most);
            return Some(format!(
                " = {} must be {low} and <= {most}{unit} ({})",
                number(value),
                self.why
            ));
        }
        if value != 0.0 && value < self.least {
            let zero = if self.zero { "0 or " } else { "" };
            let least = number(self.least);
            return Some(format!(
                " = {} must be {zero}at least {least}{unit} ({})",
                number(value),
                self.why
            ));
        }
        None
    }

    /// Checks `value` of `field`.
    pub fn check(&self, field: &str, value: f64) -> Result<(), FieldError> {
        match self.problem(value) {
            Some(problem) => Err(FieldError::new(field, problem)),
            None => Ok(()),
        }
    }
}

/// A value outside the range that its quantity allows; displays the rule and its reason.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutOfRange {
    /// A number of intervals N outside 1..=[`MAX_STEPS`].
    Steps,
    /// A duration outside [[`MIN_HORIZON_S`], [`MAX_HORIZON_S`]] s.
    Horizon,
    /// A payload outside [0, [`MAX_PAYLOAD_KG`]] kg.
    Payload,
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OutOfRange::Steps => write!(f, "the number of intervals must be 1 to {MAX_STEPS} (100 times the paper's 50; beyond that IPOPT's memory and time grow out of reach)"),
            OutOfRange::Horizon => write!(f, "the duration must be a number of seconds >= {MIN_HORIZON_S} and <= {MAX_HORIZON_S} (from a hundredth of a second, below which no motor makes the motion and IPOPT's numbers overflow, to an hour, far beyond any pick-and-place)"),
            OutOfRange::Payload => write!(f, "the payload must be 0 or a mass from {MIN_PAYLOAD_KG} kg (a milligram, below what any scale resolves) to {MAX_PAYLOAD_KG} kg (a tonne, far beyond what this class of arm lifts)"),
        }
    }
}

impl std::error::Error for OutOfRange {}

/// A field of a task whose value makes no sense.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldError {
    /// The field, e.g. `motion.horizon_s` or `motion.start[2]`.
    pub field: String,
    /// What is wrong, as it follows the field's name (e.g. ` = -1 must be >= 0`).
    pub problem: String,
}

impl FieldError {
    pub(super) fn new(field: impl Into<String>, problem: impl Into<String>) -> FieldError {
        FieldError {
            field: field.into(),
            problem: problem.into(),
        }
    }

    /// The error of a `value` of `field` outside its range.
    pub(super) fn out_of_range(field: &str, value: f64, range: OutOfRange) -> FieldError {
        FieldError::new(field, format!(" = {}: {range}", number(value)))
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.field, self.problem)
    }
}

impl std::error::Error for FieldError {}

/// Checks a number of intervals N.
pub fn check_steps(steps: usize) -> Result<(), OutOfRange> {
    if (1..=MAX_STEPS).contains(&steps) {
        Ok(())
    } else {
        Err(OutOfRange::Steps)
    }
}

/// Checks a motion's duration, s.
pub fn check_horizon(seconds: f64) -> Result<(), OutOfRange> {
    if (MIN_HORIZON_S..=MAX_HORIZON_S).contains(&seconds) {
        Ok(())
    } else {
        Err(OutOfRange::Horizon)
    }
}

/// Checks a payload mass, kg.
pub fn check_payload(kg: f64) -> Result<(), OutOfRange> {
    if kg == 0.0 || (MIN_PAYLOAD_KG..=MAX_PAYLOAD_KG).contains(&kg) {
        Ok(())
    } else {
        Err(OutOfRange::Payload)
    }
}

/// Ok if the vector's length is at most `largest`; else an error naming `name` with `why`.
pub(super) fn check_norm(
    name: &str,
    values: &[f64; 3],
    largest: f64,
    why: &str,
) -> Result<(), FieldError> {
    let norm = values.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm <= largest {
        Ok(())
    } else {
        Err(FieldError::new(
            name,
            format!(" = {values:?} is longer than {largest} ({why})"),
        ))
    }
}

/// Ok if every value is finite; else an error naming `name[i]` of the first that is not.
pub(super) fn check_finite(name: &str, values: &[f64]) -> Result<(), FieldError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(FieldError::new(
            format!("{name}[{i}]"),
            " is not a finite number",
        )),
        None => Ok(()),
    }
}
