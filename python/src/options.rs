//! The keyword arguments every method shares, read into the library's choices: where the task
//! comes from with its payload and ends, and the space, limit modes and linear solver.

use crate::errors::{Failure, Outcome};
use codesign::design::penalty::Penalty;
use codesign::design::run::{Loaded, ModelChoice, ProblemChoice};
use codesign::store::log::Start;
use codesign_core::choice::Choice;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::{Ends, LimitMode, TaskFile, TaskSource};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, FormulationError, Space};
use codesign_core::text::{listed, number};
use std::sync::Arc;

/// The start of a run from the keywords `resume` and `overwrite`, which exclude each other.
pub fn start_of(resume: bool, overwrite: bool) -> Outcome<Start> {
    if resume && overwrite {
        return Err(Failure::input("resume=True and overwrite=True: choose one"));
    }
    Ok(Start::from_flags(resume, overwrite))
}

/// The value of keyword `name` among the values of `T` (the command line's names), or an error
/// listing them.
pub fn choice<T: Choice>(name: &str, text: &str) -> Outcome<T> {
    T::from_name(text).ok_or_else(|| {
        Failure::input(format!(
            "{name}={text:?}: must be one of {}",
            T::names().join(", ")
        ))
    })
}

/// The penalty of `penalty=` (`"flat"`, the paper's; `"graded"`; or a number, a flat penalty of
/// that value), as the command line's `--penalty` reads it.
pub fn penalty_of(text: Option<&str>) -> Outcome<Option<Penalty>> {
    text.map(|text| {
        text.parse::<Penalty>()
            .map_err(|error| Failure::input(format!("penalty={text:?}: {error}")))
    })
    .transpose()
}

/// `choice` of an optional keyword.
pub fn optional<T: Choice>(name: &str, text: Option<&str>) -> Outcome<Option<T>> {
    text.map(|text| choice(name, text)).transpose()
}

/// A task read once, with its robot: what every call on the task starts from, so that a
/// thousand solves read the task file and the URDF once.
#[derive(Debug)]
pub struct ReadTask {
    /// The task file as read.
    pub file: TaskFile,
    /// The robot of its own task (its URDF and payload).
    pub robot: Robot,
}

impl ReadTask {
    /// Reads the task from `source` and its robot; errors name the file.
    pub fn of(source: &TaskSource) -> Outcome<ReadTask> {
        let file = source.load().map_err(|e| Failure::input(e.to_string()))?;
        let robot = Robot::load(&file.task)
            .map_err(|e| Failure::input(format!("{e} (the `robot` of {source})")))?;
        Ok(ReadTask { file, robot })
    }
}

/// The model and problem of one call: the task, its payload and ends, and the space, limit modes
/// and linear solver.
#[derive(Clone, Debug)]
pub struct Posed {
    /// Task, payload and ends.
    pub model: ModelChoice,
    /// Space, limit modes and linear solver.
    pub problem: ProblemChoice,
    /// The task and robot as read when the task was made.
    read: Arc<ReadTask>,
}

/// The keywords [`Posed`] is read from, as Python gives them.
pub struct Keywords<'a> {
    /// `space=`: `joint` or `actuation`.
    pub space: &'a str,
    /// `payload=`, kg.
    pub payload: Option<f64>,
    /// `ends=`: `paper`, `hold` or `rest`.
    pub ends: Option<&'a str>,
    /// `torque_mode=`.
    pub torque_mode: Option<&'a str>,
    /// `speed_mode=`.
    pub speed_mode: Option<&'a str>,
    /// `linear_solver=`: `ldl` or `mumps`.
    pub linear_solver: Option<&'a str>,
}

impl Keywords<'_> {
    /// The model (the task from `source`) and problem these keywords choose; an unknown name or
    /// a payload out of range is an input error naming the keyword.
    pub fn choices(&self, source: TaskSource) -> Outcome<(ModelChoice, ProblemChoice)> {
        let keywords = self;
        let model = ModelChoice {
            task: source,
            robot: None,
            payload: keywords.payload,
            ends: optional::<Ends>("ends", keywords.ends)?,
        };
        if let Some(payload) = keywords.payload {
            codesign_core::model::task::check_payload(payload)
                .map_err(|why| Failure::input(format!("payload={}: {why}", number(payload))))?;
        }
        let problem = ProblemChoice {
            space: choice::<Space>("space", keywords.space)?,
            torque_mode: optional::<LimitMode>("torque_mode", keywords.torque_mode)?,
            speed_mode: optional::<LimitMode>("speed_mode", keywords.speed_mode)?,
            linear_solver: optional::<LinearSolver>("linear_solver", keywords.linear_solver)?,
        };
        Ok((model, problem))
    }
}

impl Posed {
    /// Reads the keywords for the task from `source`; an unknown name or a payload out of range
    /// is an input error naming the keyword.
    pub fn read(
        source: TaskSource,
        read: Arc<ReadTask>,
        keywords: &Keywords<'_>,
    ) -> Outcome<Posed> {
        let (model, problem) = keywords.choices(source)?;
        Ok(Posed {
            model,
            problem,
            read,
        })
    }

    /// Loads the task and robot, the solve settings with the linear solver applied.
    pub fn load(&self) -> Outcome<Loaded> {
        let mut loaded = self
            .model
            .load_from(&self.read.file, Some(&self.read.robot))
            .map_err(Failure::input)?;
        self.problem.configure(&mut loaded.settings);
        Ok(loaded)
    }

    /// The hard formulation of `loaded`'s task in this problem's space and limit modes.
    pub fn formulation(&self, loaded: &Loaded) -> Outcome<Formulation> {
        let modes = self.problem.modes(&loaded.task);
        let robot = loaded.robot.clone();
        self.checked(
            loaded,
            Formulation::new(&loaded.task, robot, self.problem.space, modes),
        )
    }

    /// The formulation of `loaded`'s pure minimum-time problem (`Task::minimum_time`), its
    /// free horizon shortened, where the settings ask it, through fixed-horizon problems with
    /// the task's own weights and box (`solve --minimum-time`).
    pub fn minimum_time_formulation(&self, loaded: &Loaded) -> Outcome<Formulation> {
        let modes = self.problem.modes(&loaded.task);
        let robot = loaded.robot.clone();
        self.checked(
            loaded,
            Formulation::minimum_time_of(&loaded.task, robot, self.problem.space, modes),
        )
    }

    /// `formulation` with `loaded`'s hold tolerance, its error naming the task.
    fn checked(
        &self,
        loaded: &Loaded,
        formulation: Result<Formulation, FormulationError>,
    ) -> Outcome<Formulation> {
        let formulation =
            formulation.map_err(|e| Failure::input(format!("{}: {e}", self.model.source())))?;
        Ok(formulation.with_hold_tolerance(loaded.settings.constraint_tolerance()))
    }

    /// `ratios`, or the task's original design; checked against the design space, the error
    /// naming `ratios=` or the task's `transmission.original`.
    pub fn design(&self, formulation: &Formulation, ratios: Option<Vec<f64>>) -> Outcome<Vec<f64>> {
        let (ratios, named) = match ratios {
            Some(ratios) => (ratios, "ratios=".to_owned()),
            None => (
                formulation.task().transmission.original.clone(),
                format!("{} transmission.original", self.model.source()),
            ),
        };
        formulation
            .transmission()
            .check_design(&ratios)
            .map_err(|e| {
                Failure::input(format!("{named} {}: invalid design: {e}", listed(&ratios)))
            })?;
        Ok(ratios)
    }
}
