//! What co-design minimises: the cost at one payload, the mean cost over several, the weighted
//! costs of a task's several motions, minus the payload capacity, or the least duration; and why
//! the problems of an objective could not be built. How a design is solved for it is
//! `super::fitness`.

use crate::design::capacity::CapacitySettings;
use codesign_core::model::task::Task;
use codesign_core::model::ModelError;
use codesign_core::problem::{Formulation, FormulationError};
use serde::{Deserialize, Serialize};
use std::fmt;

/// What co-design minimises.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", tag = "kind")]
pub enum Objective {
    /// The optimal trajectory cost J at the task's payload (the paper's criterion).
    #[default]
    Cost,
    /// Minus the payload capacity, kg: the design that lifts the most.
    Capacity(CapacitySettings),
    /// The mean of the optimal costs over several payloads: one design for the whole range.
    Range(PayloadRange),
    /// The least copper losses of the motors over the motion, J, at the task's payload: the
    /// trajectory problem minimises them instead of J (docs/model.md, section 7), from the
    /// task's `motors.torque_constant_nm_per_a` and `motors.resistance_ohm`.
    Energy,
    /// The least duration T* of the task's motion, s: each design solves the task's pure
    /// minimum-time problem ([`Task::minimum_time`]: a free horizon, J = T), so J* = T*.
    Time,
}

impl Objective {
    /// The task whose trajectory problem the objective solves per design: the task itself, or
    /// its pure minimum-time problem for [`Objective::Time`].
    pub fn task(&self, task: &Task) -> Task {
        match self {
            Objective::Time => task.minimum_time(),
            _ => task.clone(),
        }
    }

    /// `formulation`, of [`Objective::task`]`(source)`: for [`Objective::Time`], its free
    /// horizon shortened through fixed-horizon problems shaped by `source`'s weights and box
    /// (where the solve settings ask it, `solver.free_horizon`), else as it is.
    pub fn shape(&self, formulation: Formulation, source: &Task) -> Formulation {
        match self {
            Objective::Time => formulation.shaped_by(source),
            _ => formulation,
        }
    }
}

/// The payloads of [`Objective::Range`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PayloadRange {
    /// The payloads, kg, in the order they are solved (the mean sums in this order).
    pub payloads_kg: Vec<f64>,
}

/// Why the formulations of an objective could not be built.
#[derive(Clone, Debug, PartialEq)]
pub enum ScoreError {
    /// The robot model could not be loaded.
    Model(ModelError),
    /// The trajectory problem could not be formulated (at some payload, or of some motion).
    Formulation(FormulationError),
    /// The objective is of one motion (`capacity`, `range`), and the task lists several.
    SeveralMotions {
        /// The objective's name.
        objective: &'static str,
        /// The task's motions.
        motions: usize,
    },
}

impl fmt::Display for ScoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScoreError::Model(error) => error.fmt(f),
            ScoreError::Formulation(error) => error.fmt(f),
            ScoreError::SeveralMotions { objective, motions } => write!(
                f,
                "the {objective} objective is of one motion, and the task lists {motions} \
                 motions (`motions`); co-design several motions with the cost, energy or time \
                 objective"
            ),
        }
    }
}

impl std::error::Error for ScoreError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ScoreError::Model(error) => Some(error),
            ScoreError::Formulation(error) => Some(error),
            ScoreError::SeveralMotions { .. } => None,
        }
    }
}

impl From<ModelError> for ScoreError {
    fn from(error: ModelError) -> ScoreError {
        ScoreError::Model(error)
    }
}

impl From<FormulationError> for ScoreError {
    fn from(error: FormulationError) -> ScoreError {
        ScoreError::Formulation(error)
    }
}

/// The error of an objective of one motion, `objective`, for `task`, which lists several.
pub(super) fn several(objective: &'static str, task: &Task) -> ScoreError {
    ScoreError::SeveralMotions {
        objective,
        motions: task.motions.len(),
    }
}
