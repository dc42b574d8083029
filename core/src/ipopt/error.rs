//! Why a solve could not run: the IPOPT layer's typed errors.

use super::LinearSolver;
use std::fmt;

/// Why a solve could not produce a [`Solution`](super::Solution). (A solve that ran and failed to converge is not
/// an error: it is a `Solution` with a non-success [`Status`](super::Status).)
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// IPOPT rejected an option: unknown name, wrong type or value out of range.
    InvalidOption {
        /// The option's name.
        name: String,
        /// The value given, as text.
        value: String,
    },
    /// The problem's description is inconsistent (sizes, sparsity indices, bounds).
    InvalidProblem(String),
    /// A callback returned an error or panicked; IPOPT was stopped.
    Callback {
        /// Which callback: `objective`, `gradient`, `constraints`, `jacobian` or `hessian`.
        callback: &'static str,
        /// The error's or the panic's message.
        message: String,
    },
    /// IPOPT could not open the requested log file.
    OutputFile(String),
    /// IPOPT refused the options when the solve started (it checks some values only then).
    OptionsAtStart,
    /// The work the solve belongs to was asked to stop ([`crate::signals::StopToken`]): IPOPT
    /// was stopped at an iteration, so its point is no answer.
    Stopped,
    /// The linear solver could not be used; names it and says why.
    LinearSolver {
        /// The solver asked for.
        solver: LinearSolver,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidOption { name, value } => {
                write!(f, "IPOPT rejected option `{name}` = {value}")
            }
            Error::InvalidProblem(message) => write!(f, "invalid NLP: {message}"),
            Error::Callback { callback, message } => {
                write!(f, "the {callback} callback failed: {message}")
            }
            Error::OutputFile(path) => write!(f, "IPOPT could not open its log file {path}"),
            Error::OptionsAtStart => f.write_str(
                "IPOPT refused an option's value when the solve started (a value out of its \
                 range, or one that contradicts another); run `codesign solve --verbose` to see \
                 IPOPT's message",
            ),
            Error::Stopped => f.write_str("the solve was stopped before it ended"),
            Error::LinearSolver { solver, message } => {
                write!(f, "linear solver `{solver}` cannot be used: {message}")
            }
        }
    }
}

impl std::error::Error for Error {}
