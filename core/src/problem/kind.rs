//! Which of the two trajectory problems a formulation poses.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Hard or elastic: which trajectory problem a [`Formulation`](super::formulation::Formulation) builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProblemKind {
    /// Dynamics and speed limits as hard constraints (the problem of docs/model.md, section 6).
    Hard,
    /// Dynamics and speed limits relaxed by slacks under an exact penalty (section 14).
    Elastic,
}

impl ProblemKind {
    /// The lower-case name used in files: `hard` or `elastic`.
    pub fn name(self) -> &'static str {
        match self {
            ProblemKind::Hard => "hard",
            ProblemKind::Elastic => "elastic",
        }
    }
}

impl fmt::Display for ProblemKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
