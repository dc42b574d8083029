//! The payload capacity of one design against the duration of its motion: for each duration T,
//! the heaviest payload the design moves within T ([`payload_capacity`] of the task's motion
//! with its horizon fixed at T, as `codesign capacity --duration T` searches it).

use super::capacity::{payload_capacity, Capacity, CapacityError, CapacitySettings};
use codesign_core::model::task::{check_horizon, Horizon, LimitModes, OutOfRange, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, FormulationError, Space};
use codesign_core::solve::SolveSettings;
use codesign_core::text::number;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The capacity within one duration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TradeoffPoint {
    /// The fixed duration T of the motion, s.
    pub duration_s: f64,
    /// The capacity search at T, flattened into the point.
    #[serde(flatten)]
    pub capacity: Capacity,
}

/// What the problem of a trade-off is: the task (its horizon replaced at each duration), its
/// robot, the space and limit modes, and IPOPT's settings.
#[derive(Clone, Copy, Debug)]
pub struct TradeoffProblem<'a> {
    /// The task.
    pub task: &'a Task,
    /// Its robot.
    pub robot: &'a Robot,
    /// Joint or actuation space.
    pub space: Space,
    /// The limit modes.
    pub modes: LimitModes,
    /// IPOPT's settings of every probe.
    pub solve: &'a SolveSettings,
}

/// Why a trade-off could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum TradeoffError {
    /// No duration was given.
    NoDuration,
    /// A duration is outside the range a task accepts.
    Duration(f64, OutOfRange),
    /// The problem could not be formulated at a duration.
    Formulation(f64, FormulationError),
    /// A capacity search failed at a duration.
    Capacity(f64, CapacityError),
}

impl fmt::Display for TradeoffError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TradeoffError::NoDuration => write!(f, "a trade-off needs at least one duration"),
            TradeoffError::Duration(seconds, why) => {
                write!(f, "duration {}: {why}", number(*seconds))
            }
            TradeoffError::Formulation(seconds, error) => {
                write!(f, "at {} s: {error}", number(*seconds))
            }
            TradeoffError::Capacity(seconds, error) => {
                write!(f, "at {} s: {error}", number(*seconds))
            }
        }
    }
}

impl std::error::Error for TradeoffError {}

/// Checks the durations of a trade-off, s: at least one, each within the range a task accepts.
pub fn check_durations(durations: &[f64]) -> Result<(), TradeoffError> {
    if durations.is_empty() {
        return Err(TradeoffError::NoDuration);
    }
    for &seconds in durations {
        check_horizon(seconds).map_err(|why| TradeoffError::Duration(seconds, why))?;
    }
    Ok(())
}

/// The payload capacity of design `ratios` in `problem` at each of `durations` (s, in the order
/// given), each searched with `settings` on the task's motion with its horizon fixed at that
/// duration.
pub fn capacity_tradeoff(
    problem: &TradeoffProblem<'_>,
    ratios: &[f64],
    durations: &[f64],
    settings: &CapacitySettings,
) -> Result<Vec<TradeoffPoint>, TradeoffError> {
    check_durations(durations)?;
    durations
        .iter()
        .map(|&seconds| {
            let mut task = problem.task.clone();
            task.motion.horizon = Horizon::Fixed(seconds);
            let robot = problem.robot.clone();
            let formulation = Formulation::new(&task, robot, problem.space, problem.modes)
                .map_err(|e| TradeoffError::Formulation(seconds, e))?
                .with_hold_tolerance(problem.solve.constraint_tolerance());
            let capacity = payload_capacity(&formulation, problem.solve, ratios, settings)
                .map_err(|e| TradeoffError::Capacity(seconds, e))?;
            Ok(TradeoffPoint {
                duration_s: seconds,
                capacity,
            })
        })
        .collect()
}
