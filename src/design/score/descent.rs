//! Scoring a design for a gradient descent: the evaluation every method records, and beside it
//! the merit the descent lowers, the merit's gradient in r and the solution that warm-starts
//! the solves near the design. It is what [`Fitness::descend_from`] gives, in this process or in
//! a worker, and what the worker protocol carries back.

use super::fitness::Scored;
use super::merit::Merit;
use super::solves::{solved, unheld};
use super::{validate, Evaluation, Fitness, Score, Verdict};
use crate::design::penalty::Grading;
use codesign_core::problem::{Formulation, ProblemKind};
use codesign_core::solve::StartPoint;

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
    /// design's merit's starts; none: the standard guess) and judged, with the merit of the
    /// solves. Its verdict is the one [`Fitness::evaluate`] gives: a design whose motors cannot
    /// hold the load at rest is infeasible by the hold's deficit alone. With the flat penalty it
    /// is then not solved; with the graded one it is, for the elastic merit that moves the
    /// descent toward designs that hold it. Only the cost, energy, time and range objectives
    /// have a merit (one payload's optimal cost, a task's motions' or a range's payloads'); the
    /// capacity scores as [`Fitness::evaluate`] does, with none. A start that does not fit the
    /// problems is a solver error.
    pub fn descend_from(&self, ratios: &[f64], start: &[StartPoint]) -> Descent {
        let unsolved = |verdict: Verdict| Descent {
            evaluation: Evaluation::new(ratios, &Score::unsolved(verdict), &self.penalty),
            merit: None,
        };
        let Some(problems) = self.merit_problems() else {
            return Descent {
                evaluation: self.evaluate(ratios),
                merit: None,
            };
        };
        if let Err(message) = self.check_starts(&problems, start) {
            return unsolved(Verdict::SolverError {
                message: format!("warm start: {message}"),
            });
        }
        if let Err(verdict) = validate(&self.transmission, ratios) {
            return unsolved(verdict);
        }
        let (score, merit) = match &self.scored {
            Scored::Motions(motions) => {
                let graded = self.penalty.grading == Grading::Graded;
                motions.descend(graded, ratios, start, |problem, from| {
                    self.descend_one(problem, ratios, from)
                })
            }
            _ => self.descend_one(problems[0], ratios, start.first()),
        };
        Descent {
            evaluation: Evaluation::new(ratios, &score, &self.penalty),
            merit,
        }
    }

    /// The problems a merit is made of, in order: the cost objective's one, or one per motion;
    /// None for the objectives without a merit.
    fn merit_problems(&self) -> Option<Vec<&Formulation>> {
        match &self.scored {
            Scored::Cost(formulation) => Some(vec![formulation]),
            Scored::Motions(motions) => Some(motions.formulations()),
            Scored::Capacity(..) => None,
        }
    }

    /// Checks that `starts` are none, or one per problem of `problems`, each fitting its
    /// problem; what is wrong, in words.
    fn check_starts(&self, problems: &[&Formulation], starts: &[StartPoint]) -> Result<(), String> {
        if !starts.is_empty() && starts.len() != problems.len() {
            return Err(format!(
                "{} start points for {} problems",
                starts.len(),
                problems.len()
            ));
        }
        for (start, problem) in starts.iter().zip(problems) {
            start
                .check_fits(problem, &self.task_hash)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// Valid `ratios` scored for a descent in `formulation`'s problem from `start`: the score,
    /// and the merit when the descent can use it.
    pub(super) fn descend_one(
        &self,
        formulation: &Formulation,
        ratios: &[f64],
        start: Option<&StartPoint>,
    ) -> (Score, Option<Merit>) {
        let hard = formulation.kind() == ProblemKind::Hard;
        let unheld = unheld(&[(String::new(), formulation)], ratios);
        if let (Some(verdict), true) = (&unheld, hard) {
            return (Score::unsolved(verdict.clone()), None);
        }
        let warm = start.map(StartPoint::to_solution);
        let (mut score, ran) = solved(formulation, &self.solve, ratios, warm.as_ref());
        let Some((result, solution)) = ran else {
            return (score, None);
        };
        if let Some(verdict) = unheld {
            score.verdict = verdict;
        }
        // The flat penalty descends on feasible designs only: the elastic result the rule
        // reports for an infeasible design of the hard problem is not its objective.
        if hard && !result.feasible {
            return (score, None);
        }
        let merit = match result.elastic {
            Some(measures) => measures.objective_gradient.map(|g| (measures.objective, g)),
            None => result.cost_gradient.map(|g| (result.cost, g)),
        };
        let merit = merit.map(|(value, gradient)| Merit {
            value,
            gradient,
            feasible_cost: result.feasible.then_some(result.cost),
            starts: vec![StartPoint::from_solution(
                &solution,
                formulation,
                &self.task_hash,
            )],
        });
        (score, merit)
    }

    /// What `merit`, answered for `evaluation` by a worker of this fitness, holds that cannot
    /// be (a phrase after "worker answered"): a merit or gradient that is not a finite number
    /// per ratio, a feasible cost that is not the evaluation's, a start that does not fit the
    /// problem. None when it can be.
    pub fn implausible_merit(&self, evaluation: &Evaluation, merit: &Merit) -> Option<String> {
        let Some(problems) = self.merit_problems() else {
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
        if merit.starts.len() != problems.len() {
            return Some(format!(
                "a merit with {} start points for {} problems",
                merit.starts.len(),
                problems.len()
            ));
        }
        let fits = self.check_starts(&problems, &merit.starts);
        fits.err()
            .map(|error| format!("a merit whose start {error}"))
    }
}
