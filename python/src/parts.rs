//! `parts`: a search over a task's candidate parts, as `codesign parts` runs it (each
//! combination co-designed by the gradient method, its workers started as `python -m
//! codesign.worker`), its `pareto.json` and `pareto.svg` written, its progress handed to a
//! Python callable after each combination.

use crate::errors::{json, Failure, Outcome};
use crate::interrupt::{self, Message};
use crate::options::{penalty_of, start_of, Keywords};
use codesign::design::gradient::GradientSettings;
use codesign::design::optimize::Progress;
use codesign::design::parts::{
    run_parts, Better, PartsError, PartsEvent, PartsObjective, PartsSearch,
};
use codesign::design::penalty::Penalty;
use codesign::design::run::{Execution, RunError};
use codesign::design::score::Evaluation;
use codesign::report::pareto::write_pareto;
use codesign_core::model::part_family::PartsFamily;
use codesign_core::model::task::TaskSource;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Sender;

/// The objective of `objective=`.
fn objective_of(name: &str) -> Outcome<PartsObjective> {
    match name {
        "cost" => Ok(PartsObjective::Cost),
        "capacity" => Ok(PartsObjective::Capacity),
        "time" => Ok(PartsObjective::Time),
        _ => Err(Failure::input(format!(
            "objective={name:?}: one of \"cost\", \"capacity\", \"time\""
        ))),
    }
}

/// A run's own progress, which a search does not show (it tells each combination instead).
struct Quiet;

impl Progress for Quiet {
    fn evaluated(&mut self, _evaluation: &Evaluation, _replayed: bool) {}
}

/// Whether a search's failure is the caller's input (a setting, the task, the folder) or the
/// work's.
fn failure(error: PartsError) -> Failure {
    match &error {
        PartsError::Case(case) => {
            Failure::input(format!("{}={}: {}", case.key, case.value, case.rule))
        }
        PartsError::Folder(_) => Failure::input(error.to_string()),
        PartsError::Run {
            error: RunError::Load(_) | RunError::Store { .. } | RunError::Case(_),
            ..
        } => Failure::input(error.to_string()),
        PartsError::Run { .. } => Failure::solver(error.to_string()),
    }
}

/// Runs `search` into `out`, each combination's end sent on `sender`; the front's document.
fn run(search: &PartsSearch, out: &Path, sender: Sender<Message<String>>) -> Outcome<String> {
    let display = |_total: u64, _label: String| -> Box<dyn Progress> { Box::new(Quiet) };
    let higher = search.objective.axis().better == Better::Higher;
    let mut best = if higher {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    };
    let mut observe = |event: PartsEvent<'_>| {
        if let PartsEvent::Done {
            index,
            total,
            point,
            ..
        } = event
        {
            if let Some((_, value)) = point.placed() {
                best = if higher {
                    best.max(value)
                } else {
                    best.min(value)
                };
            }
            let _ = sender.send(Message::Progress(index as u64 + 1, total as u64, best));
        }
    };
    let document = run_parts(search, out, &display, &mut observe).map_err(failure)?;
    write_pareto(out, &document).map_err(Failure::solver)?;
    json(&document)
}

/// A search over the candidate parts of the task file `task` written to the folder `out`, as
/// `codesign parts` runs it; the front's document (`pareto.json`). `progress(done, total,
/// best)` is called after each combination.
#[pyfunction]
#[pyo3(signature = (task, space, out, worker_command, payload=None, ends=None, torque_mode=None,
    speed_mode=None, linear_solver=None, objective="cost", penalty=None, gradient_iterations=None,
    workers=None, resume=false, overwrite=false, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn parts(
    py: Python<'_>,
    task: PathBuf,
    space: &str,
    out: PathBuf,
    worker_command: String,
    payload: Option<f64>,
    ends: Option<&str>,
    torque_mode: Option<&str>,
    speed_mode: Option<&str>,
    linear_solver: Option<&str>,
    objective: &str,
    penalty: Option<&str>,
    gradient_iterations: Option<usize>,
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
    let search = || -> Outcome<PartsSearch> {
        let start = start_of(resume, overwrite)?;
        let (model, problem) = keywords.choices(TaskSource::File(task.clone()))?;
        let family = PartsFamily::load(&task).map_err(|e| Failure::input(e.to_string()))?;
        let defaults = GradientSettings::default();
        Ok(PartsSearch {
            family,
            task_file: task.display().to_string(),
            model,
            problem,
            objective: objective_of(objective)?,
            penalty: penalty_of(penalty)?.unwrap_or(Penalty::PAPER),
            gradient: GradientSettings {
                max_iterations: gradient_iterations.unwrap_or(defaults.max_iterations),
                ..defaults
            },
            execution: Execution {
                workers,
                worker_command: Some(worker_command.clone()),
                start,
                ..Execution::default()
            },
        })
    };
    let search = search().map_err(|f| f.into_py(py))?;
    interrupt::run(
        py,
        move |sender| run(&search, &out, sender),
        interrupt::calling(progress),
    )
}
