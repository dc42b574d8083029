//! The evaluator over worker processes: the pool runs the protocol, this side checks each
//! answer as the scoring writes it and penalises a design whose worker failed twice.

use super::{Designs, Done, EvaluateError, Evaluator};
use crate::design::penalty::Penalty;
use crate::design::score::{Descent, Evaluation, Objective, Score, Verdict};
use crate::design::workers::{Answer, DescentRequest, Launcher, Pool, WorkerError, WorkerSetup};
use codesign_core::solve::StartPoint;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// Designs evaluated by a pool of worker processes (see `design::workers`).
pub struct WorkerEvaluator {
    /// The pool, one batch at a time (the gradient method's descents share the evaluator).
    pool: Mutex<Pool>,
    /// How many workers it keeps running.
    workers: usize,
    penalty: Penalty,
}

impl WorkerEvaluator {
    /// Starts `count` workers with `launcher`, each told `setup`; an evaluation may take
    /// `timeout` before its worker counts as hung. An answer is believed only when it is an
    /// evaluation the scoring can write under the setup's penalty and objective
    /// ([`Evaluation::implausible`]), with a merit that fits the setup's problem
    /// ([`Fitness::implausible_merit`](crate::design::score::Fitness::implausible_merit), for
    /// which this side builds the setup's fitness).
    pub fn new(
        launcher: Launcher,
        setup: &WorkerSetup,
        count: usize,
        timeout: Duration,
    ) -> Result<WorkerEvaluator, WorkerError> {
        let penalty = setup.penalty;
        let negative_fitness = matches!(setup.objective, Objective::Capacity(_));
        let fitness = setup.fitness()?;
        let check = move |evaluation: &Evaluation, merit: Option<&_>| {
            evaluation
                .implausible(&penalty, negative_fitness)
                .or_else(|| merit.and_then(|m| fitness.implausible_merit(evaluation, m)))
        };
        let pool = Pool::new(launcher, setup, count, timeout, Box::new(check))?;
        Ok(WorkerEvaluator {
            pool: Mutex::new(pool),
            workers: count,
            penalty,
        })
    }

    /// Process ids of the running workers (for monitoring).
    pub fn worker_ids(&self) -> Vec<u32> {
        self.pool().worker_ids()
    }

    /// The pool, held until the guard drops. Nothing in a batch panics by design; were one to,
    /// the next batch still finds the workers, and replaces any that misbehave.
    fn pool(&self) -> MutexGuard<'_, Pool> {
        self.pool.lock().unwrap_or_else(PoisonError::into_inner)
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
        let penalty = self.penalty;
        let pool = self.pool.get_mut().unwrap_or_else(PoisonError::into_inner);
        pool.set_start(anchor.map(<[f64]>::to_vec), None);
        let answers = pool.evaluate_all(designs, |id, answer| {
            warn_failed(answer, &penalty);
            done(id, &scored(answer, &penalty))
        })?;
        Ok(answers
            .iter()
            .map(|answer| scored(answer, &penalty))
            .collect())
    }

    fn descend(
        &self,
        designs: &Designs,
        start: &[StartPoint],
    ) -> Result<Vec<Descent>, EvaluateError> {
        let descent = DescentRequest {
            starts: start.to_vec(),
        };
        let penalty = self.penalty;
        let mut pool = self.pool();
        pool.set_start(None, Some(descent));
        let answers = pool.evaluate_all(designs, |_, answer| {
            warn_failed(answer, &penalty);
            Ok::<(), EvaluateError>(())
        })?;
        Ok(answers
            .into_iter()
            .map(|answer| match answer {
                Answer::Evaluated { evaluation, merit } => Descent {
                    evaluation,
                    merit: merit.map(|merit| *merit),
                },
                failed => Descent {
                    evaluation: scored(&failed, &penalty),
                    merit: None,
                },
            })
            .collect())
    }

    fn parallelism(&self) -> usize {
        self.workers
    }
}

/// Says on stderr that `answer`'s design is penalised when its worker failed twice.
fn warn_failed(answer: &Answer, penalty: &Penalty) {
    if let Answer::Failed { ratios, reason } = answer {
        let evaluation = scored(answer, penalty);
        eprintln!(
            "warning: {reason} again on design {ratios:?}; scoring it {}",
            evaluation.cost
        );
    }
}

/// The evaluation of a worker's answer: its own, or the penalty of a design whose worker
/// failed twice.
fn scored(answer: &Answer, penalty: &Penalty) -> Evaluation {
    match answer {
        Answer::Evaluated { evaluation, .. } => evaluation.clone(),
        Answer::Failed { ratios, reason } => {
            let failed = Verdict::WorkerFailed {
                message: format!("{reason}, twice"),
            };
            Evaluation::new(ratios, &Score::unsolved(failed), penalty)
        }
    }
}
