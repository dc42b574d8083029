//! Why a design could not be solved at all.

use crate::ipopt;
use crate::problem::FormulationError;
use crate::transmission::{DesignError, PoseError};
use std::fmt;

/// Why a design could not be solved at all. (A design that is valid but infeasible is not an
/// error: it is a [`super::TrajectoryResult`] with `feasible: false`.)
#[derive(Clone, Debug, PartialEq)]
pub enum SolveError {
    /// The design is outside its space (bounds, order constraints, not finite, singular G).
    Design(DesignError),
    /// IPOPT could not run (a callback failed, an option was rejected).
    Ipopt(ipopt::Error),
    /// The problem could not be formulated at a payload of the payload continuation.
    Formulation(FormulationError),
    /// A linkage of the transmission does not close at a node of the solution read back.
    Pose {
        /// The node k.
        node: usize,
        /// Which linkage, and what it lacks.
        error: PoseError,
    },
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveError::Design(error) => write!(f, "invalid design: {error}"),
            SolveError::Ipopt(error) => write!(f, "{error}"),
            SolveError::Formulation(error) => write!(f, "payload continuation: {error}"),
            SolveError::Pose { node, error } => {
                write!(f, "at node {node} of the solution: {error}")
            }
        }
    }
}

impl std::error::Error for SolveError {}

impl From<DesignError> for SolveError {
    fn from(error: DesignError) -> SolveError {
        SolveError::Design(error)
    }
}

impl From<ipopt::Error> for SolveError {
    fn from(error: ipopt::Error) -> SolveError {
        SolveError::Ipopt(error)
    }
}

impl From<FormulationError> for SolveError {
    fn from(error: FormulationError) -> SolveError {
        SolveError::Formulation(error)
    }
}
