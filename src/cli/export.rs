//! `codesign solve --export FILE.csv --rate HZ`: the solution resampled at a controller's rate
//! ([`crate::report::export`]), checked before the solve and written whole or not at all.

use super::failure::Failure;
use super::store_hints::{check_output, hint};
use crate::report::export::{grid_rows, resample, ExportError};
use crate::store::files::{resolved, write_atomic};
use codesign_core::problem::Formulation;
use codesign_core::solve::TrajectoryResult;
use codesign_core::text::number;
use std::path::{Path, PathBuf};

/// The flags of the export.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Write the trajectory resampled at `--rate` as CSV to this file: time, the joints'
    /// positions, speeds, accelerations and torques, the motors' positions, speeds, torques
    /// and (where the task gives their torque constants) currents, interpolated as the
    /// transcription integrates (docs/guide/results.md).
    #[arg(long, value_name = "FILE.csv", requires = "rate")]
    export: Option<PathBuf>,
    /// The rate of `--export`, samples per second: rows at t = i / HZ from 0 to the motion's
    /// end.
    #[arg(
        long,
        value_name = "HZ",
        requires = "export",
        allow_negative_numbers = true
    )]
    rate: Option<f64>,
}

impl ExportArgs {
    /// Whether `--export` was given.
    pub fn is_requested(&self) -> bool {
        self.export.is_some()
    }

    /// Checks, before the solve, that `--rate` gives a grid an export holds over `duration_s`
    /// and that `--export` can be written, is none of `inputs` and is not `--out`.
    pub fn check(
        &self,
        duration_s: f64,
        out: Option<&Path>,
        inputs: &[(&str, &Path)],
    ) -> Result<(), Failure> {
        let (Some(path), Some(rate)) = (&self.export, self.rate) else {
            return Ok(());
        };
        grid_rows(rate, duration_s).map_err(|e| rate_failure(rate, &e))?;
        if out.is_some_and(|out| resolved(out) == resolved(path)) {
            return Err(Failure::Usage(format!(
                "--export {}: the same file as --out; give the export a file of its own",
                path.display()
            )));
        }
        check_output("--export", path, inputs)?;
        Ok(())
    }

    /// Writes the export of `result`, solved for `formulation`, where asked, and says so.
    pub fn write(
        &self,
        formulation: &Formulation,
        result: &TrajectoryResult,
    ) -> Result<(), Failure> {
        let (Some(path), Some(rate)) = (&self.export, self.rate) else {
            return Ok(());
        };
        let table = resample(formulation, result, rate).map_err(|e| match e {
            ExportError::Rate(_) => rate_failure(rate, &e),
            _ => Failure::from(format!("--export {}: {e}", path.display())),
        })?;
        write_atomic(path, table.to_csv().as_bytes()).map_err(|e| hint(e, "--export"))?;
        let infeasible = match result.feasible {
            true => String::new(),
            false => "; note: the design is infeasible (the verdict above), so this motion is \
                      not one its motors can run within every limit"
                .to_owned(),
        };
        say!(
            "trajectory exported to {} ({} rows at {} Hz){infeasible}",
            path.display(),
            table.rows(),
            number(rate)
        );
        Ok(())
    }
}

/// The failure of a `--rate` that makes no export.
fn rate_failure(rate: f64, error: &ExportError) -> Failure {
    Failure::Usage(format!("--rate {}: {error}", number(rate)))
}
