//! The IPOPT settings of trajectory solves, apart from the robot and task model.
//!
//! A task file may hold a `solver` section; [`SolveSettings::from_section`] reads and checks it.
//! The command line overrides the linear solver ([`SolveSettings::override_linear_solver`]) and
//! asks for IPOPT's log ([`SolveSettings::verbose`]); the CLI and the workers pass the settings
//! down to every solve.

use crate::ipopt::{LinearSolver, Options};
use crate::model::task::Task;
use crate::problem::DEFAULT_HOLD_TOLERANCE_NM;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt;

/// IPOPT's convergence tolerance `tol` when a task names none.
pub const DEFAULT_TOL: f64 = 1e-8;

/// IPOPT's `max_iter` when a task names none.
pub const DEFAULT_MAX_ITER: u32 = 3000;

/// How IPOPT runs on a trajectory problem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolveSettings {
    /// Convergence tolerance `tol`; also the largest slack of an elastic solve that still counts
    /// as feasible, N m or rad/s. Absent: [`DEFAULT_TOL`].
    #[serde(default = "default_tol")]
    pub tol: f64,
    /// `max_iter`. Absent: [`DEFAULT_MAX_ITER`].
    #[serde(default = "default_max_iter")]
    pub max_iter: u32,
    /// The linear solver, `"ldl"` or `"mumps"`; absent: [`LinearSolver::default`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_solver: Option<LinearSolver>,
    /// Further IPOPT options by name: JSON integers set integer options, other numbers real
    /// options, strings string options (e.g. `"mumps_pivot_order": 6`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub options: BTreeMap<String, Value>,
    /// How a free horizon's duration is searched: the local optimum of the free problem, or
    /// that optimum shortened by the fixed-horizon rule ([`FreeHorizonSearch`]). Absent:
    /// [`FreeHorizonSearch::Local`].
    #[serde(default, skip_serializing_if = "FreeHorizonSearch::is_local")]
    pub free_horizon: FreeHorizonSearch,
    /// Show IPOPT's iteration log (a flag of the command, never read from a file).
    #[serde(skip)]
    pub verbose: bool,
}

/// How the solve of a problem with a free horizon (`{"free": [T_min, T_max]}`) searches its
/// duration (docs/model.md, section 6, "Shortening a free horizon").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FreeHorizonSearch {
    /// The local optimum the rule's first feasible start reaches (one solve where the standard
    /// guess succeeds).
    #[default]
    Local,
    /// That optimum, then shortened in rounds: the fixed-horizon rule at the current duration
    /// T, with the task's weights and box, starts the free problem bounded to [T_min, T], kept
    /// while J falls; several solves more, each round's last verdict typically infeasible.
    Descend,
}

impl crate::choice::Choice for FreeHorizonSearch {
    const ALL: &'static [FreeHorizonSearch] =
        &[FreeHorizonSearch::Local, FreeHorizonSearch::Descend];

    fn name(self) -> &'static str {
        match self {
            FreeHorizonSearch::Local => "local",
            FreeHorizonSearch::Descend => "descend",
        }
    }
}

impl FreeHorizonSearch {
    /// Whether it is the default, [`FreeHorizonSearch::Local`].
    pub fn is_local(&self) -> bool {
        *self == FreeHorizonSearch::Local
    }
}

fn default_tol() -> f64 {
    DEFAULT_TOL
}

fn default_max_iter() -> u32 {
    DEFAULT_MAX_ITER
}

impl Default for SolveSettings {
    fn default() -> SolveSettings {
        SolveSettings {
            tol: default_tol(),
            max_iter: default_max_iter(),
            linear_solver: None,
            options: BTreeMap::new(),
            free_horizon: FreeHorizonSearch::Local,
            verbose: false,
        }
    }
}

/// A `solver` section that does not make sense; names the field at fault.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SettingsError {
    /// The field, e.g. `solver.tol`.
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for SettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.field, self.message)
    }
}

impl std::error::Error for SettingsError {}

impl SettingsError {
    fn new(field: impl Into<String>, message: impl Into<String>) -> SettingsError {
        SettingsError {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl SolveSettings {
    /// Reads and checks a task file's `solver` section; none gives the defaults.
    pub fn from_section(section: Option<&Value>) -> Result<SolveSettings, SettingsError> {
        let Some(section) = section else {
            return Ok(SolveSettings::default());
        };
        let settings = crate::json_keys::read_value::<SolveSettings>(section)
            .map_err(|e| SettingsError::new(e.field("solver"), format!(": {}", e.message)))?;
        settings.validate()?;
        Ok(settings)
    }

    /// Checks `tol` > 0 and that every further option is an integer, a number or a string other
    /// than `linear_solver` (chosen by [`SolveSettings::linear_solver`] instead) and
    /// `output_file` (which would write over any file it names).
    pub fn validate(&self) -> Result<(), SettingsError> {
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return Err(SettingsError::new(
                "solver.tol",
                format!(" = {} must be > 0", self.tol),
            ));
        }
        for (name, value) in &self.options {
            let field = format!("solver.options.{name}");
            if name == "linear_solver" {
                return Err(SettingsError::new(
                    field,
                    ": choose the linear solver with solver.linear_solver (\"ldl\" or \"mumps\")",
                ));
            }
            if name == "option_file_name" {
                return Err(SettingsError::new(
                    field,
                    ": codesign reads no IPOPT options file (an `ipopt.opt` in the working folder \
                     is ignored); write each option in solver.options, where results record it",
                ));
            }
            if name == "output_file" {
                return Err(SettingsError::new(
                    field,
                    ": codesign writes no IPOPT log file (its outputs are result files and \
                     evaluation logs, written whole); `codesign solve --verbose` shows IPOPT's log",
                ));
            }
            let valid = value.as_i64().is_some_and(|v| i32::try_from(v).is_ok())
                || value.as_f64().is_some_and(f64::is_finite)
                || value.is_string();
            if !valid {
                return Err(SettingsError::new(
                    field,
                    format!(" = {value} must be an integer, a number or a string"),
                ));
            }
        }
        Ok(())
    }

    /// The violation of a constraint IPOPT accepts at an optimum, in the constraints' units:
    /// the option `constr_viol_tol` where the section sets it, else IPOPT's default
    /// ([`DEFAULT_HOLD_TOLERANCE_NM`]). The static hold's margins are judged at it.
    pub fn constraint_tolerance(&self) -> f64 {
        self.options
            .get("constr_viol_tol")
            .and_then(Value::as_f64)
            .filter(|tol| tol.is_finite() && *tol > 0.0)
            .unwrap_or(DEFAULT_HOLD_TOLERANCE_NM)
    }

    /// The linear solver of the solves: the one named, else the default.
    pub fn linear_solver(&self) -> LinearSolver {
        self.linear_solver.unwrap_or_default()
    }

    /// Applies a `--linear-solver` flag: the solver given replaces the task's.
    pub fn override_linear_solver(&mut self, flag: Option<LinearSolver>) {
        if flag.is_some() {
            self.linear_solver = flag;
        }
    }

    /// The section as result files and evaluation logs record it: the linear solver is recorded
    /// in a field of its own (so that a log written before it existed compares by that field).
    pub fn recorded(&self) -> SolveSettings {
        SolveSettings {
            linear_solver: None,
            ..self.clone()
        }
    }

    /// IPOPT options of a trajectory solve: exact Hessian, the linear solver, `tol`, `max_iter`
    /// and the further `options` (checked by [`SolveSettings::validate`]).
    pub fn ipopt_options(&self) -> Options {
        let mut options = Options::new()
            .linear_solver(self.linear_solver())
            .str("hessian_approximation", "exact")
            .num("tol", self.tol)
            .int("max_iter", i32::try_from(self.max_iter).unwrap_or(i32::MAX))
            .verbose(self.verbose);
        for (name, value) in &self.options {
            options = match (
                value.as_i64().and_then(|v| i32::try_from(v).ok()),
                value.as_f64(),
                value.as_str(),
            ) {
                (Some(integer), _, _) => options.int(name, integer),
                (None, Some(number), _) => options.num(name, number),
                (None, None, Some(text)) => options.str(name, text),
                _ => options,
            };
        }
        options
    }
}

/// A task as result files and evaluation logs record it: the task's fields, then the `solver`
/// section it was solved with, as in a task file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskRecord {
    /// The task with every override applied.
    #[serde(flatten)]
    pub task: Task,
    /// The settings it was solved with.
    pub solver: SolveSettings,
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_missing_section_gives_the_defaults_and_the_built_in_one_reads() {
        assert_eq!(
            SolveSettings::from_section(None).unwrap(),
            SolveSettings::default()
        );
        let section = json!({"tol": 1e-8, "max_iter": 3000, "options": {"mumps_pivot_order": 6}});
        let settings = SolveSettings::from_section(Some(&section)).unwrap();
        assert_eq!(settings.tol, DEFAULT_TOL);
        let mumps = SolveSettings::from_section(Some(&json!({"linear_solver": "mumps"}))).unwrap();
        assert_eq!((mumps.tol, mumps.max_iter), (DEFAULT_TOL, DEFAULT_MAX_ITER));
        assert_eq!(mumps.linear_solver(), LinearSolver::Mumps);
        assert_eq!(settings.linear_solver(), LinearSolver::Ldl);
        assert_eq!(serde_json::to_value(&settings).unwrap(), section);
    }

    #[test]
    fn errors_name_the_field() {
        let cases = [
            (
                json!({"tol": 0.0, "max_iter": 10}),
                "solver.tol = 0 must be > 0",
            ),
            (
                json!({"tol": 1e-8, "max_iter": 10, "options": {"linear_solver": "ma27"}}),
                "solver.options.linear_solver: choose",
            ),
            (
                json!({"tol": 1e-8, "max_iter": 10, "options": {"x": [1]}}),
                "solver.options.x = [1] must be",
            ),
            (
                json!({"tol": 1e-8, "max_iter": 10, "tool": 1}),
                "unknown field `tool`",
            ),
            (
                json!({"options": {"output_file": "task.json"}}),
                "solver.options.output_file: codesign writes no IPOPT log file",
            ),
            (
                json!({"options": {"option_file_name": "mine.opt"}}),
                "solver.options.option_file_name: codesign reads no IPOPT options file",
            ),
            (
                json!({"tol": 1e-8, "max_iter": 10, "linear_solver": "ma57"}),
                "solver.linear_solver: unknown variant `ma57`",
            ),
            (
                json!({"max_iter": 1e20}),
                "solver.max_iter: invalid type: floating point",
            ),
        ];
        for (section, expected) in cases {
            let message = SolveSettings::from_section(Some(&section))
                .unwrap_err()
                .to_string();
            assert!(message.contains(expected), "{message}");
        }
    }

    #[test]
    fn the_flag_overrides_the_section_and_the_record_leaves_it_out() {
        let mut settings = SolveSettings {
            linear_solver: Some(LinearSolver::Ldl),
            ..SolveSettings::default()
        };
        settings.override_linear_solver(None);
        assert_eq!(settings.linear_solver(), LinearSolver::Ldl);
        settings.override_linear_solver(Some(LinearSolver::Mumps));
        assert_eq!(settings.linear_solver(), LinearSolver::Mumps);
        assert_eq!(settings.recorded().linear_solver, None);
        assert_eq!(settings.ipopt_options().linear_solver, LinearSolver::Mumps);
    }

    #[test]
    fn a_recorded_task_reads_back_as_written() {
        let path = crate::testing::repository().join("results/quick/runs/actuation-1kg-seed0.json");
        let text = std::fs::read_to_string(path).unwrap();
        let document: Value = serde_json::from_str(&text).unwrap();
        let written = &document["inputs"]["task"];
        let record: TaskRecord = serde_json::from_value(written.clone()).unwrap();
        assert_eq!(record.solver.options["mumps_pivot_order"], 6);
        assert_eq!(&serde_json::to_value(&record).unwrap(), written);
        // Field for field, in the order written.
        let again = serde_json::to_string_pretty(&record).unwrap();
        let start = text.find("\"task\": {").unwrap();
        assert!(text[start..].contains(&again.replace('\n', "\n    ")[1..]));
    }
}
