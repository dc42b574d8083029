//! The robot model and the task: what is read from files before any computation.

pub mod task;
