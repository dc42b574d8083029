//! Why a command failed, which sets its exit code: 2 for a command line that asks for something
//! out of range (as clap's own usage errors), 1 for work that failed.

use std::fmt;
use std::process::ExitCode;

/// Why a command failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    /// A flag's value is out of its range or contradicts another flag, known before any file is
    /// read; the message names the flag. Exit 2.
    Usage(String),
    /// Anything else: an input, the work or an output failed. Exit 1.
    Work(String),
}

impl Failure {
    /// The process's exit code for this failure.
    pub fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Usage(_) => ExitCode::from(2),
            Failure::Work(_) => ExitCode::FAILURE,
        }
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure::Work(message)
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Usage(message) | Failure::Work(message) => f.write_str(message),
        }
    }
}
