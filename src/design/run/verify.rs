//! The run's own check of what its workers said: the best design of a CMA-ES run is evaluated
//! again in this process, as a worker would (same fitness, same warm start), and the run is
//! believed only when both agree. A worker that lies, or a log edited with a recomputed
//! checksum, is caught where it matters: at the design the run would report.

use super::error::RunError;
use crate::design::evaluate::{EvaluateError, Evaluator, InProcess};
use crate::design::outcome::{BestStart, DesignOutcome};
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
    if outcome.best_ratios.is_empty() {
        return Ok(());
    }
    let anchor = match outcome.best_start() {
        BestStart::Anchor(anchor) => Some(anchor),
        BestStart::Solution(_) | BestStart::Cold => None,
    };
    let mut evaluator = InProcess::new(setup.fitness()?, 1);
    let design = [(0, outcome.best_ratios.clone())];
    let evaluations = evaluator.evaluate(&design, anchor, &mut |_, _| Ok(()))?;
    let own = evaluations.first().ok_or(EvaluateError::Interrupted)?;
    let claimed = outcome.best_cost;
    let tolerance = COST_AGREEMENT * claimed.abs().max(1.0);
    if own.feasible && (own.cost - claimed).abs() <= tolerance {
        return Ok(());
    }
    let found = match own.feasible {
        true => format!("feasible at a fitness of {}", number(own.cost)),
        false => format!("not feasible ({})", own.status),
    };
    Err(RunError::Unconfirmed(format!(
        "the best design r = {:?} was answered feasible at a fitness of {}, but this process's \
         own evaluation of it finds it {found}: the answers of the workers (`{launcher}`), or \
         of the evaluation log they were replayed from, are not believed and no result was \
         written; check the worker command, then start afresh with --overwrite",
        outcome.best_ratios,
        number(claimed)
    )))
}
