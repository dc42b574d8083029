//! Flags shared by the commands that load a task and a robot.

use crate::ipopt::LinearSolver;
use crate::model::task::{check_payload, LimitMode, LimitModes, Task, TaskSource};
use crate::model::Robot;
use crate::problem::Space;
use crate::solve::SolveSettings;
use std::path::{Path, PathBuf};

/// Where the task and robot come from, and the payload.
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// Task file (JSON): motion, weights, box, motors, transmission, limit modes, solver
    /// [default: the built-in task, which `codesign task` prints].
    #[arg(long, value_name = "FILE")]
    pub task: Option<PathBuf>,
    /// URDF of the robot; overrides the task's `robot` [default: the task's, or the built-in
    /// robot for the built-in task].
    #[arg(long, value_name = "URDF")]
    pub robot: Option<PathBuf>,
    /// Payload at the task's payload point, kg; overrides the task's `payload.mass_kg`.
    #[arg(long, value_name = "KG", allow_negative_numbers = true)]
    pub payload: Option<f64>,
}

/// The task `--task` names, or the built-in one.
pub fn task_source(task: Option<&PathBuf>) -> TaskSource {
    task.map_or(TaskSource::BuiltIn, |path| TaskSource::File(path.clone()))
}

impl ModelArgs {
    /// The files a command with these flags reads, each with where it was named: the task file
    /// (unless built in) and the robot's URDF (unless built in). An output must be none of them.
    pub fn inputs<'a>(&'a self, task: &'a Task) -> Vec<(&'static str, &'a Path)> {
        let task_file = self.task.as_deref().map(|path| ("--task", path));
        let robot = task.robot.as_deref().map(|path| ("robot", path));
        task_file.into_iter().chain(robot).collect()
    }

    /// Where the task comes from.
    pub fn source(&self) -> TaskSource {
        task_source(self.task.as_ref())
    }

    /// Loads the task (with the overrides applied), the robot carrying the payload, and the
    /// solve settings of the task file's `solver` section.
    pub fn load(&self) -> Result<(Task, Robot, SolveSettings), String> {
        let source = self.source();
        let file = source.load().map_err(|e| e.to_string())?;
        let settings = SolveSettings::from_section(file.solver.as_ref())
            .map_err(|e| format!("{source}: {e}"))?;
        let mut task = file.task;
        if let Some(robot) = &self.robot {
            task.robot = Some(robot.clone());
        }
        if let Some(payload) = self.payload {
            check_payload(payload).map_err(|why| format!("--payload {payload}: {why}"))?;
            task.payload.mass_kg = payload;
        }
        let robot = Robot::load(&task).map_err(|e| match (&self.robot, self.source()) {
            (None, source @ TaskSource::File(_)) => format!(
                "{e} (the `robot` of {source}, relative to its folder; see `codesign task --help`)"
            ),
            _ => e.to_string(),
        })?;
        Ok((task, robot, settings))
    }
}

/// The space and limit modes of the trajectory problem.
#[derive(Debug, Clone, clap::Args)]
pub struct ProblemArgs {
    /// Joint torques (baseline) or motor torques (the paper's method) as controls.
    #[arg(long, value_enum, default_value = "actuation")]
    pub space: Space,
    /// Joint torque limit mode of the joint-space problem; default: the task's.
    #[arg(long, value_enum, value_name = "MODE")]
    pub torque_mode: Option<LimitMode>,
    /// Joint speed limit mode; default: the task's.
    #[arg(long, value_enum, value_name = "MODE")]
    pub speed_mode: Option<LimitMode>,
    /// Linear solver inside IPOPT: codesign's sparse LDLᵀ or MUMPS; default: the task's
    /// `solver.linear_solver`, else ldl.
    #[arg(long, value_enum, value_name = "SOLVER")]
    pub linear_solver: Option<LinearSolver>,
}

impl ProblemArgs {
    /// Applies `--linear-solver` to the solve settings.
    pub fn configure(&self, settings: &mut SolveSettings) {
        settings.override_linear_solver(self.linear_solver);
    }

    /// The limit modes: the flags where given, else the task's.
    pub fn modes(&self, task: &Task) -> LimitModes {
        LimitModes {
            torque: self.torque_mode.unwrap_or(task.limit_modes.torque),
            speed: self.speed_mode.unwrap_or(task.limit_modes.speed),
        }
    }
}
