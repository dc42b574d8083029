//! The fitness of one design (docs/model.md, section 10): its optimal trajectory cost, or the
//! negated payload capacity, or a penalty.

use super::capacity::{payload_capacity, CapacitySettings};
use crate::problem::Formulation;
use crate::solve::{solve_design, SolveError, SolveSettings};
use serde::{Deserialize, Serialize};

/// The outcome of evaluating one design, as logged and as the optimiser sees it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The design r.
    pub ratios: Vec<f64>,
    /// The fitness: the optimal cost J when the design is valid and feasible, else the penalty.
    pub cost: f64,
    /// Whether the design is valid and its trajectory problem was solved.
    pub feasible: bool,
    /// IPOPT's status, or `Invalid_Design` / `Worker_Failed` when IPOPT did not decide.
    pub status: String,
    /// IPOPT iterations (0 when no solve ran).
    pub iterations: usize,
    /// Wall time of the solve, s.
    pub seconds: f64,
    /// Why the design was penalised.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl Evaluation {
    /// A penalised design that was never solved.
    pub fn penalised(ratios: &[f64], penalty: f64, status: &str, reason: String) -> Evaluation {
        Evaluation {
            ratios: ratios.to_vec(),
            cost: penalty,
            feasible: false,
            status: status.to_owned(),
            iterations: 0,
            seconds: 0.0,
            reason: Some(reason),
        }
    }
}

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
}

/// The payloads of [`Objective::Range`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PayloadRange {
    /// The payloads, kg, in the order they are solved (the mean sums in this order).
    pub payloads_kg: Vec<f64>,
}

/// Scores `ratios` by the mean of its optimal costs over the payloads of `formulations`; the
/// first payload at which it is invalid or infeasible ends the evaluation with `penalty`, that
/// payload named in the reason.
pub fn evaluate_range(
    formulations: &[(f64, Formulation)],
    solve: &SolveSettings,
    ratios: &[f64],
    penalty: f64,
) -> Evaluation {
    let (mut iterations, mut seconds, mut sum) = (0, 0.0, 0.0);
    for (payload_kg, formulation) in formulations {
        let one = evaluate(formulation, solve, ratios, penalty);
        iterations += one.iterations;
        seconds += one.seconds;
        if !one.feasible {
            let why = one.reason.clone().unwrap_or_else(|| one.status.clone());
            return Evaluation {
                iterations,
                seconds,
                reason: Some(format!("at {payload_kg} kg: {why}")),
                ..one
            };
        }
        sum += one.cost;
    }
    Evaluation {
        ratios: ratios.to_vec(),
        cost: sum / formulations.len() as f64,
        feasible: true,
        status: "Solve_Succeeded".to_owned(),
        iterations,
        seconds,
        reason: None,
    }
}

/// Scores `ratios` by minus its payload capacity (the formulation's payload is ignored); a
/// design that cannot even move unloaded, or is invalid, scores `penalty`.
pub fn evaluate_capacity(
    formulation: &Formulation,
    solve: &SolveSettings,
    ratios: &[f64],
    settings: &CapacitySettings,
    penalty: f64,
) -> Evaluation {
    if let Err(error) = formulation.transmission().check_design(ratios) {
        return Evaluation::penalised(ratios, penalty, "Invalid_Design", error.to_string());
    }
    let searched = payload_capacity(formulation, solve, ratios, settings);
    match searched {
        Ok(capacity) => {
            let iterations = capacity.probes.iter().map(|p| p.iterations).sum();
            let seconds = capacity.probes.iter().map(|p| p.seconds).sum();
            match capacity.capacity_kg {
                Some(kg) => Evaluation {
                    ratios: ratios.to_vec(),
                    cost: -kg,
                    feasible: true,
                    status: format!("Capacity_{}_Probes", capacity.probes.len()),
                    iterations,
                    seconds,
                    reason: None,
                },
                None => Evaluation {
                    iterations,
                    seconds,
                    ..Evaluation::penalised(
                        ratios,
                        penalty,
                        "Infeasible_Unloaded",
                        "infeasible even without payload".to_owned(),
                    )
                },
            }
        }
        Err(error) => Evaluation::penalised(ratios, penalty, "Solver_Error", error),
    }
}

/// Solves the trajectory problem of `ratios` and scores it; never fails: an invalid design, an
/// infeasible problem or a solver error all score `penalty` with the reason recorded.
pub fn evaluate(
    formulation: &Formulation,
    solve: &SolveSettings,
    ratios: &[f64],
    penalty: f64,
) -> Evaluation {
    match solve_design(formulation, ratios, solve) {
        Ok(result) => Evaluation {
            ratios: ratios.to_vec(),
            cost: if result.feasible {
                result.cost
            } else {
                penalty
            },
            feasible: result.feasible,
            status: result.status,
            iterations: result.iterations,
            seconds: result.solve_seconds.total,
            reason: result.reason,
        },
        Err(SolveError::Design(error)) => {
            Evaluation::penalised(ratios, penalty, "Invalid_Design", error.to_string())
        }
        Err(SolveError::Ipopt(error)) => {
            Evaluation::penalised(ratios, penalty, "Solver_Error", error.to_string())
        }
    }
}
