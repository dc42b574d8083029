//! `codesign check`: inspects a robot and its task before any solve, and lists every problem.

use super::common::{finite_ratio, ModelArgs};
use super::failure::Failure;
use crate::report::check::{Inspection, TaskInspection};
use codesign_core::text::shown;

/// Flags of `codesign check`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Gear ratios of the design to inspect, one per ratio of the task's transmission; default:
    /// the task's original design.
    #[arg(
        long,
        value_name = "R1,R2,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = finite_ratio
    )]
    ratios: Option<Vec<f64>>,
    /// Print the inspection as one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Loads and inspects; prints the inspection; fails (exit 1) listing every error found, and
/// notes each warning on stderr (warnings alone: exit 0). With `--robot` and no `--task`, the
/// robot alone: its chain, its notes and its tip link. A task with a `motions` list is
/// inspected motion by motion.
pub fn run(args: &Args) -> Result<(), Failure> {
    args.model.validate()?;
    let (task, robot, settings, alone) = args.model.load_robot()?;
    if alone {
        let inspection = TaskInspection::One(Box::new(Inspection::of_robot(&robot)));
        return print(&inspection, args.json);
    }
    let tolerance = settings.constraint_tolerance();
    let inspection = TaskInspection::of(&task, &robot, args.ratios.as_deref(), tolerance)
        .map_err(|e| format!("{}: {e}", args.model.source()))?;
    print(&inspection, args.json)?;
    for warning in &inspection.warnings() {
        note!("warning: {}", shown(warning));
    }
    let problems = &inspection.problems();
    if problems.is_empty() {
        return Ok(());
    }
    let listed: Vec<String> = problems.iter().map(|p| shown(p)).collect();
    Err(Failure::Work(format!(
        "{} problem(s) found: {}",
        problems.len(),
        listed.join("; ")
    )))
}

/// Prints the inspection as text, or as JSON (one object, or one per motion).
fn print(inspection: &TaskInspection, json: bool) -> Result<(), Failure> {
    if json {
        let text = serde_json::to_string_pretty(inspection).map_err(|e| e.to_string())?;
        say!("{text}");
    } else {
        say_raw!("{}", inspection.to_text());
    }
    Ok(())
}
