//! The least duration T* of one design's motion against the payload, the other side of the
//! trade-off of [`super::tradeoff`]: at each payload, in increasing order, the task's pure
//! minimum-time problem ([`Task::minimum_time`]: a free horizon in [T_min, T_max], J = T)
//! solved under the one rule of feasibility from the standard guess, as `codesign solve` of that
//! task solves it. The first payload with no trajectory within T_max ends the curve: the design
//! cannot move it in the longest duration allowed.

use super::tradeoff::TradeoffProblem;
use codesign_core::model::task::{check_payload, OutOfRange};
use codesign_core::problem::{Formulation, FormulationError};
use codesign_core::solve::{solve_design, SolveError, TrajectoryResult};
use codesign_core::text::number;
use serde::{Deserialize, Serialize};
use std::fmt;

/// T* at one payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimePoint {
    /// The payload, kg.
    pub payload_kg: f64,
    /// Whether a trajectory within [T_min, T_max] was found (the one rule of feasibility).
    pub feasible: bool,
    /// The least duration T*, s (null where infeasible).
    pub minimum_time_s: Option<f64>,
    /// IPOPT's status of the solve that decided.
    pub status: String,
    /// IPOPT iterations of that solve.
    pub iterations: usize,
}

/// One design's T* against the payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeCurve {
    /// The design r.
    pub ratios: Vec<f64>,
    /// T* at each payload solved, in increasing payload, up to and including the first
    /// infeasible one.
    pub points: Vec<TimePoint>,
    /// The first payload the design cannot move within T_max, kg, where the curve ends (null:
    /// it moves every payload asked).
    pub ends_at_kg: Option<f64>,
}

/// Why a curve could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeCurveError {
    /// No payload was given.
    NoPayload,
    /// A payload is outside the range a task accepts.
    Payload(f64, OutOfRange),
    /// The payloads do not increase: the second is not above the first.
    Order(f64, f64),
    /// The problem could not be formulated at a payload.
    Formulation(f64, FormulationError),
    /// A solve could not run at a payload (an invalid design among them).
    Solve(f64, SolveError),
}

impl fmt::Display for TimeCurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TimeCurveError::NoPayload => write!(f, "T* against payload needs a payload"),
            TimeCurveError::Payload(kg, why) => write!(f, "payload {}: {why}", number(*kg)),
            TimeCurveError::Order(before, kg) => write!(
                f,
                "payload {} after {}: the payloads must increase",
                number(*kg),
                number(*before)
            ),
            TimeCurveError::Formulation(kg, error) => write!(f, "at {} kg: {error}", number(*kg)),
            TimeCurveError::Solve(kg, error) => write!(f, "at {} kg: {error}", number(*kg)),
        }
    }
}

impl std::error::Error for TimeCurveError {}

/// Checks the payloads of a curve, kg: at least one, each a payload a task accepts, increasing.
pub fn check_payloads(payloads: &[f64]) -> Result<(), TimeCurveError> {
    if payloads.is_empty() {
        return Err(TimeCurveError::NoPayload);
    }
    for &kg in payloads {
        check_payload(kg).map_err(|why| TimeCurveError::Payload(kg, why))?;
    }
    match payloads.windows(2).find(|pair| pair[1] <= pair[0]) {
        Some(pair) => Err(TimeCurveError::Order(pair[0], pair[1])),
        None => Ok(()),
    }
}

/// The pure minimum-time problem of `problem`'s task at `payload_kg`, its free horizon shortened,
/// where the solve settings ask it, through the task's own weights and box.
pub fn minimum_time_problem(
    problem: &TradeoffProblem<'_>,
    payload_kg: f64,
) -> Result<Formulation, FormulationError> {
    let mut source = problem.task.clone();
    source.payload.mass_kg = payload_kg;
    let robot = problem.robot.with_payload(payload_kg);
    let pure = Formulation::minimum_time_of(&source, robot, problem.space, problem.modes)?;
    Ok(pure.with_hold_tolerance(problem.solve.constraint_tolerance()))
}

/// T* of design `ratios` in `problem` at each of `payloads` (kg, increasing), each its
/// minimum-time problem solved from the standard guess; the curve ends at the first payload
/// with no trajectory within T_max.
pub fn minimum_time_curve(
    problem: &TradeoffProblem<'_>,
    ratios: &[f64],
    payloads: &[f64],
) -> Result<TimeCurve, TimeCurveError> {
    check_payloads(payloads)?;
    let mut points = Vec::new();
    for &kg in payloads {
        let formulation =
            minimum_time_problem(problem, kg).map_err(|e| TimeCurveError::Formulation(kg, e))?;
        let result = solve_design(&formulation, ratios, problem.solve)
            .map_err(|e| TimeCurveError::Solve(kg, e))?;
        let point = point(kg, &result);
        let feasible = point.feasible;
        points.push(point);
        if !feasible {
            return Ok(TimeCurve {
                ratios: ratios.to_vec(),
                points,
                ends_at_kg: Some(kg),
            });
        }
    }
    Ok(TimeCurve {
        ratios: ratios.to_vec(),
        points,
        ends_at_kg: None,
    })
}

/// The point of the solve `result` at `payload_kg`: T* its chosen horizon where feasible.
fn point(payload_kg: f64, result: &TrajectoryResult) -> TimePoint {
    TimePoint {
        payload_kg,
        feasible: result.feasible,
        minimum_time_s: result.horizon_s.filter(|_| result.feasible),
        status: result.status.clone(),
        iterations: result.iterations,
    }
}
