//! The checks of a task's numbers, each error naming its field (the ranges and the errors are
//! `super::ranges`'s).

use super::ranges::{
    check_finite, check_norm, check_payload, check_steps, Bounds, FieldError, MAX_GRAVITY,
    MAX_POINT_M,
};
use super::task::{CartesianBox, Motion, SoftInterval, Task, Weights};

impl Motion {
    /// Checks the end points (finite, one value per joint each), the horizon and the steps;
    /// `name` names the motion in errors (`motion`, `motions[1]`).
    pub(super) fn validate(&self, name: &str) -> Result<(), FieldError> {
        check_finite(&format!("{name}.start"), &self.start)?;
        self.goal.validate(&format!("{name}.goal"))?;
        if let Some(goal) = self
            .goal
            .joints()
            .filter(|goal| goal.len() != self.start.len())
        {
            return Err(FieldError::new(
                format!("{name}.start"),
                format!(
                    " has {} joints but {name}.goal has {}",
                    self.start.len(),
                    goal.len()
                ),
            ));
        }
        self.horizon.validate(&format!("{name}.horizon_s"))?;
        check_steps(self.steps).map_err(|why| {
            FieldError::out_of_range(&format!("{name}.steps"), self.steps as f64, why)
        })?;
        self.validate_targets(name)
    }
}

impl Weights {
    /// Checks that every weight is 0 or within [`Bounds::weight`].
    fn validate(&self) -> Result<(), FieldError> {
        Bounds::weight("per rad^2").check("weights.position", self.position)?;
        Bounds::weight("per (rad/s)^2").check("weights.velocity", self.velocity)?;
        Bounds::weight("per (N m)^2").check("weights.control", self.control)?;
        Bounds::weight("per s").check("weights.time", self.time)
    }
}

impl CartesianBox {
    /// Checks each given axis: a finite range with lower < upper and a weight within
    /// [`Bounds::weight`].
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
            Bounds::weight("per m^2").check(&format!("cartesian_box.{axis}.weight"), *weight)?;
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
        let far = "m from its link: beyond any robot's reach";
        check_norm(
            "gravity",
            &self.gravity,
            MAX_GRAVITY,
            "m/s^2: a hundred times the Earth's",
        )?;
        check_norm("tcp.point", &self.tcp.point, MAX_POINT_M, far)?;
        check_norm("payload.at.point", &self.payload.at.point, MAX_POINT_M, far)?;
        check_payload(self.payload.mass_kg).map_err(|why| {
            FieldError::out_of_range("payload.mass_kg", self.payload.mass_kg, why)
        })?;
        self.motion.validate("motion")?;
        self.validate_motions()?;
        self.weights.validate()?;
        self.cartesian_box.validate()?;
        super::carried::validate(&self.carried, self.transmission.original.len())?;
        self.motors.validate(self.transmission.matrix.len())
    }
}
