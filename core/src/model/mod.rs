//! The robot model and the task: what is read from files before any computation.

pub mod carried;
mod carried_mass;
pub mod catalogue;
pub mod chain;
mod ends;
mod error;
pub mod experiment;
mod goal;
mod horizon;
pub mod identity;
pub mod matrix_row;
mod minimum_time;
mod motions;
pub mod motor_parts;
mod motors;
pub mod part_family;
mod part_slots;
mod ranges;
mod read_experiment;
mod robot;
pub mod task;
mod urdf;
mod validate;
mod via;
mod via_nodes;

pub use error::ModelError;
pub use robot::{Robot, BUILT_IN_URDF};

#[cfg(test)]
mod catalogue_tests;
#[cfg(test)]
mod section_tests;
#[cfg(test)]
mod tests;
