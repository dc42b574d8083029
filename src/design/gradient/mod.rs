//! Gradient-based co-design: projected quasi-Newton (BFGS) on the ratios, with the exact design
//! sensitivity dJ*/dr of every solve (`problem::cost_gradient`) and warm-started inner solves.
//!
//! The feasible set of designs is the box of the bounds cut by the order constraints
//! (r_i <= r_j, or r_i < r_j kept by a margin). Steps are projected onto it exactly (a small
//! active-set enumeration); a backtracking line search accepts a step when the inner problem
//! is solved (and, with the flat penalty, feasible) and the merit falls by the Armijo fraction.
//! Candidate starts (the original design and designs spread through the box) are solved once;
//! the best ones are descended from, and the best feasible design is kept. The merit is J*
//! with the flat penalty; with the graded one it is the optimal objective of the elastic
//! problem (docs/model.md, section 14), whose exact penalty makes it J* on feasible designs and
//! larger by the weighted slack elsewhere, so that descents from infeasible designs move toward
//! feasibility.

//!
//! Every solve goes through an [`Evaluator`] (`Evaluator::descend`), in this process or on
//! worker processes; its modules: `starts` (the candidate starts), `descent` (the quasi-Newton
//! descent and its line search).

mod descent;
mod starts;
#[cfg(test)]
mod tests;

pub use starts::{default_starts, spread_designs};

use super::evaluate::{EvaluateError, Evaluator};
use super::outcome::{DesignOutcome, GradientIterate, MethodOutcome};
use super::score::{Descent, Merit};
use super::verdicts::VerdictTally;
use super::workers::WorkerError;
use codesign_core::solve::StartPoint;
use codesign_core::transmission::Transmission;
use std::fmt;

/// Settings of a gradient-based run; `Default` gives the values `optimize` and `reproduce` use.
#[derive(Clone, Debug, PartialEq)]
pub struct GradientSettings {
    /// Quasi-Newton iterations per descent at most.
    pub max_iterations: usize,
    /// Stop when the projected gradient step is shorter than this, or an iteration lowers the
    /// cost by less than this fraction.
    pub tolerance: f64,
    /// Halton designs solved as candidate starts beside the original design.
    pub spread: u32,
    /// Further Halton designs, solved in order only while fewer than `descents` feasible
    /// candidates are known (feasible designs can be rare: about 3% of the box at 3 kg in
    /// actuation space).
    pub fallbacks: u32,
    /// How many of the feasible candidates, best first, are descended from.
    pub descents: usize,
}

impl Default for GradientSettings {
    fn default() -> GradientSettings {
        GradientSettings {
            max_iterations: 50,
            tolerance: 1e-6,
            spread: 12,
            fallbacks: 64,
            descents: 3,
        }
    }
}

/// A design with the merit its solve gave (see [`Merit`]): the point a descent moves from.
#[derive(Clone)]
struct Point {
    ratios: Vec<f64>,
    merit: Merit,
    /// The starts its solve began at (none: the standard guess), to solve it again as it was.
    from: Vec<StartPoint>,
}

impl Point {
    fn iterate(&self, start: usize) -> GradientIterate {
        GradientIterate {
            start,
            ratios: self.ratios.clone(),
            cost: self.merit.value,
            gradient: self.merit.gradient.clone(),
        }
    }
}

/// The solves of a run (or of one descent) on its evaluator, with the fitness and time of each
/// recorded in order, and the best feasible point accepted so far.
struct Solves<'a> {
    evaluator: &'a dyn Evaluator,
    costs: Vec<f64>,
    seconds: Vec<f64>,
    verdicts: VerdictTally,
    best: Option<Point>,
}

impl<'a> Solves<'a> {
    /// No solve yet.
    fn new(evaluator: &'a dyn Evaluator) -> Solves<'a> {
        Solves {
            evaluator,
            costs: Vec::new(),
            seconds: Vec::new(),
            verdicts: VerdictTally::default(),
            best: None,
        }
    }

    /// Appends `later`'s solves, which came after these, and keeps its best as
    /// [`Solves::keep`] would have kept each of its points in turn.
    fn append(&mut self, later: Solves<'_>) {
        self.costs.extend(later.costs);
        self.seconds.extend(later.seconds);
        self.verdicts.merge(&later.verdicts);
        if let Some(best) = &later.best {
            self.keep(best);
        }
    }

    /// Records `descent`'s fitness and, when a solve ran, its time; its point, solved from
    /// `from` (none: the standard guess), when the descent can use it.
    fn record(&mut self, descent: Descent, from: &[StartPoint]) -> Option<Point> {
        let Descent { evaluation, merit } = descent;
        if evaluation.iterations > 0 {
            self.seconds.push(evaluation.seconds);
        }
        self.costs.push(evaluation.cost);
        self.verdicts.add(&evaluation);
        merit.map(|merit| Point {
            ratios: evaluation.ratios,
            merit,
            from: from.to_vec(),
        })
    }

    /// Solves `ratios` from `start` and records it; the point when the descent can use it.
    fn solve(
        &mut self,
        ratios: &[f64],
        start: &[StartPoint],
    ) -> Result<Option<Point>, GradientError> {
        let mut solved = self.evaluator.descend(&[(0, ratios.to_vec())], start)?;
        Ok(solved.pop().and_then(|descent| self.record(descent, start)))
    }

    /// Keeps `point` as the best if it is feasible and cheaper than the best so far.
    fn keep(&mut self, point: &Point) {
        let better = |cost: f64| {
            self.best
                .as_ref()
                .is_none_or(|best| cost < best.merit.feasible_cost.unwrap_or(f64::INFINITY))
        };
        if point.merit.feasible_cost.is_some_and(better) {
            self.best = Some(point.clone());
        }
    }
}

/// Why a gradient-based run found no result.
#[derive(Debug)]
pub enum GradientError {
    /// With the flat penalty, no candidate start was feasible to descend from.
    NoFeasibleStart {
        /// The candidate designs solved.
        solved: usize,
    },
    /// The host asked the run to stop (its `signals::StopToken`).
    Interrupted,
    /// The evaluator stopped (its worker pool failed).
    Evaluate(EvaluateError),
}

impl fmt::Display for GradientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GradientError::NoFeasibleStart { solved } => write!(
                f,
                "the gradient method found no feasible start among {solved} candidate designs"
            ),
            GradientError::Interrupted => f.write_str("interrupted"),
            GradientError::Evaluate(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for GradientError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            GradientError::Evaluate(error) => Some(error),
            _ => None,
        }
    }
}

impl From<EvaluateError> for GradientError {
    fn from(error: EvaluateError) -> GradientError {
        match error {
            EvaluateError::Interrupted | EvaluateError::Workers(WorkerError::Interrupted) => {
                GradientError::Interrupted
            }
            error => GradientError::Evaluate(error),
        }
    }
}

/// Runs the projected quasi-Newton method on the designs of `transmission` from the best
/// candidate starts (the original design and Halton-spread designs, see [`default_starts`]),
/// every solve by `evaluator`, the descents side by side (as many as its parallelism; each
/// descent's solves are recorded after the last one's). With its flat penalty the descents start from feasible
/// candidates and lower J*, and the run fails when no candidate is feasible; with a graded one
/// they lower the elastic problem's optimal objective from any candidate, moving infeasible
/// designs toward feasibility (docs/model.md, section 14). Each solve is recorded with its
/// fitness (J*, or the penalty of an infeasible design); the best feasible accepted design is
/// the result.
pub fn optimize_gradient(
    transmission: &Transmission,
    evaluator: &dyn Evaluator,
    settings: &GradientSettings,
) -> Result<DesignOutcome, GradientError> {
    let set = transmission.design_space();
    let mut solves = Solves::new(evaluator);
    let interrupted = || codesign_core::signals::stop_requested();
    let (candidates, solved) = starts::descent_starts(transmission, settings, &mut solves)?;
    if interrupted() {
        return Err(GradientError::Interrupted);
    }
    if candidates.is_empty() {
        return Err(GradientError::NoFeasibleStart { solved });
    }
    let iterates = descent::descend_all(&candidates, set, settings, &mut solves)?;
    let count = solves.costs.len();
    let stop_reason = format!(
        "{solved} candidate starts solved, {} descents, {} iterates, {count} solves",
        settings.descents,
        iterates.len()
    );
    let (best_ratios, best_cost, best_solution, best_from) = match solves.best {
        Some(Point {
            ratios,
            merit,
            from,
        }) => (
            ratios,
            merit.feasible_cost,
            merit.starts.first().map(|s| Box::new(s.to_solution())),
            from,
        ),
        // Only a graded descent can end without a feasible design.
        None => (Vec::new(), None, None, Vec::new()),
    };
    Ok(DesignOutcome {
        best_ratios,
        best_cost,
        costs: solves.costs,
        seconds: solves.seconds,
        verdicts: solves.verdicts,
        stop_reason,
        method: MethodOutcome::Gradient {
            iterates,
            best_solution,
            best_from,
        },
    })
}
