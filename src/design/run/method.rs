//! The outer method of a run on what it needs: CMA-ES on an evaluator of worker processes with
//! the run's evaluation log; the gradient method on one of threads of this process, or of
//! worker processes when the run names a worker command; each gives the one [`DesignOutcome`].

use super::case::Case;
use super::document::OptimizeInputs;
use super::error::RunError;
use super::settings::{CaseError, Method};
use super::verify::confirm_best;
use crate::design::evaluate::{InProcess, WorkerEvaluator};
use crate::design::gradient::optimize_gradient;
use crate::design::optimize::{optimize, EvaluationLog, Finished, Logged, Progress, Sampling};
use crate::design::outcome::DesignOutcome;
use crate::design::workers::{WorkerSetup, MAX_GROUPS};
use crate::parallel;
use codesign_core::model::task::Task;
use codesign_core::problem::Formulation;
use codesign_core::solve::SolveSettings;
use std::time::Duration;

/// Makes the progress display of a CMA-ES run, given its number of evaluations and a label.
pub type ProgressDisplay<'a> = &'a dyn Fn(u64, String) -> Box<dyn Progress>;

/// What a run's method works on: its case, recorded inputs, task, solve settings and
/// formulation.
pub(super) struct MethodRun<'a> {
    /// The case.
    pub case: &'a Case,
    /// Its recorded inputs.
    pub inputs: &'a OptimizeInputs,
    /// The task, every override applied.
    pub task: &'a Task,
    /// IPOPT's settings.
    pub settings: &'a SolveSettings,
    /// The trajectory problem.
    pub formulation: &'a Formulation,
}

/// Whether `method` logs its evaluations (and resumes from its log): CMA-ES does; the gradient
/// method's descents are short and start afresh.
pub(super) fn logs_evaluations(method: Method) -> bool {
    match method {
        Method::Cmaes => true,
        Method::Gradient => false,
    }
}

/// Runs the case's method; `log` is the open evaluation log (with the evaluations a resumed
/// run finished) of a method that logs.
pub(super) fn run_method(
    run: &MethodRun<'_>,
    log: Option<&mut (EvaluationLog, Finished)>,
    display: ProgressDisplay<'_>,
) -> Result<DesignOutcome, RunError> {
    let case = run.case;
    match case.settings.method {
        Method::Cmaes => run_cmaes(run, log, display),
        Method::Gradient => run_gradient(run),
    }
}

/// The gradient method on threads of this process (one with MUMPS, which is not thread-safe),
/// or on worker processes when the case names a worker command (a cluster's), with this
/// process's own check of the best design, as a CMA-ES run's.
fn run_gradient(run: &MethodRun<'_>) -> Result<DesignOutcome, RunError> {
    let case = run.case;
    let setup = worker_setup(run)?;
    // The workers asked for (default: one per core).
    let count = parallel::threads(case.execution.workers);
    let transmission = run.formulation.transmission();
    let Some(_) = &case.execution.worker_command else {
        let evaluator = InProcess::new(setup.fitness()?, count);
        return Ok(optimize_gradient(transmission, &evaluator, &case.gradient)?);
    };
    let timeout = Duration::from_secs_f64(case.execution.solve_timeout_s);
    let launcher = case.launcher(&program()?);
    let count = count.min(MAX_GROUPS);
    let evaluator = WorkerEvaluator::new(launcher.clone(), &setup, count, timeout)?;
    let outcome = optimize_gradient(transmission, &evaluator, &case.gradient)?;
    confirm_best(&outcome, &setup, &launcher)?;
    Ok(outcome)
}

/// This program, which the workers run.
fn program() -> Result<std::path::PathBuf, RunError> {
    std::env::current_exe()
        .map_err(|e| RunError::Load(format!("cannot locate the codesign executable: {e}")))
}

/// What the workers of a CMA-ES run are told: the task (its robot's path made absolute), the
/// solve settings, the problem and how designs are scored.
fn worker_setup(run: &MethodRun<'_>) -> Result<WorkerSetup, RunError> {
    let (case, task) = (run.case, run.task);
    let mut worker_task = task.clone();
    if let Some(robot) = &task.robot {
        let absolute = std::fs::canonicalize(robot)
            .map_err(|e| RunError::Load(format!("robot {}: {e}", robot.display())))?;
        worker_task.robot = Some(absolute);
    }
    Ok(WorkerSetup {
        objective: run.inputs.settings.objective.clone(),
        task: worker_task,
        solve: run.settings.clone(),
        space: case.problem.space,
        modes: *run.formulation.modes(),
        penalty: case.settings.penalty(),
        robot_hash: run.inputs.robot_hash.0.clone().unwrap_or_default(),
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

/// The CMA-ES run on worker processes, logging to `log` when given: its progress display, and
/// this process's own check of the best design.
fn run_cmaes(
    run: &MethodRun<'_>,
    log: Option<&mut (EvaluationLog, Finished)>,
    display: ProgressDisplay<'_>,
) -> Result<DesignOutcome, RunError> {
    let case = run.case;
    let space = run.formulation.transmission().design_space();
    let designs = (case.settings.bounds.samples(space)).map_err(|e| {
        RunError::Case(CaseError::new(
            "bounds",
            case.settings.bounds,
            e.to_string(),
        ))
    })?;
    let setup = worker_setup(run)?;
    let workers = worker_count(case.execution.workers, case.settings.cmaes.population);
    let program = program()?;
    let timeout = Duration::from_secs_f64(case.execution.solve_timeout_s);
    let launcher = case.launcher(&program);
    let mut evaluator = WorkerEvaluator::new(launcher.clone(), &setup, workers, timeout)?;
    let settings = &case.settings.cmaes;
    let total = settings.evaluations() as u64;
    let label = format!(
        "{} {} kg seed {}",
        case.problem.space, run.inputs.payload_kg, settings.seed
    );
    let mut progress = display(total, label);
    let sampling = Sampling {
        designs,
        warm_start: case.settings.warm_start,
    };
    let logged = log.map(|(log, finished)| Logged {
        log,
        finished: &*finished,
    });
    let outcome = optimize(
        settings.clone(),
        sampling,
        &mut evaluator,
        logged,
        progress.as_mut(),
    )?;
    confirm_best(&outcome, &setup, &launcher)?;
    Ok(outcome)
}
