//! The task an experiment runs: read with its robot, its solve settings and its hash, and
//! formulated per payload and space.

use super::{ExperimentError, Plan};
use crate::design::run::task_source;
use codesign_core::model::identity::task_hash;
use codesign_core::model::task::{Task, TaskFile};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::SolveSettings;

/// The experiment's task, checked with its robot.
pub struct ExperimentTask {
    /// The task as read.
    pub task: Task,
    /// Its solve settings, the plan's linear solver applied.
    pub solver: SolveSettings,
    /// Its task hash on its robot (`model::identity::task_hash`).
    pub hash: String,
}

impl ExperimentTask {
    /// The plan's task from its `file` (the plan's ends applied), its solve settings (the
    /// plan's linear solver applied) and its task hash, checked with its robot.
    pub fn load(plan: &Plan, mut file: TaskFile) -> Result<ExperimentTask, ExperimentError> {
        if file.task.has_motions() {
            return Err(ExperimentError::SeveralMotions {
                source: task_source(plan.task.as_ref()),
                motions: file.task.motions.len(),
            });
        }
        file.task.motion.ends = plan.ends;
        let mut solver = SolveSettings::from_section(file.solver.as_ref()).map_err(|error| {
            ExperimentError::Settings {
                source: task_source(plan.task.as_ref()),
                error,
            }
        })?;
        solver.override_linear_solver(plan.linear_solver);
        let robot = Robot::load(&file.task)?;
        Ok(ExperimentTask {
            hash: task_hash(&file.task, robot.urdf_hash()),
            task: file.task,
            solver,
        })
    }

    /// The formulation of the task with `payload_kg` in `space`, with the task's limit modes.
    pub fn formulation_at(
        &self,
        payload_kg: f64,
        space: Space,
    ) -> Result<Formulation, ExperimentError> {
        let robot = Robot::load(&self.task)?;
        let formulation = Formulation::new(&self.task, robot, space, self.task.limit_modes)?
            .with_hold_tolerance(self.solver.constraint_tolerance())
            .with_payload(payload_kg)?;
        Ok(formulation)
    }
}
