//! The run's own check of what its workers said: the best design of a run on worker processes
//! (CMA-ES, or the gradient method with a worker command) is evaluated again in this process, as
//! its worker evaluated it (same fitness, same start), and the run is believed only when both
//! agree. A worker that lies, or a log edited with a recomputed checksum, is caught where it
//! matters: at the design the run would report.

use super::error::RunError;
use crate::design::evaluate::{EvaluateError, Evaluator, InProcess};
use crate::design::outcome::{DesignOutcome, MethodOutcome};
use crate::design::score::Evaluation;
use crate::design::workers::{Launcher, WorkerSetup};
use codesign_core::text::number;

/// The relative difference of two costs of one design beyond which two evaluations disagree:
/// far above the last digits a solve's rounding can move, far below any design's difference
/// that matters (equal builds give equal bits).
const COST_AGREEMENT: f64 = 1e-6;

/// Evaluates `outcome`'s best design here and compares it with the answer behind `best_cost`
/// (a worker's, or a resumed log's); an error naming the worker command when they disagree.
/// Nothing to check when no design was feasible.
pub(super) fn confirm_best(
    outcome: &DesignOutcome,
    setup: &WorkerSetup,
    launcher: &Launcher,
) -> Result<(), RunError> {
    let Some(claimed) = outcome.best_cost else {
        return Ok(());
    };
    let mut evaluator = InProcess::new(setup.fitness()?, 1);
    let own = evaluate_again(outcome, &mut evaluator)?;
    let tolerance = COST_AGREEMENT * claimed.abs().max(1.0);
    if own.feasible && (own.cost - claimed).abs() <= tolerance {
        return Ok(());
    }
    let found = match own.feasible {
        true => format!("feasible at a fitness of {}", number(own.cost)),
        false => format!("not feasible ({})", own.status),
    };
    let (answers, then) = match outcome.method {
        MethodOutcome::Cmaes { .. } => (
            "or of the evaluation log they were replayed from, ",
            ", then start afresh with --overwrite",
        ),
        MethodOutcome::Gradient { .. } => ("", ""),
    };
    Err(RunError::Unconfirmed(format!(
        "the best design r = {:?} was answered feasible at a fitness of {}, but this process's \
         own evaluation of it finds it {found}: the answers of the workers (`{launcher}`), \
         {answers}are not believed and no result was written; check the worker command{then}",
        outcome.best_ratios,
        number(claimed)
    )))
}

/// `outcome`'s best design evaluated by `evaluator` as its method evaluated it: CMA-ES's from
/// the solution of its generation's anchor, the gradient method's scored for a descent from the
/// start its solve began at.
fn evaluate_again(
    outcome: &DesignOutcome,
    evaluator: &mut InProcess,
) -> Result<Evaluation, EvaluateError> {
    let design = [(0, outcome.best_ratios.clone())];
    let evaluations = match &outcome.method {
        MethodOutcome::Cmaes { best_anchor, .. } => {
            evaluator.evaluate(&design, best_anchor.as_deref(), &mut |_, _| Ok(()))?
        }
        MethodOutcome::Gradient { best_from, .. } => {
            let descents = evaluator.descend(&design, best_from)?;
            descents.into_iter().map(|d| d.evaluation).collect()
        }
    };
    evaluations
        .into_iter()
        .next()
        .ok_or(EvaluateError::Interrupted)
}
