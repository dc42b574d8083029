//! Scoring a design for a gradient descent: the evaluation every method records, and beside it
//! the merit the descent lowers, the merit's gradient in r and the solution that warm-starts
//! the solves near the design. It is what [`Fitness::descend_from`] gives, in this process or in
//! a worker, and what the worker protocol carries back.

use super::objective::{solved, unheld, Scored};
use super::{validate, Evaluation, Fitness, Score, Verdict};
use codesign_core::problem::ProblemKind;
use codesign_core::solve::StartPoint;
use serde::{Deserialize, Serialize};

/// What a descent uses of one design's solve (docs/model.md, section 12).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Merit {
    /// The merit: the optimal cost J* (flat penalty), or the elastic problem's optimal penalised
    /// objective (graded penalty), which is J* where the design is feasible.
    pub value: f64,
    /// Its gradient with respect to the ratios (the exact sensitivity of the solve).
    pub gradient: Vec<f64>,
    /// The optimal cost J*, when the design is feasible.
    pub feasible_cost: Option<f64>,
    /// The solve's raw solution, to start the solves of designs near it from.
    pub start: StartPoint,
}

/// A design scored for a descent: its evaluation, and its merit when the descent can use it (a
/// valid design whose solve gave a merit with its gradient; with the flat penalty, a feasible
/// one).
#[derive(Clone, Debug, PartialEq)]
pub struct Descent {
    /// The evaluation, as [`Fitness::evaluate_from`] records it.
    pub evaluation: Evaluation,
    /// The merit, when the descent can use it.
    pub merit: Option<Merit>,
}

impl Fitness {
    /// Scores `ratios` for a descent: validated, solved under the one rule from `start` (a nearby
    /// design's merit's start; None: the standard guess) and judged, with the merit of the
    /// solve. Its verdict is the one [`Fitness::evaluate`] gives: a design whose motors cannot
    /// hold the load at rest is infeasible by the hold's deficit alone. With the flat penalty it
    /// is then not solved; with the graded one it is, for the elastic merit that moves the
    /// descent toward designs that hold it. Only the cost and energy objectives have a merit
    /// (one payload's optimal cost); the others score as [`Fitness::evaluate`] does, with none.
    /// A start that does not fit the problem is a solver error.
    pub fn descend_from(&self, ratios: &[f64], start: Option<&StartPoint>) -> Descent {
        let unsolved = |verdict: Verdict| Descent {
            evaluation: Evaluation::new(ratios, &Score::unsolved(verdict), &self.penalty),
            merit: None,
        };
        let Scored::Cost(formulation) = &self.scored else {
            return Descent {
                evaluation: self.evaluate(ratios),
                merit: None,
            };
        };
        if let Some(Err(error)) = start.map(|s| s.check_fits(formulation, &self.task_hash)) {
            return unsolved(Verdict::SolverError {
                message: format!("warm start: {error}"),
            });
        }
        if let Err(verdict) = validate(&self.transmission, ratios) {
            return unsolved(verdict);
        }
        let hard = formulation.kind() == ProblemKind::Hard;
        let unheld = unheld(&[(0.0, formulation)], ratios);
        if let (Some(verdict), true) = (&unheld, hard) {
            return unsolved(verdict.clone());
        }
        let warm = start.map(StartPoint::to_solution);
        let (mut score, ran) = solved(formulation, &self.solve, ratios, warm.as_ref());
        let Some((result, solution)) = ran else {
            return unsolved(score.verdict);
        };
        if let Some(verdict) = unheld {
            score.verdict = verdict;
        }
        let evaluation = Evaluation::new(ratios, &score, &self.penalty);
        // The flat penalty descends on feasible designs only: the elastic result the rule
        // reports for an infeasible design of the hard problem is not its objective.
        if hard && !result.feasible {
            return Descent {
                evaluation,
                merit: None,
            };
        }
        let merit = match result.elastic {
            Some(measures) => measures.objective_gradient.map(|g| (measures.objective, g)),
            None => result.cost_gradient.map(|g| (result.cost, g)),
        };
        Descent {
            evaluation,
            merit: merit.map(|(value, gradient)| Merit {
                value,
                gradient,
                feasible_cost: result.feasible.then_some(result.cost),
                start: StartPoint::from_solution(&solution, formulation, &self.task_hash),
            }),
        }
    }

    /// What `merit`, answered for `evaluation` by a worker of this fitness, holds that cannot
    /// be (a phrase after "worker answered"): a merit or gradient that is not a finite number
    /// per ratio, a feasible cost that is not the evaluation's, a start that does not fit the
    /// problem. None when it can be.
    pub fn implausible_merit(&self, evaluation: &Evaluation, merit: &Merit) -> Option<String> {
        let Scored::Cost(formulation) = &self.scored else {
            return Some("a merit for an objective that has none".to_owned());
        };
        if !merit.value.is_finite() {
            return Some(format!("a merit of {}", merit.value));
        }
        let ratios = evaluation.ratios.len();
        if merit.gradient.len() != ratios || merit.gradient.iter().any(|g| !g.is_finite()) {
            return Some(format!(
                "a merit gradient {:?} for {ratios} ratios",
                merit.gradient
            ));
        }
        let feasible = evaluation.feasible.then_some(evaluation.cost.to_bits());
        if merit.feasible_cost.map(f64::to_bits) != feasible {
            return Some(format!(
                "a feasible cost {:?} for an evaluation of cost {} (feasible: {})",
                merit.feasible_cost, evaluation.cost, evaluation.feasible
            ));
        }
        let fits = merit.start.check_fits(formulation, &self.task_hash);
        fits.err()
            .map(|error| format!("a merit whose start {error}"))
    }
}
