//! Co-design of the gear ratios and the motion of robots with parallel (belt) transmissions.
//!
//! The data flow one way: the robot model, its rigid-body dynamics, the trajectory problem, the
//! IPOPT solve, the design loop, and the reports. Beneath them all, the store writes result
//! files and the evaluation log, and imports nothing from the rest of the crate.

#![warn(missing_docs)]

pub mod cli;
pub mod design;
pub mod dynamics;
pub mod ipopt;
pub mod ldl;
pub mod model;
pub mod problem;
pub mod report;
pub mod solver;
pub mod stats;
pub mod store;
#[cfg(test)]
mod testing;
pub mod transmission;
