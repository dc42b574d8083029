//! A sparse LDLᵀ for IPOPT's KKT systems, plugged into IPOPT through its Pardiso interface.
//!
//! IPOPT 3.11 as Debian builds it can load a Pardiso library at run time. This module is such a
//! library, written in Rust: [`Symbolic`] analyses a structure once (fill-reducing order with
//! every constraint row behind a primal neighbour, elimination tree, the pattern of L and the
//! index maps), [`Numeric`] factorises and solves with it for each new matrix without allocating,
//! and reports the exact inertia IPOPT needs for its inertia correction. [`pardiso`] speaks the
//! Pardiso calling convention; [`install`] hands it to IPOPT (see `loader.rs`).
//!
//! Every factorisation lives behind IPOPT's own Pardiso handle, so solves with this linear
//! solver may run on several threads at once. The analyses are shared: [`AnalysisCache::shared`]
//! keeps those of the last few structures, so that a process solving many problems of one shape
//! analyses it once.

mod cache;
mod loader;
mod numeric;
mod ordering;
mod pardiso;
mod symbolic;
#[cfg(test)]
mod tests;

pub use cache::{AnalysisCache, CacheCounts, KEPT_ANALYSES};
pub use loader::{install, InstallError};
pub use numeric::{Inertia, Numeric, CANCELLATION};
pub use symbolic::{Symbolic, UpperCsr};

use std::fmt;

/// Why a matrix could not be analysed or factorised.
#[derive(Clone, Debug, PartialEq)]
pub enum LdlError {
    /// The structure arrays are inconsistent (lengths, indices outside the upper triangle).
    Structure(String),
    /// A pivot had nothing to be computed from (an empty row and column): the matrix is
    /// singular.
    Singular {
        /// Index of the pivot in elimination order.
        pivot: usize,
    },
    /// A pivot came out infinite or NaN (a non-finite value in the matrix, or overflow).
    NotFinite {
        /// Index of the pivot in elimination order.
        pivot: usize,
    },
}

impl fmt::Display for LdlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LdlError::Structure(what) => write!(f, "inconsistent sparse structure: {what}"),
            LdlError::Singular { pivot } => write!(f, "singular matrix (pivot {pivot} vanished)"),
            LdlError::NotFinite { pivot } => write!(f, "pivot {pivot} is not finite"),
        }
    }
}

impl std::error::Error for LdlError {}
