//! The checks of a task's numbers, each error naming its field: ranges with their limits and
//! reasons ([`OutOfRange`]), and fields that make no sense ([`FieldError`]).

use super::task::{CartesianBox, Motion, SoftInterval, Task, Weights};
use std::fmt;

/// Most intervals N of a motion: the problem has about 20 variables per interval and IPOPT's
/// factorisation grows faster than that; 5000 is 100 times the paper's 50.
pub const MAX_STEPS: usize = 5_000;

/// Longest motion, s: an hour, far beyond a pick-and-place of seconds.
pub const MAX_HORIZON_S: f64 = 3_600.0;

/// Heaviest payload, kg: a tonne, far beyond what a 4-DOF arm of this class can lift.
pub const MAX_PAYLOAD_KG: f64 = 1_000.0;

/// A value outside the range that its quantity allows; displays the rule and its reason.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutOfRange {
    /// A number of intervals N outside 1..=[`MAX_STEPS`].
    Steps,
    /// A duration outside (0, [`MAX_HORIZON_S`]] s.
    Horizon,
    /// A payload outside [0, [`MAX_PAYLOAD_KG`]] kg.
    Payload,
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OutOfRange::Steps => write!(f, "the number of intervals must be 1 to {MAX_STEPS} (100 times the paper's 50; beyond that IPOPT's memory and time grow out of reach)"),
            OutOfRange::Horizon => write!(f, "the duration must be a number of seconds > 0 and <= {MAX_HORIZON_S} (an hour, far beyond any pick-and-place)"),
            OutOfRange::Payload => write!(f, "the payload must be a mass >= 0 and <= {MAX_PAYLOAD_KG} kg (a tonne, far beyond what this class of arm lifts)"),
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
    fn new(field: impl Into<String>, problem: impl Into<String>) -> FieldError {
        FieldError {
            field: field.into(),
            problem: problem.into(),
        }
    }

    /// The error of a `value` of `field` outside its range.
    fn out_of_range(field: &str, value: impl fmt::Display, range: OutOfRange) -> FieldError {
        FieldError::new(field, format!(" = {value}: {range}"))
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
    if seconds.is_finite() && seconds > 0.0 && seconds <= MAX_HORIZON_S {
        Ok(())
    } else {
        Err(OutOfRange::Horizon)
    }
}

/// Checks a payload mass, kg.
pub fn check_payload(kg: f64) -> Result<(), OutOfRange> {
    if kg.is_finite() && (0.0..=MAX_PAYLOAD_KG).contains(&kg) {
        Ok(())
    } else {
        Err(OutOfRange::Payload)
    }
}

/// Ok if every value is finite; else an error naming `name[i]` of the first that is not.
fn check_finite(name: &str, values: &[f64]) -> Result<(), FieldError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(FieldError::new(
            format!("{name}[{i}]"),
            " is not a finite number",
        )),
        None => Ok(()),
    }
}

impl Motion {
    /// Checks the end points (finite, one value per joint each), the horizon and the steps.
    fn validate(&self) -> Result<(), FieldError> {
        check_finite("motion.start", &self.start)?;
        check_finite("motion.goal", &self.goal)?;
        if self.start.len() != self.goal.len() {
            return Err(FieldError::new(
                "motion.start",
                format!(
                    " has {} joints but motion.goal has {}",
                    self.start.len(),
                    self.goal.len()
                ),
            ));
        }
        check_horizon(self.horizon_s)
            .map_err(|why| FieldError::out_of_range("motion.horizon_s", self.horizon_s, why))?;
        check_steps(self.steps)
            .map_err(|why| FieldError::out_of_range("motion.steps", self.steps, why))
    }
}

impl Weights {
    /// Checks that every weight is finite and >= 0.
    fn validate(&self) -> Result<(), FieldError> {
        let weights = [
            ("weights.position", self.position),
            ("weights.velocity", self.velocity),
            ("weights.control", self.control),
        ];
        for (name, value) in weights {
            if !(value.is_finite() && value >= 0.0) {
                return Err(FieldError::new(name, format!(" = {value} must be >= 0")));
            }
        }
        Ok(())
    }
}

impl CartesianBox {
    /// Checks each given axis: a finite range with lower < upper and a finite weight >= 0.
    fn validate(&self) -> Result<(), FieldError> {
        let axes = [("x", &self.x), ("y", &self.y), ("z", &self.z)];
        for (axis, interval) in axes {
            let Some(SoftInterval {
                range: [lo, hi],
                weight,
            }) = interval
            else {
                continue;
            };
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(FieldError::new(
                    format!("cartesian_box.{axis}.range"),
                    format!(" [{lo}, {hi}] must be finite with lower < upper"),
                ));
            }
            if !(weight.is_finite() && *weight >= 0.0) {
                return Err(FieldError::new(
                    format!("cartesian_box.{axis}.weight"),
                    format!(" = {weight} must be >= 0"),
                ));
            }
        }
        Ok(())
    }
}

impl Task {
    /// Checks every number for sense; the error names the offending field.
    pub fn validate(&self) -> Result<(), FieldError> {
        check_finite("gravity", &self.gravity)?;
        check_finite("tcp.point", &self.tcp.point)?;
        check_finite("payload.at.point", &self.payload.at.point)?;
        check_payload(self.payload.mass_kg).map_err(|why| {
            FieldError::out_of_range("payload.mass_kg", self.payload.mass_kg, why)
        })?;
        self.motion.validate()?;
        self.weights.validate()?;
        self.cartesian_box.validate()?;
        for (name, value) in [
            ("motors.torque_limit_nm", self.motors.torque_limit_nm),
            ("motors.speed_limit_rad_s", self.motors.speed_limit_rad_s),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(FieldError::new(name, format!(" = {value} must be > 0")));
            }
        }
        Ok(())
    }
}
