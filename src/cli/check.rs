//! `codesign check`: inspects a robot and its task before any solve, and lists every problem.

use super::common::{finite_ratio, ModelArgs};
use super::failure::Failure;
use crate::dynamics::Dynamics;
use crate::model::task::Task;
use crate::model::Robot;
use crate::report::check::Inspection;
use crate::report::mechanism::{linkage_reports, linkages_text};
use crate::transmission::{SpecError, Transmission};

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

/// Loads and inspects; prints the inspection; fails (exit 1) listing every problem found. With
/// `--robot` and no `--task`, the robot alone: its chain, its notes and its tip link.
pub fn run(args: &Args) -> Result<(), Failure> {
    args.model.validate()?;
    let (task, robot, settings, alone) = args.model.load_robot()?;
    if alone {
        let inspection = Inspection::of_robot(&robot);
        print(&inspection, args.json)?;
        return Ok(());
    }
    let source = args.model.source();
    let transmission = match Transmission::from_spec(&task.transmission) {
        Err(SpecError::PoseDependent { .. }) => {
            return linkages(&task, robot, args.json, &source.to_string())
        }
        other => other.map_err(|e| format!("{source}: {e}"))?,
    };
    if transmission.dof() != robot.dof() {
        return Err(Failure::Work(format!(
            "{source}: transmission.matrix is {0}x{0} but the robot has {1} moving joints",
            transmission.dof(),
            robot.dof()
        )));
    }
    let ratios = args
        .ratios
        .clone()
        .unwrap_or_else(|| task.transmission.original.clone());
    let tolerance = settings.constraint_tolerance();
    let inspection = Inspection::of(&task, &robot, (&transmission, &ratios), tolerance);
    print(&inspection, args.json)?;
    let problems = inspection.problems();
    if problems.is_empty() {
        return Ok(());
    }
    Err(Failure::Work(format!(
        "{} problem(s) found: {}",
        problems.len(),
        problems.join("; ")
    )))
}

/// Shows the linkage rows of a transmission whose ratio changes with the pose (the constant
/// rows' inspection is not yet written for such a task); fails listing the linkages' warnings
/// (dead points, loops open, strokes left), if any.
fn linkages(task: &Task, robot: Robot, json: bool, source: &str) -> Result<(), Failure> {
    let dynamics = Dynamics::new(robot);
    let reports = linkage_reports(task, &dynamics).map_err(|e| format!("{source}: {e}"))?;
    if json {
        let object = serde_json::json!({ "linkages": reports });
        let text = serde_json::to_string_pretty(&object).map_err(|e| e.to_string())?;
        say!("{text}");
    } else {
        say_raw!("{}", linkages_text(&reports));
    }
    let warnings: Vec<String> = (reports.iter())
        .flat_map(|report| {
            let motor = &report.motor;
            report.warnings.iter().map(move |w| format!("{motor}: {w}"))
        })
        .collect();
    if warnings.is_empty() {
        return Ok(());
    }
    Err(Failure::Work(format!(
        "{source}: {} problem(s) found in the linkages: {}",
        warnings.len(),
        warnings.join("; ")
    )))
}

/// Prints the inspection as text, or as JSON.
fn print(inspection: &Inspection, json: bool) -> Result<(), String> {
    if json {
        let text = serde_json::to_string_pretty(inspection).map_err(|e| e.to_string())?;
        say!("{text}");
    } else {
        say_raw!("{}", inspection.to_text());
    }
    Ok(())
}
