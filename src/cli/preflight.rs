//! The check of a co-design run made before its first evaluation: whether IPOPT takes the task's
//! solver options.

use super::case::Case;
use crate::model::task::{LimitModes, Task};
use crate::model::Robot;
use crate::problem::Formulation;
use crate::solve::{solve_design, SolveError, SolveSettings};

/// Solves the original design once on a 2-interval copy of the problem, so that a solver
/// option IPOPT rejects (the task file's `solver`) fails the run before its first generation,
/// with IPOPT's complaint, instead of penalising every design.
pub fn probe_solver(
    task: &Task,
    settings: &SolveSettings,
    robot: &Robot,
    case: &Case,
    modes: LimitModes,
) -> Result<(), String> {
    let mut small = task.clone();
    small.motion.steps = 2;
    let formulation = Formulation::new(&small, robot.clone(), case.problem.space, modes)
        .map_err(|e| e.to_string())?;
    match solve_design(&formulation, &small.transmission.original, settings) {
        Err(SolveError::Ipopt(error)) => Err(format!(
            "{} solver: {error} (checked by a solve of the original design before the run)",
            case.model.source()
        )),
        _ => Ok(()),
    }
}
