//! Evaluating a batch of designs to checked [`Evaluation`]s, whichever way they are solved: the
//! [`Evaluator`] trait that the outer methods take, with two implementations, worker processes
//! ([`WorkerEvaluator`], over the worker pool) and threads of this process ([`InProcess`]).
//! Both score on this side: the workers' answers are checked like any input, and a design
//! whose worker failed twice is penalised here. CMA-ES asks for evaluations
//! ([`Evaluator::evaluate`]), the gradient method for evaluations with their merits
//! ([`Evaluator::descend`]).

mod local;
mod process;

pub use local::InProcess;
pub use process::WorkerEvaluator;

use super::penalty::Penalty;
use super::score::{Descent, Evaluation};
use super::workers::WorkerError;
use crate::store::StoreError;
use codesign_core::solve::StartPoint;
use std::fmt;

/// Designs to evaluate, each with the caller's identifier (echoed to `done`).
pub type Designs = [(usize, Vec<f64>)];

/// What hears each evaluation as it finishes (a log, a progress display); its error stops the
/// batch.
pub type Done<'a> = &'a mut dyn FnMut(usize, &Evaluation) -> Result<(), EvaluateError>;

/// Something that evaluates designs under a run's penalty. It is shared by the gradient
/// method's descents, which ask for their trials side by side.
pub trait Evaluator: Sync {
    /// The penalty the evaluations are scored under.
    fn penalty(&self) -> Penalty;

    /// Evaluates every design of `designs`, each started from the solution of `anchor` (a
    /// design in the design space; None: the standard initial guess), and returns the
    /// evaluations in the order given. `done` hears each as it finishes, in any order.
    fn evaluate(
        &mut self,
        designs: &Designs,
        anchor: Option<&[f64]>,
        done: Done<'_>,
    ) -> Result<Vec<Evaluation>, EvaluateError>;

    /// Scores every design of `designs` for a gradient descent (`Fitness::descend_from`), each
    /// solved from `start` (a merit's starts; none: the standard guess), and returns them in the
    /// order given.
    fn descend(
        &self,
        designs: &Designs,
        start: &[StartPoint],
    ) -> Result<Vec<Descent>, EvaluateError>;

    /// How many designs it solves at once.
    fn parallelism(&self) -> usize;
}

/// Why a batch of evaluations stopped.
#[derive(Debug)]
pub enum EvaluateError {
    /// The worker pool stopped.
    Workers(WorkerError),
    /// An evaluation could not be appended to the evaluation log.
    Log(StoreError),
    /// The host asked the run to stop (its `signals::StopToken`).
    Interrupted,
}

impl fmt::Display for EvaluateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvaluateError::Workers(error) => error.fmt(f),
            EvaluateError::Log(error) => error.fmt(f),
            EvaluateError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for EvaluateError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            EvaluateError::Workers(error) => Some(error),
            _ => None,
        }
    }
}

impl From<WorkerError> for EvaluateError {
    fn from(error: WorkerError) -> EvaluateError {
        EvaluateError::Workers(error)
    }
}
