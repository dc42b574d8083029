//! A solve document read as the start of another solve (`codesign solve --start FILE`): its
//! `start_point`, checked against the problem about to be solved, and the record the new result
//! keeps of it (`inputs.start`).

use super::solve_document::StartRecord;
use super::table::{read_result_file, ResultFile};
use super::{ReadFailure, ReportError};
use codesign_core::problem::Formulation;
use codesign_core::solve::{StartError, StartPoint};
use std::fmt;
use std::path::{Path, PathBuf};

/// A start read from a solve document: the point and what the new result records of it.
#[derive(Clone, Debug, PartialEq)]
pub struct StartFile {
    /// The point and multipliers, checked to fit.
    pub point: StartPoint,
    /// The record of it for the new result's inputs.
    pub record: StartRecord,
}

/// Why a file cannot start a solve; each names the file.
#[derive(Clone, Debug, PartialEq)]
pub enum StartFileError {
    /// The file is not read, not JSON, or no codesign result ([`read_result_file`]).
    Read(ReportError),
    /// The file is a result of another kind than a solve.
    NotASolve {
        /// The file.
        path: PathBuf,
        /// Its kind: `optimize`, `capacity`, `table`.
        kind: &'static str,
    },
    /// A solve's result without `start_point`: written before it was recorded, or by
    /// `reproduce`.
    NoStartPoint {
        /// The file.
        path: PathBuf,
    },
    /// The start does not fit the problem about to be solved.
    Fits {
        /// The file.
        path: PathBuf,
        /// Why.
        error: StartError,
    },
}

impl fmt::Display for StartFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StartFileError::Read(error) => write!(f, "{error}"),
            StartFileError::NotASolve { path, kind } => write!(
                f,
                "{}: a codesign {kind} result, not a solve's (write a start with `codesign solve \
                 --out`)",
                path.display()
            ),
            StartFileError::NoStartPoint { path } => write!(
                f,
                "{}: a solve result without `start_point` (written by `reproduce`, or by a \
                 codesign before it was recorded): solve again with `codesign solve --out`",
                path.display()
            ),
            StartFileError::Fits { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for StartFileError {}

/// Reads the solve document at `path` as the start of a solve of `formulation`'s problem for the
/// task of hash `task_hash`: its `start_point`, checked to fit ([`StartPoint::check_fits`]).
pub fn read_start(
    path: &Path,
    formulation: &Formulation,
    task_hash: &str,
) -> Result<StartFile, StartFileError> {
    let other = |kind| StartFileError::NotASolve {
        path: path.to_owned(),
        kind,
    };
    let document = match read_result_file(path) {
        Ok(ResultFile::Solve(document)) => document,
        Ok(ResultFile::Optimize(_)) => return Err(other("optimize")),
        Ok(ResultFile::Capacity(_)) => return Err(other("capacity")),
        Err(ReportError::Read {
            why: ReadFailure::Table,
            ..
        }) => return Err(other("table")),
        Err(error) => return Err(StartFileError::Read(error)),
    };
    let point = (document.start_point).ok_or_else(|| StartFileError::NoStartPoint {
        path: path.to_owned(),
    })?;
    point
        .check_fits(formulation, task_hash)
        .map_err(|error| StartFileError::Fits {
            path: path.to_owned(),
            error,
        })?;
    Ok(StartFile {
        point,
        record: StartRecord {
            file: path.display().to_string(),
            ratios: document.inputs.ratios,
            payload_kg: document.inputs.payload_kg,
        },
    })
}
