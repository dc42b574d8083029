//! `NativeTask`: a task, where it comes from, and what the package does with it: check, solve,
//! capacity and its trade-off against cycle time here, optimize in `runs`. Each answers with the command line's JSON document.

use crate::errors::{json, Failure, Outcome};
use crate::interrupt;
use crate::options::{Keywords, Posed, ReadTask};
use crate::solution::NativeSolution;
use crate::tradeoff::{TimeCurveAsked, TradeoffAsked};
use codesign::design::capacity::{payload_capacity, CapacitySettings};
use codesign::design::run::RecordedHash;
use codesign::design::time_curve::check_payloads;
use codesign::design::tradeoff::check_durations;
use codesign::report::check::TaskInspection;
use codesign::report::codesign::{CapacityDocument, CapacityInputs};
use codesign::report::solve_document::{SolveDocument, StartRecord};
use codesign_core::choice::Choice;
use codesign_core::model::task::BUILT_IN_TASK;
use codesign_core::model::task::{
    check_horizon, check_steps, GivenTask, Horizon, TaskFile, TaskSource,
};
use codesign_core::solve::{
    solve_design_from, FreeHorizonSearch, SolveError, StartPoint, ToolInfo,
};
use codesign_core::text::number;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A task: the built-in one, a task file, or one built in memory (see `codesign.Task`).
#[pyclass(module = "codesign._native", frozen)]
pub struct NativeTask {
    pub(crate) source: TaskSource,
    /// The task and its robot, read when the task was made.
    pub(crate) read: Arc<ReadTask>,
}

impl NativeTask {
    /// The task of `source`, read with its robot.
    fn of(source: TaskSource) -> Outcome<NativeTask> {
        let read = Arc::new(ReadTask::of(&source)?);
        Ok(NativeTask { source, read })
    }

    /// The call's choices read for this task.
    pub(crate) fn posed(&self, keywords: &Keywords<'_>) -> Outcome<Posed> {
        Posed::read(self.source.clone(), self.read.clone(), keywords)
    }
}

/// The text of the task file at `path` (None: the built-in task, its robot null, which means the
/// built-in robot), to change and read again as a given task.
#[pyfunction]
#[pyo3(signature = (path=None))]
pub fn task_text(py: Python<'_>, path: Option<PathBuf>) -> PyResult<String> {
    let Some(path) = path else {
        let built_in = || -> Result<String, serde_json::Error> {
            let mut value: serde_json::Value = serde_json::from_str(BUILT_IN_TASK)?;
            value["robot"] = serde_json::Value::Null;
            serde_json::to_string(&value)
        };
        return built_in().map_err(|e| Failure::solver(e.to_string()).into_py(py));
    };
    codesign_core::input::read_text(&path, codesign_core::input::MAX_TASK_BYTES)
        .map_err(|e| Failure::input(format!("task file {}: {e}", path.display())).into_py(py))
}

#[pymethods]
impl NativeTask {
    /// The task file at `path`, read and checked.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<NativeTask> {
        NativeTask::of(TaskSource::File(path)).map_err(|f| f.into_py(py))
    }

    /// The built-in task.
    #[staticmethod]
    fn builtin(py: Python<'_>) -> PyResult<NativeTask> {
        NativeTask::of(TaskSource::BuiltIn).map_err(|f| f.into_py(py))
    }

    /// The task of JSON `text`, named `label`, read and checked as a file is; a relative robot
    /// path is resolved against `folder`.
    #[staticmethod]
    fn given(py: Python<'_>, text: &str, label: &str, folder: PathBuf) -> PyResult<NativeTask> {
        let file = TaskFile::from_text(text, label, &folder)
            .map_err(|e| Failure::input(e.to_string()).into_py(py))?;
        let given = GivenTask {
            label: label.to_owned(),
            file,
        };
        NativeTask::of(TaskSource::Given(Arc::new(given))).map_err(|f| f.into_py(py))
    }

    /// How result documents name the task (`task_file`).
    fn label(&self) -> String {
        self.source.label()
    }

    /// The inspection of `codesign check` as JSON, its text, its problems and its warnings.
    #[pyo3(signature = (payload=None, ends=None, ratios=None))]
    fn check(
        &self,
        py: Python<'_>,
        payload: Option<f64>,
        ends: Option<&str>,
        ratios: Option<Vec<f64>>,
    ) -> PyResult<(String, String, Vec<String>, Vec<String>)> {
        let keywords = Keywords {
            space: "actuation",
            payload,
            ends,
            torque_mode: None,
            speed_mode: None,
            linear_solver: None,
        };
        let inspect = || -> Outcome<(String, String, Vec<String>, Vec<String>)> {
            let posed = self.posed(&keywords)?;
            let loaded = posed.load()?;
            let tolerance = loaded.settings.constraint_tolerance();
            let inspection =
                TaskInspection::of(&loaded.task, &loaded.robot, ratios.as_deref(), tolerance)
                    .map_err(|e| Failure::input(format!("{}: {e}", posed.model.source())))?;
            let text = serde_json::to_string_pretty(&inspection)
                .map_err(|e| Failure::solver(e.to_string()))?;
            let words = inspection.to_text();
            Ok((text, words, inspection.problems(), inspection.warnings()))
        };
        inspect().map_err(|failure| failure.into_py(py))
    }

    /// One solve, as `codesign solve --out` writes it, and where it ended (see `Task.solve`).
    #[pyo3(signature = (space, payload=None, ends=None, torque_mode=None, speed_mode=None,
        linear_solver=None, ratios=None, duration=None, steps=None, elastic=false, start=None,
        motion=None, minimum_time=false, free_horizon=None))]
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &self,
        py: Python<'_>,
        space: &str,
        payload: Option<f64>,
        ends: Option<&str>,
        torque_mode: Option<&str>,
        speed_mode: Option<&str>,
        linear_solver: Option<&str>,
        ratios: Option<Vec<f64>>,
        duration: Option<Vec<f64>>,
        steps: Option<usize>,
        elastic: bool,
        start: Option<Py<NativeSolution>>,
        motion: Option<String>,
        minimum_time: bool,
        free_horizon: Option<&str>,
    ) -> PyResult<NativeSolution> {
        let free_horizon = (free_horizon.map(|name| {
            FreeHorizonSearch::from_name(name).ok_or_else(|| {
                Failure::input(format!(
                    "free_horizon={name:?}: must be one of {}",
                    FreeHorizonSearch::names().join(", ")
                ))
            })
        }))
        .transpose()
        .map_err(|f| f.into_py(py))?;
        let keywords = Keywords {
            space,
            payload,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
        };
        let posed = self.posed(&keywords).map_err(|f| f.into_py(py))?;
        let request = SolveRequest {
            posed,
            ratios,
            duration,
            steps,
            elastic,
            start,
            motion,
            minimum_time,
            free_horizon,
        };
        interrupt::run(py, move |_| request.solve(), |_, _, _, _| Ok(()))
    }

    /// The payload capacity of a design, as `codesign capacity --out` writes it.
    #[pyo3(signature = (space, ends=None, torque_mode=None, speed_mode=None, linear_solver=None,
        ratios=None, resolution=None, first_step=None, max=None, duration=None))]
    #[allow(clippy::too_many_arguments)]
    fn capacity(
        &self,
        py: Python<'_>,
        space: &str,
        ends: Option<&str>,
        torque_mode: Option<&str>,
        speed_mode: Option<&str>,
        linear_solver: Option<&str>,
        ratios: Option<Vec<f64>>,
        resolution: Option<f64>,
        first_step: Option<f64>,
        max: Option<f64>,
        duration: Option<f64>,
    ) -> PyResult<String> {
        let keywords = Keywords {
            space,
            payload: None,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
        };
        let posed = self.posed(&keywords).map_err(|f| f.into_py(py))?;
        let settings = search_settings(resolution, first_step, max).map_err(|f| f.into_py(py))?;
        interrupt::run(
            py,
            move |_| capacity(&posed, ratios, settings, duration),
            |_, _, _, _| Ok(()),
        )
    }

    /// The payload capacity of a design at each duration, as `codesign tradeoff --out` writes
    /// it (and, given `out`, written there with its plot beside it).
    #[pyo3(signature = (space, durations, ends=None, torque_mode=None, speed_mode=None,
        linear_solver=None, ratios=None, resolution=None, first_step=None, max=None, out=None))]
    #[allow(clippy::too_many_arguments)]
    fn tradeoff(
        &self,
        py: Python<'_>,
        space: &str,
        durations: Vec<f64>,
        ends: Option<&str>,
        torque_mode: Option<&str>,
        speed_mode: Option<&str>,
        linear_solver: Option<&str>,
        ratios: Option<Vec<f64>>,
        resolution: Option<f64>,
        first_step: Option<f64>,
        max: Option<f64>,
        out: Option<PathBuf>,
    ) -> PyResult<String> {
        let keywords = Keywords {
            space,
            payload: None,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
        };
        let posed = self.posed(&keywords).map_err(|f| f.into_py(py))?;
        let settings = search_settings(resolution, first_step, max).map_err(|f| f.into_py(py))?;
        check_durations(&durations)
            .map_err(|e| Failure::input(format!("durations: {e}")).into_py(py))?;
        let asked = TradeoffAsked {
            ratios,
            durations,
            settings,
            out,
        };
        interrupt::run(py, move |_| asked.run(&posed), |_, _, _, _| Ok(()))
    }

    /// The least duration T* of each design at each payload, as `codesign tradeoff --payloads
    /// --out` writes it (and, given `out`, written there with its plot beside it); `designs`
    /// none: the original design alone.
    #[pyo3(signature = (space, payloads, ends=None, torque_mode=None, speed_mode=None,
        linear_solver=None, designs=None, out=None))]
    #[allow(clippy::too_many_arguments)]
    fn time_curve(
        &self,
        py: Python<'_>,
        space: &str,
        payloads: Vec<f64>,
        ends: Option<&str>,
        torque_mode: Option<&str>,
        speed_mode: Option<&str>,
        linear_solver: Option<&str>,
        designs: Option<Vec<Vec<f64>>>,
        out: Option<PathBuf>,
    ) -> PyResult<String> {
        let keywords = Keywords {
            space,
            payload: None,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
        };
        let posed = self.posed(&keywords).map_err(|f| f.into_py(py))?;
        check_payloads(&payloads)
            .map_err(|e| Failure::input(format!("payloads: {e}")).into_py(py))?;
        let asked = TimeCurveAsked {
            designs,
            payloads,
            out,
        };
        interrupt::run(py, move |_| asked.run(&posed), |_, _, _, _| Ok(()))
    }
}

/// The settings of a capacity search from its keywords (None: the default), checked, an error
/// naming the keyword.
fn search_settings(
    resolution: Option<f64>,
    first_step: Option<f64>,
    max: Option<f64>,
) -> Outcome<CapacitySettings> {
    let defaults = CapacitySettings::default();
    let settings = CapacitySettings {
        resolution_kg: resolution.unwrap_or(defaults.resolution_kg),
        first_step_kg: first_step.unwrap_or(defaults.first_step_kg),
        max_kg: max.unwrap_or(defaults.max_kg),
    };
    settings.validate().map_err(|error| {
        let keyword = error.key.trim_end_matches("_kg");
        Failure::input(format!(
            "{keyword}={}: {}",
            number(error.value),
            error.rule()
        ))
    })?;
    Ok(settings)
}

/// What one solve was asked.
struct SolveRequest {
    posed: Posed,
    ratios: Option<Vec<f64>>,
    /// [T] fixes the duration, [T_min, T_max] frees it.
    duration: Option<Vec<f64>>,
    steps: Option<usize>,
    elastic: bool,
    start: Option<Py<NativeSolution>>,
    /// The motion of the task's `motions` list to solve (None: the task's one motion).
    motion: Option<String>,
    /// Solve the task's pure minimum-time problem instead (`solve --minimum-time`).
    minimum_time: bool,
    /// How a free horizon is searched, where given (`solve --free-horizon`).
    free_horizon: Option<FreeHorizonSearch>,
}

impl SolveRequest {
    /// Solves under the one rule, from the start when given; the document and where it ended.
    fn solve(self) -> Outcome<NativeSolution> {
        let mut loaded = (self.posed.load()?)
            .one_motion(self.motion.as_deref())
            .map_err(|why| match self.motion {
                Some(_) => Failure::input(format!("motion={why}")),
                None => Failure::input(format!("motion=: {why}")),
            })?;
        if let Some(duration) = self.duration {
            loaded.task.motion.horizon = horizon_of(&duration)?;
        }
        if let Some(steps) = self.steps {
            check_steps(steps).map_err(|why| Failure::input(format!("steps={steps}: {why}")))?;
            loaded.task.motion.steps = steps;
        }
        if let Some(search) = self.free_horizon {
            loaded.settings.free_horizon = search;
        }
        let hard = match self.minimum_time {
            true => self.posed.minimum_time_formulation(&loaded)?,
            false => self.posed.formulation(&loaded)?,
        };
        let formulation = if self.elastic { hard.elastic() } else { hard };
        let ratios = self.posed.design(&formulation, self.ratios)?;
        let given = self.start.as_ref().map(|start| start.get());
        let start = match given {
            Some(given) => Some(given.point.as_ref().ok_or_else(|| {
                Failure::input(
                    "start=: a run's best solution keeps no point to start from; solve its \
                     design first (ratios=run.best.ratios)",
                )
            })?),
            None => None,
        };
        if let Some(point) = start {
            point
                .check_fits(&formulation, &loaded.task_hash)
                .map_err(|e| Failure::input(format!("start=: {e}")))?;
        }
        let warm = start.map(|point| point.to_solution());
        let warm = warm.as_ref();
        let (result, solution) = solve_design_from(&formulation, &ratios, &loaded.settings, warm)
            .map_err(|e| match e {
            SolveError::Design(_) | SolveError::Formulation(_) | SolveError::Pose { .. } => {
                Failure::input(format!("{}: {e}", self.posed.model.source()))
            }
            SolveError::Ipopt(_) => Failure::solver(format!("solver: {e}")),
        })?;
        if let Some(part) = result.non_finite() {
            return Err(Failure::solver(format!(
                "the solve (IPOPT status {}) gave a result whose {part} holds a number that is \
                 not finite",
                result.status
            )));
        }
        let label = self.posed.model.source().label();
        let point = StartPoint::from_solution(&solution, &formulation, &loaded.task_hash);
        let fits = point.check_fits(&formulation, &loaded.task_hash).is_ok();
        let mut document = SolveDocument::new(
            &label,
            &loaded.task_hash,
            &formulation,
            &loaded.settings,
            result,
        );
        // As `solve --out`: only a point that could start this very problem again is kept.
        if fits {
            document = document.with_start_point(point.clone());
        }
        if let Some(given) = given {
            document = document.started_from(StartRecord {
                file: IN_MEMORY.to_owned(),
                ratios: given.document.result.ratios.clone(),
                payload_kg: given.document.inputs.payload_kg,
            });
        }
        Ok(NativeSolution {
            document,
            point: Some(point),
            formulation: Some(formulation),
        })
    }
}

/// What a result started from a Python solution records as its start's file.
const IN_MEMORY: &str = "start= (a Solution in memory)";

/// The capacity search of design `ratios` (None: the original) with `settings`, each payload
/// moved in `duration` s where given, its document.
fn capacity(
    posed: &Posed,
    ratios: Option<Vec<f64>>,
    settings: CapacitySettings,
    duration: Option<f64>,
) -> Outcome<String> {
    let mut loaded = posed.load()?;
    if loaded.task.has_motions() {
        return Err(Failure::input(format!(
            "{}: a payload capacity is the heaviest payload of one motion, and the task lists \
             {} motions (`motions`); search each motion's capacity with a task of that motion \
             alone",
            posed.model.source(),
            loaded.task.motions.len()
        )));
    }
    if let Some(seconds) = duration {
        loaded.task.motion.horizon = horizon_of(&[seconds])?;
    }
    let formulation = posed.formulation(&loaded)?;
    let ratios = posed.design(&formulation, ratios)?;
    let capacity = payload_capacity(&formulation, &loaded.settings, &ratios, &settings)
        .map_err(|e| Failure::solver(format!("{}: {e}", posed.model.source())))?;
    let document = CapacityDocument {
        tool: ToolInfo::current(loaded.settings.linear_solver()),
        inputs: CapacityInputs {
            task_file: posed.model.source().label(),
            task_hash: RecordedHash(Some(loaded.task_hash.clone())),
            space: formulation.space(),
            ratios,
            limit_modes: *formulation.modes(),
            ends: loaded.task.motion.ends,
            settings,
            duration_s: duration,
        },
        capacity,
    };
    json(&document)
}

/// The horizon of `duration=`: [T] fixed, [T_min, T_max] free, each within the task's range.
fn horizon_of(duration: &[f64]) -> Result<Horizon, Failure> {
    let checked = |name: &str, seconds: f64| {
        check_horizon(seconds)
            .map_err(|why| Failure::input(format!("{name}={}: {why}", number(seconds))))
    };
    match *duration {
        [seconds] => checked("duration", seconds).map(|()| Horizon::Fixed(seconds)),
        [min_s, max_s] => {
            checked("duration[0]", min_s)?;
            checked("duration[1]", max_s)?;
            if min_s >= max_s {
                return Err(Failure::input(format!(
                    "duration=({}, {}): T_min must be below T_max",
                    number(min_s),
                    number(max_s)
                )));
            }
            Ok(Horizon::Free { min_s, max_s })
        }
        _ => Err(Failure::input(
            "duration: a duration in s or a pair (T_min, T_max) in s".to_owned(),
        )),
    }
}
