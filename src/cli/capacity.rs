//! `codesign capacity`: the largest payload a design can move through the task.

use super::common::{finite_ratio, ModelArgs, ProblemArgs};
use super::failure::Failure;
use super::store_hints::check_output;
use crate::design::capacity::{payload_capacity, Capacity, CapacityLimit, CapacitySettings};
use crate::design::run::{Loaded, RecordedHash};
use crate::report::codesign::{CapacityDocument, CapacityInputs};
use crate::store::document::write_document;
use codesign_core::model::task::{check_horizon, Horizon};
use codesign_core::problem::Formulation;
use codesign_core::solve::ToolInfo;
use codesign_core::text::{listed, number, numbers};
use std::path::PathBuf;

/// Flags of `codesign capacity`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    problem: ProblemArgs,
    /// Gear ratios of the design, one per ratio of the task's transmission (r1,r2,..); default:
    /// the task's original design.
    #[arg(
        long,
        value_name = "R1,R2,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = finite_ratio
    )]
    ratios: Option<Vec<f64>>,
    /// Width of the final bracket, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().resolution_kg)]
    resolution: f64,
    /// First payload tried after 0 kg, doubled until infeasible, kg (by default the first step
    /// of the rule's payload continuation, whose steps the bracketing then climbs).
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().first_step_kg)]
    first_step: f64,
    /// Duration T of the motion each payload is moved in, s: the heaviest payload moved within T
    /// (a fixed duration); default: the task's `motion.horizon_s`.
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Largest payload tried, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().max_kg)]
    max: f64,
    /// Write the search as JSON to this file (checked before the search; a symbolic link is
    /// followed, an input file, a folder, a special file or a file the user may not write
    /// refused; a file replaced keeps its permissions).
    #[arg(long, value_name = "FILE.json")]
    out: Option<PathBuf>,
}

/// Searches the capacity, prints it, writes the file.
pub fn run(args: &Args) -> Result<(), Failure> {
    let settings = search_settings(args).map_err(Failure::Usage)?;
    args.model.validate()?;
    let Loaded {
        mut task,
        robot,
        settings: mut solve,
        task_hash,
    } = args.model.load()?;
    if task.has_motions() {
        return Err(Failure::from(format!(
            "{}: a payload capacity is the heaviest payload of one motion, and the task lists {} \
             motions (`motions`); search each motion's capacity with a task of that motion alone",
            args.model.source(),
            task.motions.len()
        )));
    }
    if let Some(duration) = args.duration {
        task.motion.horizon = Horizon::Fixed(duration);
    }
    args.problem.configure(&mut solve);
    if let Some(path) = &args.out {
        check_output("--out", path, &args.model.choice().inputs(&task))?;
    }
    let modes = args.problem.modes(&task);
    let ratios = args
        .ratios
        .clone()
        .unwrap_or_else(|| task.transmission.original.clone());
    let formulation = Formulation::new(&task, robot, args.problem.space, modes)
        .map_err(|e| format!("{}: {e}", args.model.source()))?
        .with_hold_tolerance(solve.constraint_tolerance());
    formulation
        .transmission()
        .check_design(&ratios)
        .map_err(|e| match &args.ratios {
            Some(_) => format!("--ratios {}: invalid design: {e}", listed(&ratios)),
            None => format!(
                "{} transmission.original ({}): invalid design: {e}",
                args.model.source(),
                listed(&ratios)
            ),
        })?;
    let capacity = payload_capacity(&formulation, &solve, &ratios, &settings)
        .map_err(|e| format!("{}: {e}", args.model.source()))?;
    print_capacity(&formulation, &ratios, &capacity)?;
    if let Some(path) = &args.out {
        let document = CapacityDocument {
            tool: ToolInfo::current(solve.linear_solver()),
            inputs: CapacityInputs {
                task_file: args.model.source().label(),
                task_hash: RecordedHash(Some(task_hash)),
                space: args.problem.space,
                ratios: ratios.clone(),
                limit_modes: modes,
                ends: task.motion.ends,
                settings,
                duration_s: args.duration,
            },
            capacity,
        };
        write_document(path, &document).map_err(|e| e.to_string())?;
        say!("result written to {}", path.display());
    }
    Ok(())
}

/// The search's settings from the flags, checked as the library checks them
/// ([`CapacitySettings::validate`]).
fn search_settings(args: &Args) -> Result<CapacitySettings, String> {
    if args.model.payload.is_some() {
        return Err("--payload: capacity searches the payload itself; leave it out".to_owned());
    }
    if let Some(duration) = args.duration {
        check_horizon(duration).map_err(|why| format!("--duration {}: {why}", number(duration)))?;
    }
    capacity_settings(args.resolution, args.first_step, args.max)
}

/// The search's settings of flags `--resolution`, `--first-step` and `--max`, checked as the
/// library checks them ([`CapacitySettings::validate`]), an error naming the flag.
pub(super) fn capacity_settings(
    resolution_kg: f64,
    first_step_kg: f64,
    max_kg: f64,
) -> Result<CapacitySettings, String> {
    let settings = CapacitySettings {
        resolution_kg,
        first_step_kg,
        max_kg,
    };
    settings.validate().map_err(|error| {
        let flag = match error.key {
            "resolution_kg" => "--resolution",
            "first_step_kg" => "--first-step",
            _ => "--max",
        };
        format!("{flag} {}: {}", number(error.value), error.rule())
    })?;
    Ok(settings)
}

/// Prints the capacity of design `ratios`, what bounds it, and the search's work.
fn print_capacity(
    formulation: &Formulation,
    ratios: &[f64],
    capacity: &Capacity,
) -> Result<(), String> {
    let seconds = capacity.probes.iter().fold(0.0, |sum, p| sum + p.seconds);
    let design = numbers(ratios);
    let space = formulation.space();
    match (capacity.capacity_kg, capacity.limited_by, capacity.first_infeasible_kg) {
        (None, Some(CapacityLimit::Hold), _) => {
            let unloaded = formulation.with_payload(0.0).map_err(|e| e.to_string())?;
            let reason = unloaded
                .static_hold(ratios)
                .map_err(|e| format!("invalid design: {e}"))?
                .reason()
                .unwrap_or_default();
            say!("{space} space, r = ({design}): infeasible even without payload: {reason}")
        }
        (None, _, _) => say!("{space} space, r = ({design}): infeasible even without payload"),
        (Some(kg), Some(CapacityLimit::Hold), _) => say!(
            "{space} space, r = ({design}): payload capacity {kg:.3} kg, bounded by static hold \
             (the motors cannot hold more at rest at the start or the goal)"
        ),
        (Some(kg), _, Some(limit)) => say!(
            "{space} space, r = ({design}): payload capacity {kg:.3} kg ({limit:.3} kg is infeasible)"
        ),
        (Some(kg), _, None) => say!("{space} space, r = ({design}): carries at least {kg:.3} kg (--max)"),
    }
    let ends = formulation.task().motion.ends;
    let judged = if ends.judges_hold() {
        ""
    } else {
        " (not required: ends paper)"
    };
    if let Some(kg) = capacity.hold_kg {
        let ends = match formulation.task().motion.goal.tcp() {
            Some(_) => "the start (a TCP goal's pose is the solve's choice)",
            None => "both ends",
        };
        say!("  the motors hold at most {kg:.3} kg at rest at {ends}{judged}");
    }
    say!("  {} solves in {seconds:.1} s", capacity.probes.len());
    Ok(())
}
