//! Failures as Python exceptions: the classes of `codesign._errors`, with the command line's
//! messages.

use codesign::store::document::{document_json, Document};
use pyo3::prelude::*;

/// Which exception of `codesign._errors` a failure raises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `InputError` (a `ValueError`): a task, a file or an argument that is not valid.
    Input,
    /// `SolverError` (a `RuntimeError`): IPOPT, a worker or a file write failed.
    Solver,
}

/// A failure of the native module: its kind and the message the command line would print.
#[derive(Clone, Debug)]
pub struct Failure {
    /// The exception class.
    pub kind: Kind,
    /// What went wrong, naming the file, field or argument.
    pub message: String,
}

impl Failure {
    /// A bad input.
    pub fn input(message: impl Into<String>) -> Failure {
        Failure {
            kind: Kind::Input,
            message: message.into(),
        }
    }

    /// A failure of the work itself.
    pub fn solver(message: impl Into<String>) -> Failure {
        Failure {
            kind: Kind::Solver,
            message: message.into(),
        }
    }

    /// The Python exception: an instance of `codesign._errors.InputError` or `SolverError`.
    pub fn into_py(self, py: Python<'_>) -> PyErr {
        let class = match self.kind {
            Kind::Input => "InputError",
            Kind::Solver => "SolverError",
        };
        let made = py
            .import("codesign._errors")
            .and_then(|module| module.getattr(class))
            .and_then(|class| class.call1((self.message.clone(),)));
        match made {
            Ok(instance) => PyErr::from_value(instance),
            Err(error) => error,
        }
    }
}

/// The result of native work.
pub type Outcome<T> = Result<T, Failure>;

/// The document `document` as JSON, an encoding error a solver error.
pub(crate) fn json<D: Document>(document: &D) -> Outcome<String> {
    document_json(document).map_err(|e| Failure::solver(format!("result not encoded: {e}")))
}
