//! What a formulation poses where G depends on the pose (docs/model.md, section 17), and what it
//! refuses there, naming the field to change.
//!
//! The box modes `paper` and `interval` carry the motor limits to fixed boxes on the joints
//! through one constant G; with G(q) no box is the motors' limit, so such a task must use the
//! mode `exact`, whose rows hold each motor's own limit at every node. The motors' rotor
//! inertia and friction (their speed term dG/dt v included), their torque-speed envelope and
//! the transmissions' losses are posed through G(q).

use super::error::FormulationError;
use crate::model::task::{LimitMode, LimitModes};
use crate::transmission::{Space, Transmission};

/// Ok where `transmission` is constant, or where the problem's space and modes pose its
/// pose-dependent rows; otherwise the error naming every limit mode to change (the torque mode
/// only in the joint space: the actuation space's controls are the motor torques themselves).
/// `codesign check` reports the same words before any solve.
pub fn check_modes(
    transmission: &Transmission,
    space: Space,
    modes: &LimitModes,
) -> Result<(), FormulationError> {
    let Some(first) = transmission.linkages().first() else {
        return Ok(());
    };
    let torque = (space == Space::Joint).then_some(("torque", modes.torque));
    let boxed: Vec<(&str, LimitMode)> = [torque, Some(("speed", modes.speed))]
        .into_iter()
        .flatten()
        .filter(|&(_, mode)| mode != LimitMode::Exact)
        .collect();
    if boxed.is_empty() {
        return Ok(());
    }
    let given: Vec<String> = (boxed.iter())
        .map(|(which, mode)| format!("limit_modes.{which} = \"{}\"", mode.name()))
        .collect();
    let wanted: Vec<String> = (boxed.iter())
        .map(|(which, _)| format!("limit_modes.{which} = \"exact\""))
        .collect();
    let (carry, hold) = match boxed.len() {
        1 => ("carries", "holds"),
        _ => ("carry", "hold"),
    };
    Err(FormulationError(format!(
        "task: transmission.matrix[{}] is a {} linkage, whose ratio changes with the pose: {} \
         {carry} the motor limits to a fixed box on the joints through one constant G; give {}, \
         which {hold} each motor's own limit through G(q) at every node",
        first.motor,
        first.linkage.kind(),
        given.join(" and "),
        wanted.join(" and ")
    )))
}
