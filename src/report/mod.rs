//! Reports: SVG plots, the paper table, the front page of a results folder, and the documents of
//! each command (written through [`crate::store`]).

pub mod check;
pub mod codesign;
mod error;
pub mod export;
pub mod mechanism;
pub mod migrate;
pub mod motor_plots;
pub mod pareto;
pub mod plots;
pub mod poses;
pub mod solve_document;
pub mod start;
pub mod table;
pub mod time_curve;
pub mod tradeoff;
pub mod trajectory;
pub mod world;

pub use error::{ReadFailure, ReportError};
