//! `codesign check`: inspects a robot and its task before any solve, and lists every problem.

use super::common::{finite_ratio, ModelArgs};
use super::failure::Failure;
use crate::report::check::Inspection;
use crate::report::mechanism::{linkage_reports, linkages_text, LinkageReport};
use codesign_core::dynamics::Dynamics;
use codesign_core::transmission::Transmission;

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
        print(&inspection, &[], args.json)?;
        return Ok(());
    }
    let source = args.model.source();
    let dynamics = Dynamics::new(robot.clone());
    let transmission = Transmission::on_chain(&task.transmission, &dynamics)
        .map_err(|e| format!("{source}: {e}"))?;
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
    // The linkages at the design inspected where it is valid (the inspection names it otherwise).
    let original = &task.transmission.original;
    let design = match transmission.check_design(&ratios) {
        Ok(()) => &ratios,
        Err(_) => original,
    };
    let reports =
        linkage_reports(&task, &dynamics, design).map_err(|e| format!("{source}: {e}"))?;
    print(&inspection, &reports, args.json)?;
    let mut problems = inspection.problems();
    for report in &reports {
        let motor = &report.motor;
        problems.extend(report.warnings.iter().map(|w| format!("{motor}: {w}")));
    }
    if problems.is_empty() {
        return Ok(());
    }
    Err(Failure::Work(format!(
        "{} problem(s) found: {}",
        problems.len(),
        problems.join("; ")
    )))
}

/// Prints the inspection, and the linkages' readings where the transmission has linkage rows
/// (docs/model.md, section 17), as text, or as one JSON object (the linkages under `linkages`).
fn print(inspection: &Inspection, linkages: &[LinkageReport], json: bool) -> Result<(), String> {
    if json {
        let mut value = serde_json::to_value(inspection).map_err(|e| e.to_string())?;
        if let (Some(object), false) = (value.as_object_mut(), linkages.is_empty()) {
            let readings = serde_json::to_value(linkages).map_err(|e| e.to_string())?;
            object.insert("linkages".into(), readings);
        }
        let text = serde_json::to_string_pretty(&value).map_err(|e| e.to_string())?;
        say!("{text}");
    } else {
        say_raw!("{}", inspection.to_text());
        if !linkages.is_empty() {
            say_raw!("{}", linkages_text(linkages));
        }
    }
    Ok(())
}
