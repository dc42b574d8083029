//! The outer, design level: CMA-ES over the design ratios, driven ask/tell so that designs are
//! evaluated elsewhere (worker processes, or a log replayed on resumption).

pub mod bounds;
pub mod capacity;
pub mod cmaes;
pub mod gradient;
pub mod optimize;
pub mod outcome;
pub mod penalty;
pub mod rng;
pub mod run;
pub mod score;
pub mod warm;
pub mod workers;

pub use penalty::PENALTY;
