//! Scoring one design (docs/model.md, section 10): the one place where a design is validated,
//! solved and judged, and where the judgement and the run's [`Penalty`] become the fitness that
//! CMA-ES and the gradient method compare.
//!
//! A [`Verdict`] says what a design is: feasible with its cost, infeasible by a shortfall,
//! invalid at a distance from the design space, or not judged (a solver error, a failed worker).
//! [`Verdict::fitness`] is the one rule turning it into a number; [`Evaluation`] is its record as
//! the evaluation log and the worker protocol write it. Its modules: `objective` (what co-design
//! minimises), `fitness` (what is solved per design: the cost, the payload capacity, elastic
//! solves for a graded penalty), `solves` (one solve judged), `motions` (one design over a
//! task's several motions, or over a range's payloads, their mean), `descent` and `merit` (a
//! design scored for a gradient descent), `record` (the evaluation record and its status
//! texts).

mod descent;
mod fitness;
mod merit;
#[cfg(test)]
mod motion_tests;
mod motions;
mod objective;
mod plausible;
mod record;
mod solves;
#[cfg(test)]
mod tests;

pub use descent::Descent;
pub use fitness::{anchor_solution, Fitness};
pub use merit::Merit;
pub use motions::{Aggregate, MotionProblem, Motions};
pub use objective::{Objective, PayloadRange, ScoreError};
pub use plausible::MAX_REASON_BYTES;
pub use record::{Evaluation, SolveStatus, Status};

use super::penalty::Penalty;
use codesign_core::ipopt::Solution;
use codesign_core::problem::{Formulation, StaticHold};
use codesign_core::solve::{solve_design_from, SolveError, SolveSettings, TrajectoryResult};
use codesign_core::transmission::{DesignError, Transmission};

/// What scoring one design found.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// The design is valid and its trajectory problem feasible (at every payload).
    Feasible {
        /// The objective's value: the optimal cost J, the mean J over a range, or minus the
        /// payload capacity, kg.
        cost: f64,
        /// What the solves said.
        status: SolveStatus,
    },
    /// The design is valid but a trajectory problem of it has no feasible solution.
    Infeasible {
        /// How far it is from feasible, motor-seconds (s): the torque deficit of the elastic
        /// solves plus the static hold's deficit times the horizon, over the torque limit, plus
        /// the speed excess over the speed limit; a design not solved because its motors
        /// cannot hold the load at rest ([`SolveStatus::StaticHoldFailed`]) measures only the
        /// hold's part.
        shortfall: f64,
        /// Why, in words.
        reason: String,
        /// What the solves said.
        status: SolveStatus,
    },
    /// The design is outside the design space (bounds, order constraints) or its G(r) is
    /// singular: nothing was solved.
    Invalid {
        /// Its Euclidean distance from the design space (dimensionless, as the ratios): 0 when
        /// only G(r) is singular, infinite when the number of ratios is wrong.
        distance: f64,
        /// The violation, e.g. `r2 = 9.5 is outside [1, 9]`.
        reason: String,
    },
    /// IPOPT could not run (an option rejected, a callback failed): the design was not judged.
    SolverError {
        /// The solver's complaint.
        message: String,
    },
    /// The worker evaluating the design crashed, hung or answered nonsense, twice: the design
    /// was not judged.
    WorkerFailed {
        /// What went wrong.
        message: String,
    },
}

impl Verdict {
    /// The fitness under `penalty`: the cost of a feasible design, else the penalty of an
    /// infeasible one (by its shortfall) or an invalid one (by its distance), or the base
    /// penalty when the design was not judged.
    pub fn fitness(&self, penalty: &Penalty) -> f64 {
        match self {
            Verdict::Feasible { cost, .. } => *cost,
            Verdict::Infeasible { shortfall, .. } => penalty.infeasible(*shortfall),
            Verdict::Invalid { distance, .. } => penalty.invalid(*distance),
            Verdict::SolverError { .. } | Verdict::WorkerFailed { .. } => penalty.base,
        }
    }

    /// Whether the design is valid and feasible.
    pub fn is_feasible(&self) -> bool {
        matches!(self, Verdict::Feasible { .. })
    }

    /// What decided the verdict, as the record names it.
    pub fn status(&self) -> Status {
        match self {
            Verdict::Feasible { status, .. } | Verdict::Infeasible { status, .. } => {
                Status::Solved(status.clone())
            }
            Verdict::Invalid { .. } => Status::InvalidDesign,
            Verdict::SolverError { .. } => Status::SolverError,
            Verdict::WorkerFailed { .. } => Status::WorkerFailed,
        }
    }

    /// Why the design was penalised (none when it is feasible).
    pub fn reason(&self) -> Option<&str> {
        match self {
            Verdict::Feasible { .. } => None,
            Verdict::Infeasible { reason, .. } | Verdict::Invalid { reason, .. } => Some(reason),
            Verdict::SolverError { message } | Verdict::WorkerFailed { message } => Some(message),
        }
    }

    /// The verdict with its reason prefixed by `label` (`at 1 kg`, `motion low`) and a colon.
    fn labelled(mut self, label: &str) -> Verdict {
        match &mut self {
            Verdict::Feasible { .. } => {}
            Verdict::Infeasible { reason, .. }
            | Verdict::Invalid { reason, .. }
            | Verdict::SolverError { message: reason }
            | Verdict::WorkerFailed { message: reason } => {
                *reason = format!("{label}: {reason}");
            }
        }
        self
    }
}

/// A verdict with the solver work behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct Score {
    /// What the design is.
    pub verdict: Verdict,
    /// IPOPT iterations over the evaluation's solves (0 when none ran).
    pub iterations: usize,
    /// Wall time of those solves, s.
    pub seconds: f64,
}

impl Score {
    /// A verdict reached without a solve.
    pub fn unsolved(verdict: Verdict) -> Score {
        Score {
            verdict,
            iterations: 0,
            seconds: 0.0,
        }
    }
}

/// Checks `ratios` against `transmission` (bounds, order constraints, G(r) invertible): the one
/// check of an evaluation, made before its solves. The invalid verdict when it fails.
pub fn validate(transmission: &Transmission, ratios: &[f64]) -> Result<(), Verdict> {
    transmission
        .check_design(ratios)
        .map_err(|error| invalid(transmission, ratios, &error))
}

/// The invalid verdict of `ratios`, with its distance from the design space.
fn invalid(transmission: &Transmission, ratios: &[f64], error: &DesignError) -> Verdict {
    let space = transmission.design_space();
    let distance = if ratios.len() == space.num_ratios() {
        let projected = space.project(ratios);
        let squares = ratios
            .iter()
            .zip(&projected)
            .map(|(a, b)| (a - b) * (a - b));
        squares.sum::<f64>().sqrt()
    } else {
        f64::INFINITY
    };
    Verdict::Invalid {
        distance,
        reason: error.to_string(),
    }
}

/// Solves the trajectory problem of `ratios`, validated by [`validate`], in `formulation`, from
/// `warm` (a nearby design's solution) or the standard initial guess: the result and the raw
/// solution, or the verdict of a solve that could not run.
pub fn solve(
    formulation: &Formulation,
    settings: &SolveSettings,
    ratios: &[f64],
    warm: Option<&Solution>,
) -> Result<(TrajectoryResult, Solution), Verdict> {
    solve_design_from(formulation, ratios, settings, warm).map_err(|error| match error {
        SolveError::Design(error) => invalid(formulation.transmission(), ratios, &error),
        SolveError::Ipopt(_) | SolveError::Formulation(_) | SolveError::Pose { .. } => {
            Verdict::SolverError {
                message: error.to_string(),
            }
        }
    })
}

/// The verdict of one result of `formulation` (under the one rule of feasibility, the result
/// of an infeasible design is its elastic solve, unless its motors cannot hold the load at
/// rest): feasible with the optimal cost J, or infeasible with the elastic solve's deficit (or
/// IPOPT's reason), the linkages' dead points its trajectory passes, and its shortfall; a solver error where the elastic solve reached no
/// optimum ([`TrajectoryResult::unjudged`]).
pub fn judge(formulation: &Formulation, result: &TrajectoryResult) -> Verdict {
    if result.feasible {
        return Verdict::Feasible {
            cost: result.cost,
            status: SolveStatus::Ipopt(result.status.clone()),
        };
    }
    if let Some(message) = result.unjudged() {
        return Verdict::SolverError { message };
    }
    let (status, reason) = match &result.elastic {
        Some(measures) => {
            let deficit = format!(
                "torque deficit {:.4} N m s, speed excess {:.4} rad",
                measures.torque_deficit, measures.speed_excess
            );
            let hold = result.static_hold.as_ref().and_then(StaticHold::failure);
            let crossings =
                (result.dead_points.iter()).map(|crossing| crossing.text(&result.trajectory.q));
            let reason = (hold.into_iter().chain(crossings))
                .chain([deficit])
                .collect::<Vec<_>>()
                .join("; ");
            (SolveStatus::ElasticDeficit, reason)
        }
        None => (
            SolveStatus::Ipopt(result.status.clone()),
            result
                .reason
                .clone()
                .unwrap_or_else(|| result.status.clone()),
        ),
    };
    Verdict::Infeasible {
        shortfall: shortfall(formulation, result),
        reason,
        status,
    }
}

/// How far a solve's design is from a feasible one, motor-seconds (s): the torque deficit of an
/// elastic solve (N m s) plus the judged static hold's deficit held over the horizon (N m times T, s),
/// over the motors' mean torque limit, plus the speed excess (rad) over their mean speed limit
/// (each motor's own limit where they differ; the deficits and the excess are sums over rows,
/// so no one motor's limit measures them). A hard solve measures only the hold's deficit.
fn shortfall(formulation: &Formulation, result: &TrajectoryResult) -> f64 {
    let hold = result
        .static_hold
        .as_ref()
        .map_or(0.0, StaticHold::judged_deficit_nm);
    let (torque, speed) = result
        .elastic
        .as_ref()
        .map_or((0.0, 0.0), |e| (e.torque_deficit, e.speed_excess));
    shortfall_of(formulation, torque, hold, speed)
}

/// The shortfall, motor-seconds (s), of a torque deficit (N m s), a static hold deficit (N m,
/// held over the horizon T, a free one's T_max) and a speed excess (rad), as
/// [`Verdict::Infeasible`] measures it.
fn shortfall_of(formulation: &Formulation, torque: f64, hold: f64, speed: f64) -> f64 {
    let task = formulation.task();
    let motors = &task.motors;
    (torque + hold * task.motion.horizon.initial_s()) / motors.torque_limit_nm.mean()
        + speed / motors.speed_limit_rad_s.mean()
}
