//! The evaluator over worker processes: the pool runs the protocol, this side checks each
//! answer as the scoring writes it and penalises a design whose worker failed twice.

use super::{Designs, Done, EvaluateError, Evaluator};
use crate::design::penalty::Penalty;
use crate::design::score::{Evaluation, Objective, Score, Verdict};
use crate::design::workers::{Answer, Launcher, Pool, WorkerError, WorkerSetup};
use std::time::Duration;

/// Designs evaluated by a pool of worker processes (see `design::workers`).
pub struct WorkerEvaluator {
    pool: Pool,
    penalty: Penalty,
}

impl WorkerEvaluator {
    /// Starts `count` workers with `launcher`, each told `setup`; an evaluation may take
    /// `timeout` before its worker counts as hung. An answer is believed only when it is an
    /// evaluation the scoring can write under the setup's penalty and objective
    /// ([`Evaluation::implausible`]).
    pub fn new(
        launcher: Launcher,
        setup: &WorkerSetup,
        count: usize,
        timeout: Duration,
    ) -> Result<WorkerEvaluator, WorkerError> {
        let penalty = setup.penalty;
        let negative_fitness = matches!(setup.objective, Objective::Capacity(_));
        let check =
            move |evaluation: &Evaluation| evaluation.implausible(&penalty, negative_fitness);
        let pool = Pool::new(launcher, setup, count, timeout, Box::new(check))?;
        Ok(WorkerEvaluator { pool, penalty })
    }

    /// Process ids of the running workers (for monitoring).
    pub fn worker_ids(&self) -> Vec<u32> {
        self.pool.worker_ids()
    }
}

impl Evaluator for WorkerEvaluator {
    fn penalty(&self) -> Penalty {
        self.penalty
    }

    fn evaluate(
        &mut self,
        designs: &Designs,
        anchor: Option<&[f64]>,
        done: Done<'_>,
    ) -> Result<Vec<Evaluation>, EvaluateError> {
        self.pool.set_anchor(anchor.map(<[f64]>::to_vec));
        let penalty = self.penalty;
        let answers = self.pool.evaluate_all(designs, |id, answer| {
            let evaluation = scored(answer, &penalty);
            if let Answer::Failed { ratios, reason } = answer {
                eprintln!(
                    "warning: {reason} again on design {ratios:?}; scoring it {}",
                    evaluation.cost
                );
            }
            done(id, &evaluation)
        })?;
        Ok(answers
            .iter()
            .map(|answer| scored(answer, &penalty))
            .collect())
    }
}

/// The evaluation of a worker's answer: its own, or the penalty of a design whose worker
/// failed twice.
fn scored(answer: &Answer, penalty: &Penalty) -> Evaluation {
    match answer {
        Answer::Evaluated(evaluation) => evaluation.clone(),
        Answer::Failed { ratios, reason } => {
            let failed = Verdict::WorkerFailed {
                message: format!("{reason}, twice"),
            };
            Evaluation::new(ratios, &Score::unsolved(failed), penalty)
        }
    }
}
