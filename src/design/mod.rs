//! The outer, design level: CMA-ES over the design ratios, driven ask/tell so that designs are
//! evaluated elsewhere (worker processes, or a log replayed on resumption).

pub mod cmaes;
pub mod rng;
