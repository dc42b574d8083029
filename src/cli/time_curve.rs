//! `codesign tradeoff --payloads`: the least duration T* of one or more designs against the
//! payload, each point the task's pure minimum-time problem solved as `solve` solves it, written
//! as JSON (schema `codesign/time_curve`) with one plot of every design's curve beside it.

use super::common::finite_ratio;
use super::failure::Failure;
use super::tradeoff_args::Args;
use crate::design::run::{Loaded, RecordedHash};
use crate::design::time_curve::{
    check_payloads, minimum_time_curve, minimum_time_problem, TimeCurve, TimeCurveError,
};
use crate::design::tradeoff::TradeoffProblem;
use crate::report::time_curve::{TimeCurveDocument, TimeCurveInputs};
use codesign_core::solve::{SolveError, ToolInfo};
use codesign_core::text::{listed, number, numbers};

/// Solves T* at every payload for each design, prints the curves, writes the file and its plot.
pub fn run(args: &Args, payloads: &[f64]) -> Result<(), Failure> {
    check_payloads(payloads).map_err(|e| Failure::Usage(format!("--payloads: {e}")))?;
    let compared = (args.compare.iter())
        .map(|text| design(text))
        .collect::<Result<Vec<_>, _>>()?;
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
    let first = (args.ratios.clone()).unwrap_or_else(|| task.transmission.original.clone());
    let problem = TradeoffProblem {
        task: &task,
        robot: &robot,
        space: args.problem.space,
        modes,
        solve: &solve,
    };
    let designs: Vec<Vec<f64>> = std::iter::once(first).chain(compared).collect();
    let source = args.model.source();
    let checked = minimum_time_problem(&problem, payloads[0])
        .map_err(|e| Failure::Work(format!("{source}: {e}")))?;
    for (i, ratios) in designs.iter().enumerate() {
        if let Err(e) = checked.transmission().check_design(ratios) {
            let given = given(args, i, ratios);
            return Err(Failure::Work(format!("{given}: invalid design: {e}")));
        }
    }
    let mut curves = Vec::new();
    for (i, ratios) in designs.into_iter().enumerate() {
        let curve = minimum_time_curve(&problem, &ratios, payloads)
            .map_err(|e| curve_error(args, i, &ratios, e))?;
        say!("{}", curve_text(args, &curve));
        curves.push(curve);
    }
    let Some((out, plot)) = &outputs else {
        return Ok(());
    };
    let document = TimeCurveDocument {
        tool: ToolInfo::current(solve.linear_solver()),
        inputs: TimeCurveInputs {
            task_file: args.model.source().label(),
            task_hash: RecordedHash(Some(task_hash)),
            space: args.problem.space,
            limit_modes: modes,
            ends: task.motion.ends,
            task_horizon_s: task.motion.horizon,
            horizon_s: task.minimum_time().motion.horizon,
            payloads_kg: payloads.to_vec(),
        },
        curves,
    };
    document.write_with_plot(out, plot)?;
    say!(
        "result written to {} (plot {})",
        out.display(),
        plot.display()
    );
    Ok(())
}

/// The design of one `--compare R1,R2,..`.
fn design(text: &str) -> Result<Vec<f64>, Failure> {
    (text.split(','))
        .map(finite_ratio)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|why| Failure::Usage(format!("--compare {text}: {why}")))
}

/// Where the `i`-th design was given: `--ratios` (or the task's original) for 0, a `--compare`
/// after.
fn given(args: &Args, i: usize, ratios: &[f64]) -> String {
    let source = args.model.source();
    match (i, &args.ratios) {
        (0, None) => format!("{source} transmission.original ({})", listed(ratios)),
        (0, Some(_)) => format!("--ratios {}", listed(ratios)),
        _ => format!("--compare {}", listed(ratios)),
    }
}

/// A curve's error worded with the flag or the task field at fault.
fn curve_error(args: &Args, i: usize, ratios: &[f64], error: TimeCurveError) -> Failure {
    let source = args.model.source();
    let given = given(args, i, ratios);
    match &error {
        TimeCurveError::Solve(_, SolveError::Design(_)) => {
            Failure::Work(format!("{given}: invalid design: {error}"))
        }
        _ => Failure::Work(format!("{source}, {given}: {error}")),
    }
}

/// One design's curve in words: T* at each payload, and where it ends.
fn curve_text(args: &Args, curve: &TimeCurve) -> String {
    let mut lines = vec![format!(
        "{} space, r = ({}): least duration T* against payload",
        args.problem.space,
        numbers(&curve.ratios)
    )];
    for point in &curve.points {
        let at = format!("  {} kg", number(point.payload_kg));
        lines.push(match point.minimum_time_s {
            Some(seconds) => format!(
                "{at}: T* = {seconds:.4} s ({} iterations)",
                point.iterations
            ),
            None => format!("{at}: no trajectory within T_max; the curve ends"),
        });
    }
    lines.join("\n")
}
