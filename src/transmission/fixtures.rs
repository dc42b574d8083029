//! The built-in task's transmission, shared by the tests of the transmission's modules.

use super::Transmission;
use crate::model::task::Task;
use std::path::Path;

/// The task file `robots/tasks/pick_place.json`.
pub fn pick_place() -> Task {
    Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json")).unwrap()
}

/// The belt arm's transmission, from [`pick_place`].
pub fn belt_arm() -> Transmission {
    Transmission::from_spec(&pick_place().transmission).unwrap()
}
