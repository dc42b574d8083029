//! The built-in task's transmission, shared by the tests of the transmission's modules.

use super::Transmission;
use crate::model::task::Task;

/// The task file `robots/tasks/pick_place.json`.
pub fn pick_place() -> Task {
    crate::testing::task()
}

/// The belt arm's transmission, from [`pick_place`].
pub fn belt_arm() -> Transmission {
    Transmission::from_spec(&pick_place().transmission).unwrap()
}
