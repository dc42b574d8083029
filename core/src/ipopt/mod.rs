//! A safe API over IPOPT's C interface: a trait for sparse NLPs, typed options, and a solve that
//! never lets a Rust panic cross into C and never runs two MUMPS factorisations at once. IPOPT
//! factorises its KKT systems with this crate's LDLᵀ ([`crate::ldl`]) or with MUMPS.

mod callbacks;
mod check;
#[cfg(test)]
mod domain_tests;
mod error;
mod hs071;
mod nlp;
mod options;
mod problem;
mod solve;
mod status;

pub use check::{check_derivatives, DerivativeOrder, DerivativeReport};
pub use error::Error;
pub use hs071::{Hs071, HS071_OPTIMUM};
pub use nlp::{EvalError, Nlp};
pub use options::{LinearSolver, OptionValue, Options};
pub use solve::{solve, solve_from, Solution, Timing};
pub use status::Status;

/// Version of the IPOPT library this binary links, as pkg-config reported it at build time.
pub const IPOPT_VERSION: &str = env!("CODESIGN_IPOPT_VERSION");
