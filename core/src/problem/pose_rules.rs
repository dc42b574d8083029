//! What a formulation poses where G depends on the pose (docs/model.md, section 17), and what it
//! refuses there, naming the field to change.
//!
//! The box modes `paper` and `interval` carry the motor limits to fixed boxes on the joints
//! through one constant G; with G(q) no box is the motors' limit, so such a task must use the
//! mode `exact`, whose rows hold each motor's own limit at every node. The motors' rotor
//! inertia and friction (their speed term dG/dt v included), their torque-speed envelope and
//! the transmissions' losses are posed through G(q).

use super::formulation::FormulationError;
use crate::model::task::{LimitMode, LimitModes};
use crate::transmission::{Space, Transmission};

/// Ok where `transmission` is constant, or where the problem's space and modes pose its
/// pose-dependent rows; otherwise the error naming the field.
pub(super) fn check(
    transmission: &Transmission,
    space: Space,
    modes: &LimitModes,
) -> Result<(), FormulationError> {
    let Some(first) = transmission.linkages().first() else {
        return Ok(());
    };
    let row = format!(
        "transmission.matrix[{}] is a {} linkage, whose ratio changes with the pose",
        first.motor,
        first.linkage.kind()
    );
    let refuse = |why: String| Err(FormulationError(format!("task: {row}: {why}")));
    let boxed = |mode: LimitMode, which: &str| {
        format!(
            "limit_modes.{which} = \"{}\" carries the motor limits to a fixed box on the joints \
             through one constant G; give limit_modes.{which} = \"exact\", which holds each \
             motor's own limit through G(q) at every node",
            mode.name()
        )
    };
    if modes.speed != LimitMode::Exact {
        return refuse(boxed(modes.speed, "speed"));
    }
    if space == Space::Joint && modes.torque != LimitMode::Exact {
        return refuse(boxed(modes.torque, "torque"));
    }
    Ok(())
}
