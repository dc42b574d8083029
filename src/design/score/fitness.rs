//! How a design is solved for an objective (`super::objective`): the problems of the cost at one
//! payload, the mean cost over several, a task's several motions (`super::motions`) or the
//! payload capacity, solved and scored; with a graded penalty the solves are the elastic ones,
//! which measure how far an infeasible design is from feasible.

use super::motions::Motions;
use super::objective::{several, Objective, ScoreError};
use super::solves::{solved, unheld};
use super::{judge, shortfall_of, solve, validate, Evaluation, Score, SolveStatus, Verdict};
use crate::design::capacity::{payload_capacity, CapacitySettings};
use crate::design::penalty::{Grading, Penalty};
use codesign_core::ipopt::{self, Solution};
use codesign_core::model::identity::task_hash;
use codesign_core::model::task::LimitModes;
use codesign_core::model::task::Task;
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space, StaticHold};
use codesign_core::solve::SolveSettings;
use codesign_core::transmission::Transmission;

/// The formulations of an objective and the penalty of a run: what a worker scores designs with.
#[derive(Debug)]
pub struct Fitness {
    pub(super) scored: Scored,
    /// The design space every design is validated against.
    pub(super) transmission: Transmission,
    pub(super) penalty: Penalty,
    pub(super) solve: SolveSettings,
    /// The task hash of the problems solved, which the warm starts of descents carry.
    pub(super) task_hash: String,
}

/// What is solved per design.
#[derive(Debug)]
pub(super) enum Scored {
    /// The cost at one payload.
    Cost(Formulation),
    /// Minus the capacity; the formulation's payload is ignored.
    Capacity(Formulation, CapacitySettings),
    /// The cost (or copper losses, or duration) of each of a task's motions, made one; or the
    /// cost at each payload of a range, their mean.
    Motions(Motions),
}

impl Fitness {
    /// The fitness of `objective` for `task` (its payload used by `Cost` and `Capacity`) in
    /// `space` with limit `modes`, solved with `solve`; with a graded `penalty` the problems are
    /// the elastic ones. A task with a `motions` list is scored over its motions by the cost,
    /// energy and time objectives, and refused by the others
    /// ([`ScoreError::SeveralMotions`]); a payload range is scored as the motions of the task's
    /// motion at each payload ([`Motions::new`]).
    pub fn new(
        task: &Task,
        solve: &SolveSettings,
        space: Space,
        modes: LimitModes,
        objective: &Objective,
        penalty: Penalty,
    ) -> Result<Fitness, ScoreError> {
        let source = task;
        let task = &objective.task(source);
        let robot = Robot::load(task)?;
        let task_hash = task_hash(task, robot.urdf_hash());
        if task.has_motions() || matches!(objective, Objective::Range(_)) {
            match objective {
                Objective::Capacity(_) => return Err(several("capacity", task)),
                Objective::Range(_) if task.has_motions() => return Err(several("range", task)),
                _ => {}
            }
            let grading = penalty.grading;
            let motions = Motions::new(task, &robot, space, modes, solve, objective, grading)?;
            return Ok(Fitness {
                transmission: motions.transmission().clone(),
                scored: Scored::Motions(motions),
                penalty,
                solve: solve.clone(),
                task_hash,
            });
        }
        let hard = (objective.shape(Formulation::new(task, robot, space, modes)?, source))
            .with_hold_tolerance(solve.constraint_tolerance());
        let hard = match objective {
            Objective::Energy => hard.minimising_copper_loss()?,
            _ => hard,
        };
        let base = match penalty.grading {
            Grading::Flat => hard,
            Grading::Graded => hard.elastic(),
        };
        let formulation = |payload_kg: f64| base.with_payload(payload_kg);
        let scored = match objective {
            Objective::Capacity(settings) => {
                Scored::Capacity(formulation(task.payload.mass_kg)?, *settings)
            }
            // The cost, energy and time objectives (a range is scored as motions above).
            _ => Scored::Cost(formulation(task.payload.mass_kg)?),
        };
        Ok(Fitness {
            scored,
            transmission: base.transmission().clone(),
            penalty,
            solve: solve.clone(),
            task_hash,
        })
    }

    /// The penalty the fitness scores with.
    pub fn penalty(&self) -> Penalty {
        self.penalty
    }

    /// The linear solver of its solves.
    pub fn linear_solver(&self) -> ipopt::LinearSolver {
        self.solve.linear_solver()
    }

    /// The problems of a task's several motions, or of a payload range's payloads (None for
    /// the other objectives of a task of one motion).
    pub fn motions(&self) -> Option<&Motions> {
        match &self.scored {
            Scored::Motions(motions) => Some(motions),
            _ => None,
        }
    }

    /// The solution the designs of a generation start from (a warm start): the cost objective's
    /// problem of `anchor` (the CMA-ES mean, in the design space) solved under the one rule,
    /// when it is feasible. None for the other objectives (motions and a range have one problem
    /// per motion or payload, a capacity search its own warm starts) and for an anchor that is
    /// invalid or infeasible.
    pub fn anchor(&self, anchor: &[f64]) -> Option<Solution> {
        let Scored::Cost(formulation) = &self.scored else {
            return None;
        };
        anchor_solution(formulation, &self.solve, anchor)
    }

    /// Scores `ratios`: validated once, then solved as the objective and the penalty ask, from
    /// the standard guess.
    pub fn score(&self, ratios: &[f64]) -> Score {
        self.score_from(ratios, None)
    }

    /// Scores `ratios` as [`Fitness::score`] does, the cost objective's solve first started
    /// from `warm` (see [`Fitness::anchor`]; ignored by the other objectives).
    pub fn score_from(&self, ratios: &[f64], warm: Option<&Solution>) -> Score {
        let graded = self.penalty.grading == Grading::Graded;
        if let Err(verdict) = validate(&self.transmission, ratios) {
            return Score::unsolved(verdict);
        }
        let held: Vec<(String, &Formulation)> = match &self.scored {
            Scored::Cost(formulation) => vec![(String::new(), formulation)],
            Scored::Motions(motions) => motions.labelled(),
            // The capacity search solves no payload its motors cannot hold.
            Scored::Capacity(..) => Vec::new(),
        };
        if let Some(verdict) = unheld(&held, ratios) {
            return Score::unsolved(verdict);
        }
        let solve = &self.solve;
        match &self.scored {
            Scored::Capacity(formulation, settings) => {
                capacity(formulation, solve, ratios, settings)
            }
            Scored::Cost(formulation) if graded => elastic(formulation, solve, ratios, warm),
            Scored::Cost(formulation) => solved(formulation, solve, ratios, warm).0,
            Scored::Motions(motions) => motions.score(solve, ratios, graded),
        }
    }

    /// Scores `ratios` and records the evaluation, its fitness under the run's penalty.
    pub fn evaluate(&self, ratios: &[f64]) -> Evaluation {
        self.evaluate_from(ratios, None)
    }

    /// Scores `ratios` from `warm` (see [`Fitness::score_from`]) and records the evaluation.
    pub fn evaluate_from(&self, ratios: &[f64], warm: Option<&Solution>) -> Evaluation {
        Evaluation::new(ratios, &self.score_from(ratios, warm), &self.penalty)
    }
}

/// The solution of `anchor` in `formulation` (solved under the one rule from the standard
/// guess) that a generation's designs start from, when the anchor is valid and feasible.
pub fn anchor_solution(
    formulation: &Formulation,
    settings: &SolveSettings,
    anchor: &[f64],
) -> Option<Solution> {
    validate(formulation.transmission(), anchor).ok()?;
    let (result, solution) = solve(formulation, settings, anchor, None).ok()?;
    result.feasible.then_some(solution)
}

/// The score of valid `ratios` by the elastic problem `formulation`, first solved from `warm`:
/// its cost when feasible, else infeasible by its shortfall.
fn elastic(
    formulation: &Formulation,
    settings: &SolveSettings,
    ratios: &[f64],
    warm: Option<&Solution>,
) -> Score {
    let result = match solve(formulation, settings, ratios, warm) {
        Ok((result, _)) => result,
        Err(verdict) => return Score::unsolved(verdict),
    };
    let verdict = match judge(formulation, &result) {
        Verdict::Feasible { .. } => Verdict::Feasible {
            cost: result.cost,
            status: SolveStatus::Ipopt(ipopt::Status::SolveSucceeded.name()),
        },
        Verdict::Infeasible {
            shortfall, reason, ..
        } => Verdict::Infeasible {
            shortfall,
            reason,
            status: SolveStatus::ElasticDeficit,
        },
        verdict => verdict,
    };
    Score {
        verdict,
        iterations: result.iterations,
        seconds: result.solve_seconds.total,
    }
}

/// The score of valid `ratios` by minus its payload capacity (the formulation's payload
/// ignored); a design that cannot even move unloaded is infeasible, one whose search failed has
/// a solver error.
fn capacity(
    formulation: &Formulation,
    settings: &SolveSettings,
    ratios: &[f64],
    search: &CapacitySettings,
) -> Score {
    let capacity = match payload_capacity(formulation, settings, ratios, search) {
        Ok(capacity) => capacity,
        Err(error) => {
            return Score::unsolved(Verdict::SolverError {
                message: error.to_string(),
            })
        }
    };
    let probes = capacity.probes.len();
    let verdict = match capacity.capacity_kg {
        Some(kg) => Verdict::Feasible {
            cost: -kg,
            status: SolveStatus::Capacity { probes },
        },
        None => unloaded(formulation, ratios),
    };
    Score {
        verdict,
        iterations: capacity.probes.iter().map(|p| p.iterations).sum(),
        seconds: capacity.probes.iter().map(|p| p.seconds).sum(),
    }
}

/// The verdict of valid `ratios` that cannot move even without payload: infeasible, by the
/// static hold's deficit at 0 kg when the motors cannot hold the arm at rest (then nothing was
/// solved, and the status says so).
fn unloaded(formulation: &Formulation, ratios: &[f64]) -> Verdict {
    let hold = formulation
        .with_payload(0.0)
        .ok()
        .and_then(|unloaded| unloaded.static_hold(ratios).ok());
    let deficit = hold.as_ref().map_or(0.0, StaticHold::judged_deficit_nm);
    let (reason, status) = match hold.and_then(|hold| hold.failure()) {
        Some(reason) => (
            format!("infeasible even without payload: {reason}"),
            SolveStatus::StaticHoldFailed,
        ),
        None => (
            "infeasible even without payload".to_owned(),
            SolveStatus::InfeasibleUnloaded,
        ),
    };
    Verdict::Infeasible {
        shortfall: shortfall_of(formulation, 0.0, deficit, 0.0),
        reason,
        status,
    }
}
