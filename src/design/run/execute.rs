//! Running a co-design case: its checks before any work, the evaluation log, the outer method
//! (CMA-ES in worker processes, or the gradient method), and the document of what it found.

use super::case::{Case, Loaded};
use super::document::{
    MotionCost, MotionCosts, OptimizeDocument, OptimizeInputs, PayloadCost, RangeCosts,
};
use super::error::{Output, RunError};
use super::method::{logs_evaluations, run_method, MethodRun, ProgressDisplay};
use crate::design::optimize::{EvaluationLog, Finished};
use crate::design::outcome::{BestStart, DesignOutcome, MethodOutcome};
use crate::design::penalty::Grading;
use crate::design::score::Objective;
use crate::design::score::{anchor_solution, Fitness};
use crate::stats::median;
use crate::store::document::write_document;
use crate::store::files::{check_output, check_result};
use crate::store::log::log_beside;
use codesign_core::model::task::{LimitModes, MotionsScore, Task};
use codesign_core::model::Robot;
use codesign_core::problem::Formulation;
use codesign_core::signals;
use codesign_core::solve::{
    solve_design, solve_design_from, SolveError, SolveSettings, ToolInfo, TrajectoryResult,
};
use std::path::Path;
use std::time::Instant;

/// Runs one co-design case and writes its document to `out`; returns it. Every method holds the
/// evaluation log beside `out`, locked, from before the first evaluation until the document is
/// written, so that one rule guards an earlier run's log (and the result it belongs to) for
/// both: it is continued or replaced only as the case's start says. A method that logs its
/// evaluations (CMA-ES) writes them there and shows its progress on what `display` makes; the
/// other's log is removed once its run ends.
pub fn run_case(
    case: &Case,
    out: &Path,
    display: ProgressDisplay<'_>,
) -> Result<OptimizeDocument, RunError> {
    case.validate().map_err(RunError::Case)?;
    let mut loaded = case.model.load().map_err(RunError::Load)?;
    (case.settings)
        .check_task(&loaded.task)
        .map_err(RunError::Case)?;
    case.problem.configure(&mut loaded.settings);
    let read = case.model.inputs(&loaded.task);
    check_result(out, &read).map_err(RunError::store(Output::Result))?;
    check_output(&log_beside(out), &read).map_err(RunError::store(Output::Log))?;
    let modes = case.problem.modes(&loaded.task);
    probe_solver(&loaded.task, &loaded.settings, &loaded.robot, case, modes)?;
    let inputs = case.inputs(&loaded, modes);
    let Loaded {
        task,
        robot,
        settings,
        ..
    } = loaded;
    let formulation = formulate(case, &task, robot, modes, &settings)?;
    let mut log = open_log(case, out, &inputs)?;
    let logged = logs_evaluations(case.settings.method);
    let started = Instant::now();
    let run = MethodRun {
        case,
        inputs: &inputs,
        task: &task,
        settings: &settings,
        formulation: &formulation,
    };
    let outcome = run_method(&run, logged.then_some(&mut log), display);
    let earlier_seconds = log.0.earlier_seconds();
    let result = outcome.and_then(|outcome| {
        let mut document = document(case, &formulation, &settings, inputs, outcome)?;
        // The document's solves of the best and the original design may have been stopped.
        if signals::stop_requested() {
            return Err(RunError::Interrupted);
        }
        document.earlier_seconds = earlier_seconds;
        document.wall_seconds = started.elapsed().as_secs_f64();
        write_document(out, &document).map_err(RunError::store(Output::Result))?;
        Ok(document)
    });
    if result.is_err() || !logged {
        log.0
            .discard_if_unused()
            .map_err(RunError::store(Output::Log))?;
    }
    result
}

/// Opens (locked) the evaluation log of a CMA-ES run as `start` says.
fn open_log(
    case: &Case,
    out: &Path,
    inputs: &OptimizeInputs,
) -> Result<(EvaluationLog, Finished), RunError> {
    let (log, finished) = EvaluationLog::open(&log_beside(out), inputs, case.execution.start)
        .map_err(RunError::store(Output::Log))?;
    // A replayed entry is believed as a worker's answer would be: only what the scoring writes.
    let negative_fitness = matches!(case.settings.objective, Objective::Capacity(_));
    let mut entries: Vec<_> = finished.iter().collect();
    entries.sort_by_key(|(key, _)| **key);
    for ((generation, index), evaluation) in entries {
        if let Some(why) = evaluation.implausible(&case.settings.penalty(), negative_fitness) {
            return Err(RunError::Load(format!(
                "{}: the evaluation of generation {generation}, design {index} holds {why}, \
                 which the scoring never writes: the log was edited; start afresh with --overwrite",
                log_beside(out).display()
            )));
        }
    }
    if let Some(line) = log.dropped_line() {
        note!(
            "note: {} ended in a line cut short by an interruption (line {line}); it was dropped \
             and that evaluation is solved again",
            log_beside(out).display()
        );
    }
    Ok((log, finished))
}

/// The best and the original design solved again in full: one solve each, or each motion of a
/// task with several, or each payload of a range.
struct SolvedAgain {
    best_result: Option<TrajectoryResult>,
    original_result: Option<TrajectoryResult>,
    payload_costs: Option<RangeCosts>,
    motion_costs: Option<MotionCosts>,
}

/// The result document of a run: the method's outcome with full solves of the best and the
/// original design (at every payload of a range, for every motion of a task with several). The
/// wall time and the earlier invocations' time are the caller's to set.
fn document(
    case: &Case,
    formulation: &Formulation,
    settings: &SolveSettings,
    inputs: OptimizeInputs,
    outcome: DesignOutcome,
) -> Result<OptimizeDocument, RunError> {
    let original_ratios = formulation.transmission().original().to_vec();
    let SolvedAgain {
        best_result,
        original_result,
        payload_costs,
        motion_costs,
    } = solve_again(case, formulation, settings, &outcome, &original_ratios)?;
    let original_cost = match &motion_costs {
        Some(costs) => motions_cost(&costs.original, costs.score).unwrap_or(case.settings.penalty),
        None => original_cost(case, original_result.as_ref(), payload_costs.as_ref()),
    };
    let at_max = at_max(&case.settings.objective, &outcome.costs);
    let (generations, iterates, replayed) = match outcome.method {
        MethodOutcome::Cmaes {
            generations,
            replayed,
            ..
        } => (generations, Vec::new(), replayed),
        MethodOutcome::Gradient { iterates, .. } => (Vec::new(), iterates, 0),
    };
    Ok(OptimizeDocument {
        tool: ToolInfo::current(inputs.linear_solver),
        inputs,
        best_ratios: outcome.best_ratios,
        best_cost: outcome.best_cost,
        best_result,
        original_ratios,
        original_cost,
        original_result,
        generations,
        evaluations: outcome.costs.len(),
        costs: outcome.costs,
        iterates,
        replayed,
        solves: outcome.seconds.len(),
        solve_seconds_total: outcome.seconds.iter().sum(),
        verdicts: Some(outcome.verdicts),
        median_solve_seconds: median(&outcome.seconds),
        stop_reason: outcome.stop_reason,
        wall_seconds: 0.0,
        earlier_seconds: None,
        payload_costs,
        motion_costs,
        at_max,
    })
}

/// `outcome`'s best design and the original one (`original_ratios`) solved again for the
/// document, as the case scored them.
fn solve_again(
    case: &Case,
    formulation: &Formulation,
    settings: &SolveSettings,
    outcome: &DesignOutcome,
    original_ratios: &[f64],
) -> Result<SolvedAgain, RunError> {
    // The designs are solved again as they were scored: the elastic problem for a graded
    // penalty, so that the reported cost is the one behind `best_cost`.
    let elastic;
    let scored = match case.settings.grading {
        Grading::Flat => formulation,
        Grading::Graded => {
            elastic = formulation.elastic();
            &elastic
        }
    };
    let fitness = || {
        Fitness::new(
            formulation.task(),
            settings,
            formulation.space(),
            *formulation.modes(),
            &case.settings.objective,
            case.settings.penalty(),
        )
    };
    let none = SolvedAgain {
        best_result: None,
        original_result: None,
        payload_costs: None,
        motion_costs: None,
    };
    Ok(match &case.settings.objective {
        _ if formulation.task().has_motions() => {
            let fitness = fitness()?;
            SolvedAgain {
                motion_costs: Some(MotionCosts {
                    score: formulation.task().motions_score,
                    best: each_motion(&fitness, settings, &outcome.best_ratios),
                    original: each_motion(&fitness, settings, original_ratios),
                }),
                ..none
            }
        }
        Objective::Range(_) => {
            let fitness = fitness()?;
            let best = payload_costs(&fitness, settings, &outcome.best_ratios);
            let original = payload_costs(&fitness, settings, original_ratios);
            SolvedAgain {
                payload_costs: Some(RangeCosts { best, original }),
                ..none
            }
        }
        // Started as its evaluation was: where the gradient method's solve of it began or from
        // its generation's anchor, so that the reported trajectory is the one behind `best_cost`.
        _ => SolvedAgain {
            best_result: solve_best(scored, settings, outcome),
            original_result: solve_design(scored, original_ratios, settings).ok(),
            ..none
        },
    })
}

/// The original design's fitness: its J where feasible (the mean over a range's payloads where
/// feasible at every one), else the case's penalty.
fn original_cost(
    case: &Case,
    result: Option<&TrajectoryResult>,
    payload_costs: Option<&RangeCosts>,
) -> f64 {
    match (result, payload_costs) {
        (Some(result), _) if result.feasible => result.cost,
        (_, Some(costs)) if costs.original.iter().all(|c| c.feasible) => {
            costs.original.iter().map(|c| c.cost).sum::<f64>() / costs.original.len() as f64
        }
        _ => case.settings.penalty,
    }
}

/// How many evaluations of a capacity search reached its ceiling `max_kg` (their capacities
/// tie there); None for other objectives.
fn at_max(objective: &Objective, costs: &[f64]) -> Option<usize> {
    match objective {
        Objective::Capacity(search) => {
            Some(costs.iter().filter(|&&cost| -cost >= search.max_kg).count())
        }
        _ => None,
    }
}

/// The best design of `outcome` solved in `scored`, started as its evaluation was (None when
/// the solve fails).
fn solve_best(
    scored: &Formulation,
    settings: &SolveSettings,
    outcome: &DesignOutcome,
) -> Option<codesign_core::solve::TrajectoryResult> {
    let anchored;
    let from;
    let start = match outcome.best_start() {
        BestStart::Point(point) => {
            from = point.to_solution();
            Some(&from)
        }
        BestStart::Anchor(anchor) => {
            anchored = anchor_solution(scored, settings, anchor);
            anchored.as_ref()
        }
        BestStart::Cold => None,
    };
    solve_design_from(scored, &outcome.best_ratios, settings, start)
        .ok()
        .map(|(result, _)| result)
}

/// `ratios` solved at every payload of a range `fitness`, as its motions (none when `ratios` is
/// empty: no feasible design was found).
fn payload_costs(fitness: &Fitness, settings: &SolveSettings, ratios: &[f64]) -> Vec<PayloadCost> {
    let Some(motions) = fitness.motions().filter(|_| !ratios.is_empty()) else {
        return Vec::new();
    };
    (motions.problems.iter())
        .map(|problem| {
            let formulation = &problem.formulation;
            let solved = solve_design(formulation, ratios, settings);
            PayloadCost {
                payload_kg: formulation.task().payload.mass_kg,
                feasible: solved.as_ref().is_ok_and(|r| r.feasible),
                cost: solved.as_ref().map_or(f64::NAN, |r| r.cost),
                status: solved.map_or_else(|e| e.to_string(), |r| r.status),
            }
        })
        .collect()
}

/// `ratios` solved from the standard guess for every motion of `fitness` (none when `ratios`
/// is empty: no feasible design was found), as the design was scored (elastic problems for a
/// graded penalty).
fn each_motion(fitness: &Fitness, settings: &SolveSettings, ratios: &[f64]) -> Vec<MotionCost> {
    let Some(motions) = fitness.motions().filter(|_| !ratios.is_empty()) else {
        return Vec::new();
    };
    (motions.problems.iter())
        .map(|problem| {
            let solved = solve_design(&problem.formulation, ratios, settings);
            MotionCost {
                name: problem.name.clone(),
                weight: problem.weight,
                payload_kg: problem.formulation.task().payload.mass_kg,
                feasible: solved.as_ref().is_ok_and(|r| r.feasible),
                cost: solved.as_ref().map_or(f64::NAN, |r| r.cost),
                status: solved
                    .as_ref()
                    .map_or_else(|e| e.to_string(), |r| r.status.clone()),
                result: solved.ok(),
            }
        })
        .collect()
}

/// The score of a design's costs for each motion, `score`-combined (w_i J_i summed in order, or
/// the worst); None unless every motion is feasible.
fn motions_cost(costs: &[MotionCost], score: MotionsScore) -> Option<f64> {
    let weighted: Option<Vec<f64>> = (costs.iter())
        .map(|c| c.feasible.then_some(c.weight * c.cost))
        .collect();
    score.combine(&weighted?).map(|(cost, _)| cost)
}

/// The hard formulation of `case` for `task` and `robot` under `modes`: minimising the motors'
/// copper losses for the energy objective, the duration T of the task's pure minimum-time
/// problem for the time objective, the task's J otherwise.
fn formulate(
    case: &Case,
    task: &Task,
    robot: Robot,
    modes: LimitModes,
    settings: &SolveSettings,
) -> Result<Formulation, RunError> {
    let objective = &case.settings.objective;
    let solved = &objective.task(task);
    let formulation = Formulation::new(solved, robot, case.problem.space, modes)
        .map_err(|e| RunError::Load(e.to_string()))?;
    let formulation =
        (objective.shape(formulation, task)).with_hold_tolerance(settings.constraint_tolerance());
    match case.settings.objective {
        Objective::Energy => formulation
            .minimising_copper_loss()
            .map_err(|e| RunError::Load(e.to_string())),
        _ => Ok(formulation),
    }
}

/// Solves the original design once on a 2-interval copy of the problem, so that a solver
/// option IPOPT rejects (the task file's `solver`) fails the run before its first generation,
/// with IPOPT's complaint, instead of penalising every design.
fn probe_solver(
    task: &Task,
    settings: &SolveSettings,
    robot: &Robot,
    case: &Case,
    modes: LimitModes,
) -> Result<(), RunError> {
    let mut small = task.clone();
    small.motion.steps = 2;
    let formulation = formulate(case, &small, robot.clone(), modes, settings)?;
    match solve_design(&formulation, &small.transmission.original, settings) {
        Err(SolveError::Ipopt(error)) => Err(RunError::Solver(format!(
            "{} solver: {error} (checked by a solve of the original design before the run)",
            case.model.source()
        ))),
        _ => Ok(()),
    }
}
