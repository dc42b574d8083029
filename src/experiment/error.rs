//! Why an experiment stopped: what failed, in the library's words. The command line adds the
//! flags that lead on (`--resume`, `--from-runs`, `--out`).

use crate::design::capacity::CapacityError;
use crate::design::run::RunError;
use crate::report::ReportError;
use crate::store::StoreError;
use codesign_core::model::task::TaskSource;
use codesign_core::model::ModelError;
use codesign_core::problem::FormulationError;
use codesign_core::solve::{SettingsError, SolveError};
use std::fmt;
use std::path::PathBuf;

/// Why an experiment's stages, its merge or its table failed.
#[derive(Debug)]
pub enum ExperimentError {
    /// The task's `solver` section is out of range.
    Settings {
        /// The task.
        source: TaskSource,
        /// What is wrong.
        error: SettingsError,
    },
    /// The task lists several motions (`motions`): an experiment's payloads, capacities and
    /// table are of one motion.
    SeveralMotions {
        /// The task.
        source: TaskSource,
        /// How many motions it lists.
        motions: usize,
    },
    /// The task's robot could not be read.
    Model(ModelError),
    /// The task could not be formulated at a payload.
    Formulation(FormulationError),
    /// The original design could not be solved.
    Original {
        /// The task.
        source: TaskSource,
        /// Why.
        error: SolveError,
    },
    /// A co-design run failed.
    Run(RunError),
    /// A capacity search could not run.
    Capacity(CapacityError),
    /// A plot or the index page could not be made.
    Report(ReportError),
    /// A folder, a result or the table could not be written or removed.
    Store(StoreError),
    /// The runs' folder holds evaluation logs of an earlier reproduction, which a fresh start
    /// would replace.
    EarlierLogs {
        /// The runs' folder.
        folder: PathBuf,
        /// Its first log, by name.
        first: PathBuf,
        /// How many more it holds.
        more: usize,
    },
    /// The results of the plan's commands cannot be merged.
    Merge(MergeError),
}

impl fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExperimentError::Settings { source, error } => write!(f, "{source}: {error}"),
            ExperimentError::SeveralMotions { source, motions } => write!(
                f,
                "{source}: reproduce runs an experiment of one motion (its payloads, payload \
                 capacities and table are of one motion), and the task lists {motions} motions \
                 (`motions`); co-design them with `codesign optimize` (the cost or energy \
                 objective)"
            ),
            ExperimentError::Model(error) => error.fmt(f),
            ExperimentError::Formulation(error) => error.fmt(f),
            ExperimentError::Original { source, error } => match error {
                SolveError::Design(_) => write!(f, "{source} transmission.original: {error}"),
                SolveError::Ipopt(_) => write!(f, "{source} solver: {error}"),
                SolveError::Formulation(_) | SolveError::Pose { .. } => {
                    write!(f, "{source}: {error}")
                }
            },
            ExperimentError::Run(error) => error.fmt(f),
            ExperimentError::Capacity(error) => error.fmt(f),
            ExperimentError::Report(error) => error.fmt(f),
            ExperimentError::Store(error) => error.fmt(f),
            ExperimentError::EarlierLogs {
                folder,
                first,
                more,
            } => write!(
                f,
                "{} holds the evaluation logs of an earlier reproduction ({} and {more} more)",
                folder.display(),
                first.display()
            ),
            ExperimentError::Merge(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for ExperimentError {}

impl From<ModelError> for ExperimentError {
    fn from(error: ModelError) -> ExperimentError {
        ExperimentError::Model(error)
    }
}

impl From<FormulationError> for ExperimentError {
    fn from(error: FormulationError) -> ExperimentError {
        ExperimentError::Formulation(error)
    }
}

impl From<RunError> for ExperimentError {
    fn from(error: RunError) -> ExperimentError {
        ExperimentError::Run(error)
    }
}

impl From<CapacityError> for ExperimentError {
    fn from(error: CapacityError) -> ExperimentError {
        ExperimentError::Capacity(error)
    }
}

impl From<ReportError> for ExperimentError {
    fn from(error: ReportError) -> ExperimentError {
        ExperimentError::Report(error)
    }
}

impl From<StoreError> for ExperimentError {
    fn from(error: StoreError) -> ExperimentError {
        ExperimentError::Store(error)
    }
}

impl From<MergeError> for ExperimentError {
    fn from(error: MergeError) -> ExperimentError {
        ExperimentError::Merge(error)
    }
}

/// Why the results of a plan's commands cannot be merged.
#[derive(Clone, Debug, PartialEq)]
pub enum MergeError {
    /// A result the plan's commands write is missing.
    Missing(PathBuf),
    /// A result could not be read, or is no codesign result.
    Read(ReportError),
    /// A result is of another kind than its place in the layout holds.
    WrongKind {
        /// The file.
        path: PathBuf,
        /// What it should be, e.g. "a `solve` result".
        expected: &'static str,
    },
    /// A result records another task hash than the plan's.
    OtherTask {
        /// The file.
        path: PathBuf,
        /// The hash it records.
        recorded: String,
        /// The task file it names.
        task_file: String,
        /// The plan's task hash.
        expected: String,
    },
    /// A co-design result was made with other settings than the plan's run.
    NotPlanned {
        /// The file.
        path: PathBuf,
        /// The settings in which it differs, in words.
        differences: Vec<String>,
    },
    /// The results make no table together (an odd value, an edited file).
    Check(ReportError),
}

impl fmt::Display for MergeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MergeError::Missing(path) => write!(f, "{} is missing", path.display()),
            MergeError::Read(error) | MergeError::Check(error) => error.fmt(f),
            MergeError::WrongKind { path, expected } => {
                write!(f, "{} is not {expected}", path.display())
            }
            MergeError::OtherTask {
                path,
                recorded,
                task_file,
                expected,
            } => write!(
                f,
                "{} is a result of another task (task hash {recorded}, task file {task_file}) \
                 than the plan's (task hash {expected})",
                path.display()
            ),
            MergeError::NotPlanned { path, differences } => write!(
                f,
                "{} is not the plan's run ({})",
                path.display(),
                differences.join("; ")
            ),
        }
    }
}

impl std::error::Error for MergeError {}
