//! Flags shared by the commands that load a task and a robot.

use crate::model::task::{check_payload, LimitMode, LimitModes, Task};
use crate::model::Robot;
use crate::problem::Space;
use std::path::PathBuf;

/// The default task file, relative to the working directory (the repository root).
pub const DEFAULT_TASK: &str = "robots/tasks/pick_place.json";

/// Where the task and robot come from, and the payload.
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// Task file (JSON): motion, weights, box, motors, transmission, limit modes, solver.
    #[arg(long, value_name = "FILE", default_value = DEFAULT_TASK)]
    pub task: PathBuf,
    /// URDF of the robot; overrides the task's `robot`.
    #[arg(long, value_name = "URDF")]
    pub robot: Option<PathBuf>,
    /// Payload at the task's payload point, kg; overrides the task's `payload.mass_kg`.
    #[arg(long, value_name = "KG", allow_negative_numbers = true)]
    pub payload: Option<f64>,
}

impl ModelArgs {
    /// Loads the task (with the overrides applied) and the robot carrying the payload.
    pub fn load(&self) -> Result<(Task, Robot), String> {
        let mut task = Task::load(&self.task).map_err(|e| e.to_string())?;
        if let Some(robot) = &self.robot {
            task.robot = robot.clone();
        }
        if let Some(payload) = self.payload {
            check_payload(payload).map_err(|why| format!("--payload {payload}: {why}"))?;
            task.payload.mass_kg = payload;
        }
        let robot = Robot::load(&task).map_err(|e| e.to_string())?;
        Ok((task, robot))
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
}

impl ProblemArgs {
    /// The limit modes: the flags where given, else the task's.
    pub fn modes(&self, task: &Task) -> LimitModes {
        LimitModes {
            torque: self.torque_mode.unwrap_or(task.limit_modes.torque),
            speed: self.speed_mode.unwrap_or(task.limit_modes.speed),
        }
    }
}
