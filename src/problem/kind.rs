//! Which of the two trajectory problems a formulation poses.

/// Hard or elastic: which trajectory problem a [`Formulation`](super::Formulation) builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProblemKind {
    /// Dynamics and speed limits as hard constraints (the problem of docs/model.md, section 6).
    Hard,
    /// Dynamics and speed limits relaxed by slacks under an exact penalty (section 14).
    Elastic,
}
