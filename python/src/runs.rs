//! `optimize`: a co-design run of a task, as `codesign optimize --out` runs it, its workers
//! started as `python -m codesign.worker`, its progress handed to a Python callable.

use crate::errors::{Failure, Outcome};
use crate::interrupt::{self, Message};
use crate::options::{choice, optional, penalty_of, start_of, Keywords, Posed};
use crate::task::NativeTask;
use codesign::design::bounds::BoundHandling;
use codesign::design::optimize::Progress;
use codesign::design::penalty::Penalty;
use codesign::design::run::{run_case, Case, CaseError, Method, RunError};
use codesign::design::score::{Evaluation, Objective};
use codesign::design::warm::WarmStart;
use codesign::store::document::document_json;
use codesign::store::log::Start;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::mpsc::Sender;

/// The settings of one run beyond the problem, as Python gives them.
#[derive(Clone, Debug)]
pub struct RunKeywords {
    method: Method,
    objective: Objective,
    penalty: Option<Penalty>,
    bounds: Option<BoundHandling>,
    population: Option<usize>,
    generations: Option<usize>,
    seed: Option<u64>,
    sigma: Option<f64>,
    gradient_iterations: Option<usize>,
    warm_start: Option<WarmStart>,
    workers: Option<usize>,
    worker_command: String,
    start: Start,
}

impl RunKeywords {
    /// The case these settings and `posed` make.
    fn case(&self, posed: Posed) -> Case {
        let mut case = Case::new(posed.model, posed.problem, self.method);
        case.settings.objective = self.objective.clone();
        if let Some(penalty) = self.penalty {
            case.settings.set_penalty(penalty);
        }
        case.settings.bounds = self.bounds.unwrap_or(case.settings.bounds);
        let cmaes = &mut case.settings.cmaes;
        cmaes.population = self.population.unwrap_or(cmaes.population);
        cmaes.generations = self.generations.unwrap_or(cmaes.generations);
        cmaes.seed = self.seed.unwrap_or(cmaes.seed);
        cmaes.sigma0 = self.sigma.unwrap_or(cmaes.sigma0);
        let gradient = &mut case.gradient;
        gradient.max_iterations = self.gradient_iterations.unwrap_or(gradient.max_iterations);
        let settings = &mut case.settings;
        settings.warm_start = self.warm_start.unwrap_or(settings.warm_start);
        let execution = &mut case.execution;
        execution.workers = self.workers;
        execution.worker_command = Some(self.worker_command.clone());
        execution.start = self.start;
        case
    }
}

/// The objective of `objective=`: one that needs no settings of its own (the capacity and range
/// objectives are the command line's, `codesign optimize --objective`).
fn objective_of(name: &str) -> Outcome<Objective> {
    match name {
        "cost" => Ok(Objective::Cost),
        "energy" => Ok(Objective::Energy),
        "time" => Ok(Objective::Time),
        _ => Err(Failure::input(format!(
            "objective={name:?}: one of \"cost\", \"energy\", \"time\""
        ))),
    }
}

/// A case's error worded with the keyword that sets the value (`sigma=-1: ...`).
fn case_message(error: &CaseError) -> String {
    let keyword = match error.key {
        "sigma0" => "sigma",
        "start" => return format!("{}=True: {}", error.value, error.rule),
        key => key,
    };
    format!("{keyword}={}: {}", error.value, error.rule)
}

/// Hands each finished evaluation to the waiting Python thread.
struct Forward {
    sender: Sender<Message<String>>,
    done: u64,
    total: u64,
    /// The least fitness so far, penalised designs included.
    best: f64,
}

impl Progress for Forward {
    fn evaluated(&mut self, evaluation: &Evaluation, _replayed: bool) {
        self.done += 1;
        self.best = self.best.min(evaluation.cost);
        let _ = self
            .sender
            .send(Message::Progress(self.done, self.total, self.best));
    }
}

/// Whether a run's failure is the caller's input (a setting, the task, an output refused or
/// a log to resume or overwrite) or the work's.
fn failure(error: RunError) -> Failure {
    match error {
        RunError::Case(error) => Failure::input(case_message(&error)),
        RunError::Load(_) | RunError::Store { .. } => Failure::input(error.to_string()),
        _ => Failure::solver(error.to_string()),
    }
}

/// Runs the case to `out`, its progress sent on `sender`; the result document.
fn run(case: &Case, out: &std::path::Path, sender: Sender<Message<String>>) -> Outcome<String> {
    let display = move |total: u64, _label: String| -> Box<dyn Progress> {
        Box::new(Forward {
            sender: sender.clone(),
            done: 0,
            total,
            best: f64::INFINITY,
        })
    };
    let document = run_case(case, out, &display).map_err(failure)?;
    document_json(&document).map_err(|e| Failure::solver(format!("result not encoded: {e}")))
}

/// Where a run whose result is `out` keeps its evaluation log (`NAME.json` ->
/// `NAME.log.jsonl`, beside the file a symbolic link `out` points to).
#[pyfunction]
pub fn log_beside(out: PathBuf) -> PathBuf {
    codesign::store::log::log_beside(&out)
}

/// A co-design run of `task` written to `out` (its evaluation log beside it), as
/// `codesign optimize` runs it; the result document. `progress(done, total, best)` is called
/// after each evaluation of a CMA-ES run.
#[pyfunction]
#[pyo3(signature = (task, space, out, worker_command, payload=None, ends=None, torque_mode=None,
    speed_mode=None, linear_solver=None, method="cmaes", objective="cost", penalty=None, bounds=None,
    population=None, generations=None,
    seed=None, sigma=None, gradient_iterations=None, warm_start=None, workers=None, resume=false,
    overwrite=false, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn optimize(
    py: Python<'_>,
    task: PyRef<'_, NativeTask>,
    space: &str,
    out: PathBuf,
    worker_command: String,
    payload: Option<f64>,
    ends: Option<&str>,
    torque_mode: Option<&str>,
    speed_mode: Option<&str>,
    linear_solver: Option<&str>,
    method: &str,
    objective: &str,
    penalty: Option<&str>,
    bounds: Option<&str>,
    population: Option<usize>,
    generations: Option<usize>,
    seed: Option<u64>,
    sigma: Option<f64>,
    gradient_iterations: Option<usize>,
    warm_start: Option<bool>,
    workers: Option<usize>,
    resume: bool,
    overwrite: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let keywords = Keywords {
        space,
        payload,
        ends,
        torque_mode,
        speed_mode,
        linear_solver,
    };
    let settings = |py| -> PyResult<Case> {
        let posed = task.posed(&keywords).map_err(|f| f.into_py(py))?;
        let start = start_of(resume, overwrite).map_err(|f| f.into_py(py))?;
        let run = RunKeywords {
            method: choice("method", method).map_err(|f| f.into_py(py))?,
            objective: objective_of(objective).map_err(|f| f.into_py(py))?,
            penalty: penalty_of(penalty).map_err(|f| f.into_py(py))?,
            bounds: optional("bounds", bounds).map_err(|f| f.into_py(py))?,
            population,
            generations,
            seed,
            sigma,
            gradient_iterations,
            warm_start: warm_start.map(|on| if on { WarmStart::On } else { WarmStart::Off }),
            workers,
            worker_command,
            start,
        };
        Ok(run.case(posed))
    };
    let case = settings(py)?;
    interrupt::run(
        py,
        move |sender| run(&case, &out, sender),
        interrupt::calling(progress),
    )
}
