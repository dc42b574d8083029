//! The flags of `codesign tradeoff`: the design, the durations of its capacity against duration
//! or the payloads of its T* against payload, the capacity search's settings and the output.

use super::common::{finite_ratio, listed_number, ModelArgs, ProblemArgs};
use super::failure::Failure;
use super::store_hints::check_output;
use crate::design::capacity::CapacitySettings;
use crate::report::tradeoff::plot_beside;
use codesign_core::model::task::Task;
use std::path::PathBuf;

/// Flags of `codesign tradeoff`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub(super) model: ModelArgs,
    #[command(flatten)]
    pub(super) problem: ProblemArgs,
    /// Durations T of the motion, s: at each, the heaviest payload the design moves within T
    /// (as `capacity --duration T`).
    #[arg(
        long,
        required_unless_present = "payloads",
        conflicts_with = "payloads",
        value_name = "S,S,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = listed_number
    )]
    pub(super) durations: Vec<f64>,
    /// Payloads, kg, increasing: at each, the least duration T* of the design's motion (its
    /// pure minimum-time problem); the first payload it cannot move within T_max ends its curve.
    #[arg(
        long,
        conflicts_with_all = ["resolution", "first_step", "max"],
        value_name = "KG,KG,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = listed_number
    )]
    pub(super) payloads: Option<Vec<f64>>,
    /// With `--payloads`: another design whose curve the file and its plot hold too (R1,R2,..);
    /// repeatable.
    #[arg(long, value_name = "R1,R2,..", action = clap::ArgAction::Append)]
    pub(super) compare: Vec<String>,
    /// Gear ratios of the design, one per ratio of the task's transmission (r1,r2,..); default:
    /// the task's original design.
    #[arg(
        long,
        value_name = "R1,R2,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = finite_ratio
    )]
    pub(super) ratios: Option<Vec<f64>>,
    /// Width of the final bracket of each search, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().resolution_kg)]
    pub(super) resolution: f64,
    /// First payload tried after 0 kg in each search, doubled until infeasible, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().first_step_kg)]
    pub(super) first_step: f64,
    /// Largest payload tried, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().max_kg)]
    pub(super) max: f64,
    /// Write the trade-off as JSON to this file and its plot beside it as the same name ending
    /// in .svg (both checked before the searches, as `capacity --out`).
    #[arg(long, value_name = "FILE.json")]
    pub(super) out: Option<PathBuf>,
}

impl Args {
    /// The `--out` file and the plot beside it (the same name ending in .svg), each checked as
    /// an output of a run on `task`; None without `--out`.
    pub(super) fn outputs(&self, task: &Task) -> Result<Option<(PathBuf, PathBuf)>, Failure> {
        let Some(out) = &self.out else {
            return Ok(None);
        };
        let plot = plot_beside(out)
            .map_err(|why| Failure::Usage(format!("--out {}: {why}", out.display())))?;
        let choice = self.model.choice();
        let inputs = choice.inputs(task);
        check_output("--out", out, &inputs)?;
        check_output("--out", &plot, &inputs)?;
        Ok(Some((out.clone(), plot)))
    }
}
