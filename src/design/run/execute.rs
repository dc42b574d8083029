//! Running a co-design case: its checks before any work, the evaluation log, the outer method
//! (CMA-ES in worker processes, or the gradient method), and the document of what it found.

use super::case::{Case, Loaded};
use super::document::{Method, OptimizeDocument, OptimizeInputs, PayloadCost, RangeCosts};
use super::error::{Output, RunError};
use super::verify::confirm_best;
use crate::design::gradient::optimize_gradient;
use crate::design::optimize::{optimize, EvaluationLog, Finished, Progress, Sampling};
use crate::design::outcome::DesignOutcome;
use crate::design::penalty::Grading;
use crate::design::score::Objective;
use crate::design::score::{anchor_solution, Fitness};
use crate::design::workers::{Pool, WorkerSetup, MAX_GROUPS};
use crate::model::task::{LimitModes, Task};
use crate::model::Robot;
use crate::problem::Formulation;
use crate::solve::{solve_design, solve_design_from, SolveError, SolveSettings, ToolInfo};
use crate::stats::median;
use crate::store::document::write_document;
use crate::store::files::{check_output, check_result};
use crate::store::log::log_beside;
use std::path::Path;
use std::time::{Duration, Instant};

/// Makes the progress display of a CMA-ES run, given its number of evaluations and a label.
pub type ProgressDisplay<'a> = &'a dyn Fn(u64, String) -> Box<dyn Progress>;

/// Runs one co-design case and writes its document to `out`; returns it. A CMA-ES run holds its
/// evaluation log, locked, from before the first evaluation until the document is written, and
/// shows its progress on what `display` makes.
pub fn run_case(
    case: &Case,
    out: &Path,
    display: ProgressDisplay<'_>,
) -> Result<OptimizeDocument, RunError> {
    case.validate().map_err(RunError::Case)?;
    let mut loaded = case.model.load().map_err(RunError::Load)?;
    case.problem.configure(&mut loaded.settings);
    let read = case.model.inputs(&loaded.task);
    check_result(out, &read).map_err(RunError::store(Output::Result))?;
    if case.settings.method == Method::Cmaes {
        check_output(&log_beside(out), &read).map_err(RunError::store(Output::Log))?;
    }
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
    let mut log = match case.settings.method {
        Method::Cmaes => Some(open_log(case, out, &inputs)?),
        Method::Gradient => None,
    };
    let started = Instant::now();
    let outcome = match log.as_mut() {
        Some((log, finished)) => {
            let setup = worker_setup(case, &inputs, &task, &settings, &formulation)?;
            let run = CmaesRun {
                case,
                inputs: &inputs,
                setup: &setup,
                formulation: &formulation,
            };
            run_cmaes(run, log, finished, display).map(|o| (o, log.earlier_seconds()))
        }
        None => optimize_gradient(
            &formulation,
            &settings,
            &case.gradient,
            case.settings.penalty(),
        )
        .map(|o| (o, Some(0.0)))
        .map_err(RunError::from),
    };
    let result = outcome.and_then(|(outcome, earlier_seconds)| {
        let mut document = document(case, &formulation, &settings, inputs, outcome)?;
        document.earlier_seconds = earlier_seconds;
        document.wall_seconds = started.elapsed().as_secs_f64();
        write_document(out, &document).map_err(RunError::store(Output::Result))?;
        Ok(document)
    });
    if let (Err(_), Some((log, _))) = (&result, log) {
        log.discard_if_unused()
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

/// The result document of a run: the method's outcome with full solves of the best and the
/// original design (at every payload of a range). The wall time and the earlier invocations'
/// time are the caller's to set.
fn document(
    case: &Case,
    formulation: &Formulation,
    settings: &SolveSettings,
    inputs: OptimizeInputs,
    outcome: DesignOutcome,
) -> Result<OptimizeDocument, RunError> {
    let original_ratios = formulation.transmission().original().to_vec();
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
    let anchored =
        (outcome.best_anchor.as_ref()).and_then(|anchor| anchor_solution(scored, settings, anchor));
    let (best_result, original_result, payload_costs) = match &case.settings.objective {
        Objective::Range(_) => {
            let fitness = Fitness::new(
                formulation.task(),
                settings,
                formulation.space(),
                *formulation.modes(),
                &case.settings.objective,
                case.settings.penalty(),
            )?;
            let best = payload_costs(&fitness, settings, &outcome.best_ratios);
            let original = payload_costs(&fitness, settings, &original_ratios);
            (None, None, Some(RangeCosts { best, original }))
        }
        // Started as its evaluation was: from the method's own inner solution or its
        // generation's anchor, so that the reported trajectory is the one behind `best_cost`.
        _ => (
            solve_design_from(
                scored,
                &outcome.best_ratios,
                settings,
                outcome.best_solution.as_ref().or(anchored.as_ref()),
            )
            .ok()
            .map(|(result, _)| result),
            solve_design(scored, &original_ratios, settings).ok(),
            None,
        ),
    };
    let original_cost = match (&original_result, &payload_costs) {
        (Some(result), _) if result.feasible => result.cost,
        (_, Some(costs)) if costs.original.iter().all(|c| c.feasible) => {
            costs.original.iter().map(|c| c.cost).sum::<f64>() / costs.original.len() as f64
        }
        _ => case.settings.penalty,
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
        generations: outcome.generations,
        evaluations: outcome.costs.len(),
        costs: outcome.costs,
        iterates: outcome.iterates,
        replayed: outcome.replayed,
        solves: outcome.seconds.len(),
        solve_seconds_total: outcome.seconds.iter().sum(),
        median_solve_seconds: median(&outcome.seconds),
        stop_reason: outcome.stop_reason,
        wall_seconds: 0.0,
        earlier_seconds: None,
        payload_costs,
    })
}

/// `ratios` solved at every payload of a range `fitness` (none when `ratios` is empty: no
/// feasible design was found).
fn payload_costs(fitness: &Fitness, settings: &SolveSettings, ratios: &[f64]) -> Vec<PayloadCost> {
    if ratios.is_empty() {
        return Vec::new();
    }
    fitness
        .payloads()
        .iter()
        .map(|(payload_kg, formulation)| {
            let solved = solve_design(formulation, ratios, settings);
            PayloadCost {
                payload_kg: *payload_kg,
                feasible: solved.as_ref().is_ok_and(|r| r.feasible),
                cost: solved.as_ref().map_or(f64::NAN, |r| r.cost),
                status: solved.map_or_else(|e| e.to_string(), |r| r.status),
            }
        })
        .collect()
}

/// The hard formulation of `case` for `task` and `robot` under `modes`: minimising the motors'
/// copper losses for the energy objective, the task's J otherwise.
fn formulate(
    case: &Case,
    task: &Task,
    robot: Robot,
    modes: LimitModes,
    settings: &SolveSettings,
) -> Result<Formulation, RunError> {
    let formulation = Formulation::new(task, robot, case.problem.space, modes)
        .map_err(|e| RunError::Load(e.to_string()))?
        .with_hold_tolerance(settings.constraint_tolerance());
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
/// What the workers of a CMA-ES run are told: the task (its robot's path made absolute), the
/// solve settings, the problem and how designs are scored.
fn worker_setup(
    case: &Case,
    inputs: &OptimizeInputs,
    task: &Task,
    settings: &SolveSettings,
    formulation: &Formulation,
) -> Result<WorkerSetup, RunError> {
    let mut worker_task = task.clone();
    if let Some(robot) = &task.robot {
        let absolute = std::fs::canonicalize(robot)
            .map_err(|e| RunError::Load(format!("robot {}: {e}", robot.display())))?;
        worker_task.robot = Some(absolute);
    }
    Ok(WorkerSetup {
        objective: inputs.settings.objective.clone(),
        task: worker_task,
        solve: settings.clone(),
        space: case.problem.space,
        modes: *formulation.modes(),
        penalty: case.settings.penalty(),
        robot_hash: inputs.robot_hash.0.clone().unwrap_or_default(),
    })
}

/// How many workers a run of `population` starts: the number asked for (default: one per core),
/// at most one per design of a generation, with a note when it is more than the cores.
fn worker_count(asked: Option<usize>, population: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let workers = asked.unwrap_or(cores).min(population).clamp(1, MAX_GROUPS);
    if asked.is_some_and(|n| n > population) {
        note!(
            "note: --workers {}: a generation has {population} designs, so {population} workers \
             are started",
            asked.unwrap_or_default()
        );
    }
    if workers > cores {
        note!(
            "note: {workers} workers on {cores} cores here: unless the worker command places them \
             on other machines, they share the cores"
        );
    }
    workers
}

/// What a CMA-ES run is: its case, recorded inputs, workers' setup and formulation.
struct CmaesRun<'a> {
    case: &'a Case,
    inputs: &'a OptimizeInputs,
    setup: &'a WorkerSetup,
    formulation: &'a Formulation,
}

/// The CMA-ES run on its open evaluation log (with the `finished` evaluations of a resumed
/// run): worker pool, progress display.
fn run_cmaes(
    run: CmaesRun<'_>,
    log: &mut EvaluationLog,
    finished: &Finished,
    display: ProgressDisplay<'_>,
) -> Result<DesignOutcome, RunError> {
    let CmaesRun {
        case,
        inputs,
        setup,
        formulation,
    } = run;
    let workers = worker_count(case.execution.workers, case.settings.cmaes.population);
    let program = std::env::current_exe()
        .map_err(|e| RunError::Load(format!("cannot locate the codesign executable: {e}")))?;
    let timeout = Duration::from_secs_f64(case.execution.solve_timeout_s);
    let launcher = case.launcher(&program);
    let mut pool = Pool::new(launcher.clone(), setup, workers, timeout)?;
    let settings = &case.settings.cmaes;
    let total = (settings.population * (settings.generations + 1)) as u64;
    let label = format!(
        "{} {} kg seed {}",
        case.problem.space, inputs.payload_kg, settings.seed
    );
    let mut progress = display(total, label);
    let sampling = Sampling {
        space: formulation.transmission().design_space(),
        bounds: case.settings.bounds,
        warm_start: case.settings.warm_start,
    };
    let outcome = optimize(
        settings.clone(),
        sampling,
        &mut pool,
        log,
        finished,
        progress.as_mut(),
    )?;
    confirm_best(&outcome, setup, &launcher)?;
    Ok(outcome)
}
