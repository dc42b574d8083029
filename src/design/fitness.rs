//! What a worker scores designs with: the objective's formulations (one per payload of a range,
//! elastic ones for a graded penalty) and the penalty.

use super::capacity::CapacitySettings;
use super::evaluate::{evaluate, evaluate_capacity, evaluate_range, Evaluation, Objective};
use super::penalty::{Grading, Penalty};
use crate::model::task::{LimitModes, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::solve::{solve_design, SolveError, SolveSettings};

/// The formulations of an objective and the penalty of a run.
#[derive(Debug)]
pub struct Fitness {
    scored: Scored,
    penalty: Penalty,
    solve: SolveSettings,
}

/// What is solved per design.
#[derive(Debug)]
enum Scored {
    /// The cost at one payload.
    Cost(Formulation),
    /// Minus the capacity; the formulation's payload is ignored.
    Capacity(Formulation, CapacitySettings),
    /// The mean cost over the payloads, each with its formulation.
    Range(Vec<(f64, Formulation)>),
}

impl Fitness {
    /// The fitness of `objective` for `task` (its payload used by `Cost` and `Capacity`) in
    /// `space` with limit `modes`, solved with `solve`; with a graded `penalty` the problems are
    /// the elastic ones.
    pub fn new(
        task: &Task,
        solve: &SolveSettings,
        space: Space,
        modes: LimitModes,
        objective: &Objective,
        penalty: Penalty,
    ) -> Result<Fitness, String> {
        let robot = Robot::load(task).map_err(|e| e.to_string())?;
        let hard = Formulation::new(task, robot, space, modes).map_err(|e| e.to_string())?;
        let base = match penalty.grading {
            Grading::Flat => hard,
            Grading::Graded => hard.elastic(),
        };
        let formulation =
            |payload_kg: f64| base.with_payload(payload_kg).map_err(|e| e.to_string());
        let scored = match objective {
            Objective::Cost => Scored::Cost(formulation(task.payload.mass_kg)?),
            Objective::Capacity(settings) => {
                Scored::Capacity(formulation(task.payload.mass_kg)?, *settings)
            }
            Objective::Range(range) => Scored::Range(
                range
                    .payloads_kg
                    .iter()
                    .map(|&kg| formulation(kg).map(|f| (kg, f)))
                    .collect::<Result<_, _>>()?,
            ),
        };
        Ok(Fitness {
            scored,
            penalty,
            solve: solve.clone(),
        })
    }

    /// The range's payloads with their formulations (empty for another objective).
    pub fn payloads(&self) -> &[(f64, Formulation)] {
        match &self.scored {
            Scored::Range(formulations) => formulations,
            _ => &[],
        }
    }

    /// Scores `ratios`; an invalid or infeasible design scores the penalty.
    pub fn evaluate(&self, ratios: &[f64]) -> Evaluation {
        let (base, solve) = (self.penalty.base, &self.solve);
        match (&self.scored, self.penalty.grading) {
            (Scored::Cost(formulation), Grading::Flat) => {
                evaluate(formulation, solve, ratios, base)
            }
            (Scored::Capacity(formulation, settings), _) => {
                evaluate_capacity(formulation, solve, ratios, settings, base)
            }
            (Scored::Range(formulations), Grading::Flat) => {
                evaluate_range(formulations, solve, ratios, base)
            }
            (Scored::Cost(formulation), Grading::Graded) => {
                graded(&[(0.0, formulation)], solve, ratios, &self.penalty)
            }
            (Scored::Range(formulations), Grading::Graded) => {
                let each: Vec<(f64, &Formulation)> =
                    formulations.iter().map(|(kg, f)| (*kg, f)).collect();
                graded(&each, solve, ratios, &self.penalty)
            }
        }
    }
}

/// How far an elastic solve's trajectory is from a feasible one, s: the torque deficit over the
/// motor torque limit plus the speed excess over the speed limit (motor-seconds of shortfall).
pub(super) fn shortfall(formulation: &Formulation, deficit_nm_s: f64, excess_rad: f64) -> f64 {
    let motors = &formulation.task().motors;
    deficit_nm_s / motors.torque_limit_nm + excess_rad / motors.speed_limit_rad_s
}

/// Scores `ratios` with the elastic problems of `formulations` (one per payload): the mean cost
/// when every one is feasible, else the graded penalty of the summed shortfall; a design outside
/// the design space scores the graded penalty of its distance from it.
fn graded(
    formulations: &[(f64, &Formulation)],
    solve: &SolveSettings,
    ratios: &[f64],
    penalty: &Penalty,
) -> Evaluation {
    let (mut iterations, mut seconds, mut sum, mut short) = (0, 0.0, 0.0, 0.0);
    let mut reasons = Vec::new();
    for (payload_kg, formulation) in formulations {
        let space = formulation.transmission().design_space();
        match solve_design(formulation, ratios, solve) {
            Ok(result) => {
                iterations += result.iterations;
                seconds += result.solve_seconds.total;
                let measures = result.elastic.unwrap_or_default();
                if result.feasible {
                    sum += result.cost;
                } else {
                    short += shortfall(formulation, measures.torque_deficit, measures.speed_excess);
                    reasons.push(format!(
                        "{}torque deficit {:.4} N m s, speed excess {:.4} rad",
                        if formulations.len() > 1 {
                            format!("at {payload_kg} kg: ")
                        } else {
                            String::new()
                        },
                        measures.torque_deficit,
                        measures.speed_excess
                    ));
                }
            }
            Err(SolveError::Design(error)) => {
                let projected = space.project(ratios);
                let distance = ratios
                    .iter()
                    .zip(&projected)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
                    .sqrt();
                return Evaluation::penalised(
                    ratios,
                    penalty.invalid(distance),
                    "Invalid_Design",
                    error.to_string(),
                );
            }
            Err(SolveError::Ipopt(error)) => {
                return Evaluation::penalised(
                    ratios,
                    penalty.base,
                    "Solver_Error",
                    error.to_string(),
                );
            }
        }
    }
    let feasible = reasons.is_empty();
    Evaluation {
        ratios: ratios.to_vec(),
        cost: if feasible {
            sum / formulations.len() as f64
        } else {
            penalty.infeasible(short)
        },
        feasible,
        status: if feasible {
            "Solve_Succeeded"
        } else {
            "Elastic_Deficit"
        }
        .to_owned(),
        iterations,
        seconds,
        reason: (!feasible).then(|| reasons.join("; ")),
    }
}
