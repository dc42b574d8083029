//! The outer, design level: CMA-ES over the design ratios, driven ask/tell so that designs are
//! evaluated by an [`evaluate::Evaluator`] (worker processes, or threads of this process) or
//! replayed from a log on resumption, and the gradient method.

pub mod bounds;
pub mod capacity;
pub mod cmaes;
pub mod evaluate;
pub mod gradient;
pub mod optimize;
pub mod outcome;
pub mod parts;
pub mod penalty;
pub mod run;
pub mod score;
pub mod time_curve;
pub mod tradeoff;
pub mod verdicts;
pub mod warm;
pub mod workers;

pub use penalty::PENALTY;
