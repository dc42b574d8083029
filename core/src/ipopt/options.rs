//! Typed IPOPT options.

use crate::choice::Choice;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::PathBuf;

/// The sparse symmetric indefinite solver IPOPT factorises its KKT systems with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearSolver {
    /// This crate's sparse LDLᵀ (`crate::ldl`), plugged in through IPOPT's Pardiso interface.
    /// Several solves may run on different threads at once.
    #[default]
    Ldl,
    /// MUMPS, IPOPT's built-in solver in Debian's build. Not thread-safe: solves with it are
    /// serialised within a process.
    Mumps,
}

impl Choice for LinearSolver {
    const ALL: &'static [LinearSolver] = &[LinearSolver::Ldl, LinearSolver::Mumps];

    fn name(self) -> &'static str {
        LinearSolver::name(self)
    }
}

impl LinearSolver {
    /// The value of IPOPT's `linear_solver` option that selects this solver.
    pub fn ipopt_name(self) -> &'static str {
        match self {
            LinearSolver::Ldl => "pardiso",
            LinearSolver::Mumps => "mumps",
        }
    }

    /// The name users give it (`--linear-solver`, the task's `solver.linear_solver`, result files).
    pub fn name(self) -> &'static str {
        match self {
            LinearSolver::Ldl => "ldl",
            LinearSolver::Mumps => "mumps",
        }
    }
}

impl fmt::Display for LinearSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The value of one IPOPT option, typed as IPOPT registers it.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    /// A string option, e.g. `hessian_approximation = exact`.
    Str(String),
    /// An integer option, e.g. `max_iter = 3000`.
    Int(i32),
    /// A real option, e.g. `tol = 1e-8`.
    Num(f64),
}

/// The options of one solve, applied in the order they were set.
///
/// By default IPOPT's banner and iteration log are silenced (`print_level = 0`); [`Options::verbose`]
/// turns the log back on. An option IPOPT rejects makes the solve fail with
/// [`crate::ipopt::Error::InvalidOption`] naming it. The linear solver is chosen with
/// [`Options::linear_solver`], never through IPOPT's raw `linear_solver` option.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    pub(crate) entries: Vec<(String, OptionValue)>,
    pub(crate) linear_solver: LinearSolver,
    pub(crate) verbose: bool,
    pub(crate) output_file: Option<(PathBuf, i32)>,
}

impl Options {
    /// Empty options: IPOPT's defaults, with output silenced.
    pub fn new() -> Options {
        Options::default()
    }

    /// Sets a string option.
    pub fn str(mut self, name: &str, value: &str) -> Options {
        self.set(name, OptionValue::Str(value.to_owned()));
        self
    }

    /// Sets an integer option.
    pub fn int(mut self, name: &str, value: i32) -> Options {
        self.set(name, OptionValue::Int(value));
        self
    }

    /// Sets a real option.
    pub fn num(mut self, name: &str, value: f64) -> Options {
        self.set(name, OptionValue::Num(value));
        self
    }

    /// Chooses the linear solver (default: [`LinearSolver::default`]).
    pub fn linear_solver(mut self, solver: LinearSolver) -> Options {
        self.linear_solver = solver;
        self
    }

    /// Shows IPOPT's banner and iteration log on standard output (print level 5 unless
    /// `print_level` is set explicitly).
    pub fn verbose(mut self, verbose: bool) -> Options {
        self.verbose = verbose;
        self
    }

    /// Also writes IPOPT's log to `path` at `print_level` (0-12), independent of the console.
    pub fn output_file(mut self, path: impl Into<PathBuf>, print_level: i32) -> Options {
        self.output_file = Some((path.into(), print_level));
        self
    }

    /// The value set for `name`, if any.
    pub fn get(&self, name: &str) -> Option<&OptionValue> {
        self.entries
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, value)| value)
    }

    fn set(&mut self, name: &str, value: OptionValue) {
        match self.entries.iter_mut().find(|(key, _)| key == name) {
            Some(entry) => entry.1 = value,
            None => self.entries.push((name.to_owned(), value)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn later_values_replace_earlier_ones() {
        let options = Options::new()
            .num("tol", 1e-6)
            .int("max_iter", 10)
            .num("tol", 1e-8);
        assert_eq!(options.get("tol"), Some(&OptionValue::Num(1e-8)));
        assert_eq!(options.entries.len(), 2);
        assert_eq!(options.get("mu_strategy"), None);
    }
}
