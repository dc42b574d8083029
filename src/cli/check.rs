//! `codesign check`: inspects a robot and its task before any solve, and lists every problem.

use super::common::{finite_ratio, ModelArgs};
use super::failure::Failure;
use crate::report::check::Inspection;
use crate::transmission::Transmission;

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
    let transmission =
        Transmission::from_spec(&task.transmission).map_err(|e| format!("{source}: {e}"))?;
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
