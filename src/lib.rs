//! Co-design of the transmissions and the motion of robots with parallel transmissions: the
//! application over the engine, `codesign_core` (the model, dynamics, transmissions, trajectory
//! problem and the solve of one design).
//!
//! The data flow one way: the design loop (`design`: CMA-ES, the gradient method, the payload
//! capacity and the evaluators, in this process or in worker processes), the experiment of a
//! task (`experiment`), the reports (`report`) and the command line (`cli`, with the feature
//! `cli`, on by default: the Python package builds without it). Beneath them, the
//! result store (`store`) writes result files and the evaluation log, and imports nothing from
//! the rest of the crate.

#![warn(missing_docs)]

#[macro_use]
extern crate codesign_core;

#[cfg(feature = "cli")]
pub mod cli;
pub mod design;
pub mod experiment;
pub mod parallel;
pub mod report;
pub mod stats;
pub mod store;
