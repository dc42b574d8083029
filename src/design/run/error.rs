//! Why a co-design run failed, by what failed: the case, its inputs, its outputs or the run.

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
    /// A setting of the case is out of its range; the message names the `optimize` flag.
    Case(String),
    /// The task, the robot or the solver settings could not be loaded; names file and field.
    Load(String),
    /// An output was refused before any work, or could not be written, opened or locked.
    Store {
        /// The output.
        output: Output,
        /// What the store said.
        error: StoreError,
    },
    /// The run failed: IPOPT refused the settings, the workers failed, no evaluation judged a
    /// design, or the gradient method found no start.
    Failed(String),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Case(message) | RunError::Load(message) | RunError::Failed(message) => {
                f.write_str(message)
            }
            RunError::Store { error, .. } => write!(f, "{error}"),
        }
    }
}

impl std::error::Error for RunError {}

impl RunError {
    /// A store error about `output`.
    pub(super) fn store(output: Output) -> impl Fn(StoreError) -> RunError {
        move |error| RunError::Store { output, error }
    }
}
