//! Why a command failed, which sets its exit code: 2 for a command line that asks for something
//! out of range (as clap's own usage errors), 1 for work that failed, 3 for a verdict of
//! infeasibility that the command line asked to fail on (`solve --fail-if-infeasible`).

use std::fmt;
use std::process::ExitCode;

/// The exit code of a design found infeasible under `solve --fail-if-infeasible`: neither a
/// usage error (2) nor failed work (1), so that a script tells the three apart.
pub const INFEASIBLE_EXIT: u8 = 3;

/// Why a command failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    /// A flag's value is out of its range or contradicts another flag, known before any file is
    /// read; the message names the flag. Exit 2.
    Usage(String),
    /// Anything else: an input, the work or an output failed. Exit 1.
    Work(String),
    /// The work was done and its files written, but the design is infeasible and the command
    /// line asked to fail on that (`--fail-if-infeasible`). Exit [`INFEASIBLE_EXIT`].
    Infeasible(String),
}

impl Failure {
    /// The process's exit code for this failure.
    pub fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Usage(_) => ExitCode::from(2),
            Failure::Work(_) => ExitCode::FAILURE,
            Failure::Infeasible(_) => ExitCode::from(INFEASIBLE_EXIT),
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
            Failure::Usage(message) | Failure::Work(message) | Failure::Infeasible(message) => {
                f.write_str(message)
            }
        }
    }
}
