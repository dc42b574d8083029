//! Why a co-design run failed, by what failed: the case, its inputs, its outputs or the run.

use super::settings::CaseError;
use crate::design::evaluate::EvaluateError;
use crate::design::gradient::GradientError;
use crate::design::optimize::OptimizeError;
use crate::design::score::ScoreError;
use crate::design::workers::WorkerError;
use crate::store::StoreError;
use std::fmt;

/// Which output of a run a store error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The result file (`--out`).
    Result,
    /// The evaluation log beside it.
    Log,
}

/// Why a co-design run failed.
#[derive(Debug)]
pub enum RunError {
    /// A setting of the case is out of its range, or at odds with another.
    Case(CaseError),
    /// The task, the robot, the solver settings or the program itself could not be loaded;
    /// names file and field.
    Load(String),
    /// An output was refused before any work, or could not be written, opened or locked.
    Store {
        /// The output.
        output: Output,
        /// What the store said.
        error: StoreError,
    },
    /// IPOPT refused the solver settings in the solve made before the run; names the task.
    Solver(String),
    /// The workers could not be started.
    Workers(WorkerError),
    /// The CMA-ES run failed: its workers, its log, or no evaluation judged a design.
    Cmaes(OptimizeError),
    /// The gradient method failed (no feasible start, its workers stopped).
    Gradient(GradientError),
    /// A fitness could not be built: the gradient method's, or the payload range's
    /// formulations for the document.
    Score(ScoreError),
    /// The host asked the run to stop while the result's designs were solved
    /// ([`codesign_core::signals::StopToken`]); nothing was written.
    Interrupted,
    /// This process's own evaluation of the best design disagrees with the answer behind it
    /// (a worker's, or a resumed log's); names the worker command.
    Unconfirmed(String),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Case(error) => write!(f, "{error}"),
            RunError::Load(message)
            | RunError::Solver(message)
            | RunError::Unconfirmed(message) => f.write_str(message),
            RunError::Store { error, .. } => write!(f, "{error}"),
            RunError::Workers(error) => write!(f, "{error}"),
            RunError::Cmaes(error) => write!(f, "{error}"),
            RunError::Gradient(error) => write!(f, "{error}"),
            RunError::Score(error) => write!(f, "{error}"),
            RunError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for RunError {}

impl From<WorkerError> for RunError {
    fn from(error: WorkerError) -> RunError {
        RunError::Workers(error)
    }
}

impl From<OptimizeError> for RunError {
    fn from(error: OptimizeError) -> RunError {
        RunError::Cmaes(error)
    }
}

impl From<EvaluateError> for RunError {
    fn from(error: EvaluateError) -> RunError {
        RunError::Cmaes(OptimizeError::Evaluate(error))
    }
}

impl From<GradientError> for RunError {
    fn from(error: GradientError) -> RunError {
        RunError::Gradient(error)
    }
}

impl From<ScoreError> for RunError {
    fn from(error: ScoreError) -> RunError {
        RunError::Score(error)
    }
}

impl RunError {
    /// A store error about `output`.
    pub(super) fn store(output: Output) -> impl Fn(StoreError) -> RunError {
        move |error| RunError::Store { output, error }
    }
}
