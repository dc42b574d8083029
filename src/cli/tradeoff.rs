//! `codesign tradeoff`: the payload capacity of one design against the duration of its motion,
//! each point the capacity `codesign capacity --duration T` finds, written as JSON with its plot;
//! with `--payloads`, the other way round: the least duration T* of one or more designs against
//! the payload (`time_curve`).

use super::capacity::capacity_settings;
use super::failure::Failure;
use super::time_curve;
use super::tradeoff_args::Args;
use crate::design::capacity::CapacityLimit;
use crate::design::run::{Loaded, RecordedHash};
use crate::design::tradeoff::{
    capacity_tradeoff, check_durations, TradeoffError, TradeoffPoint, TradeoffProblem,
};
use crate::report::tradeoff::{TradeoffDocument, TradeoffInputs};
use codesign_core::solve::ToolInfo;
use codesign_core::text::{listed, numbers};

/// Runs the trade-off the flags ask: capacity against duration, or T* against payload
/// (`--payloads`).
pub fn run(args: &Args) -> Result<(), Failure> {
    if args.model.payload.is_some() {
        return Err(Failure::Usage(
            "--payload: tradeoff searches the payload itself; leave it out".to_owned(),
        ));
    }
    match &args.payloads {
        Some(payloads) => time_curve::run(args, payloads),
        None if !args.compare.is_empty() => Err(Failure::Usage(
            "--compare: a design to compare on T* against payload; only with --payloads".to_owned(),
        )),
        None => capacity_against_duration(args),
    }
}

/// `tradeoff --durations`: the capacity within each duration, printed and, with `--out`, written
/// with its plot.
fn capacity_against_duration(args: &Args) -> Result<(), Failure> {
    check_durations(&args.durations).map_err(|e| Failure::Usage(format!("--durations: {e}")))?;
    let settings =
        capacity_settings(args.resolution, args.first_step, args.max).map_err(Failure::Usage)?;
    args.model.validate()?;
    let Loaded {
        task,
        robot,
        settings: mut solve,
        task_hash,
    } = args.model.load()?;
    args.problem.configure(&mut solve);
    let outputs = args.outputs(&task)?;
    let modes = args.problem.modes(&task);
    let ratios = args
        .ratios
        .clone()
        .unwrap_or_else(|| task.transmission.original.clone());
    let problem = TradeoffProblem {
        task: &task,
        robot: &robot,
        space: args.problem.space,
        modes,
        solve: &solve,
    };
    let points = capacity_tradeoff(&problem, &ratios, &args.durations, &settings)
        .map_err(|e| trade_off_error(args, &ratios, e))?;
    say!(
        "{} space, r = ({}): payload capacity against the duration of the motion",
        args.problem.space,
        numbers(&ratios)
    );
    for point in &points {
        say!("  {}", point_text(point));
    }
    let Some((out, plot)) = &outputs else {
        return Ok(());
    };
    let document = TradeoffDocument {
        tool: ToolInfo::current(solve.linear_solver()),
        inputs: TradeoffInputs {
            task_file: args.model.source().label(),
            task_hash: RecordedHash(Some(task_hash)),
            space: args.problem.space,
            ratios,
            limit_modes: modes,
            ends: task.motion.ends,
            settings,
            durations_s: args.durations.clone(),
        },
        points,
    };
    document.write_with_plot(out, plot)?;
    say!(
        "result written to {} (plot {})",
        out.display(),
        plot.display()
    );
    Ok(())
}

/// A trade-off's error worded with the flag or the task field at fault.
fn trade_off_error(args: &Args, ratios: &[f64], error: TradeoffError) -> Failure {
    let source = args.model.source();
    match &error {
        TradeoffError::Capacity(
            _,
            crate::design::capacity::CapacityError::Solve(
                codesign_core::solve::SolveError::Design(_),
            ),
        ) => Failure::Work(match &args.ratios {
            Some(_) => format!("--ratios {}: invalid design: {error}", listed(ratios)),
            None => format!(
                "{source} transmission.original ({}): invalid design: {error}",
                listed(ratios)
            ),
        }),
        _ => Failure::Work(format!("{source}: {error}")),
    }
}

/// One point in words: its duration and capacity, and what bounds it.
fn point_text(point: &TradeoffPoint) -> String {
    let capacity = &point.capacity;
    let at = format!("T = {} s", codesign_core::text::number(point.duration_s));
    match (
        capacity.capacity_kg,
        capacity.limited_by,
        capacity.first_infeasible_kg,
    ) {
        (None, _, _) => format!("{at}: infeasible even without payload"),
        (Some(kg), Some(CapacityLimit::Hold), _) => {
            format!("{at}: payload capacity {kg:.3} kg, bounded by static hold")
        }
        (Some(kg), _, Some(limit)) => {
            format!("{at}: payload capacity {kg:.3} kg ({limit:.3} kg is infeasible)")
        }
        (Some(kg), _, None) => format!("{at}: carries at least {kg:.3} kg (--max)"),
    }
}
