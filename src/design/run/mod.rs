//! A co-design run as library code: the [`Case`] (what to run, with every check of its
//! settings), its [`Method`], running it ([`run_case`]) and the [`OptimizeDocument`] it writes.
//! The command line only parses flags into a case; `report/` only renders documents.

mod case;
mod document;
mod error;
mod execute;
mod method;
mod settings;
mod verify;

pub use case::{shell_quote, task_source, Case, Loaded, ModelChoice, ProblemChoice};
pub use document::{
    number_or_nan, MotionCost, MotionCosts, OptimizeDocument, OptimizeInputs, PayloadCost,
    RangeCosts, RecordedHash,
};
pub use error::{Output, RunError};
pub use execute::run_case;
pub use method::ProgressDisplay;
pub use settings::{
    CaseError, Execution, Method, RunSettings, MAX_SOLVE_TIMEOUT_S, MIN_SOLVE_TIMEOUT_S,
};
