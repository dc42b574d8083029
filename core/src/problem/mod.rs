//! The trajectory problem (docs/model.md, section 6) of one design, as a sparse NLP for IPOPT.
//!
//! A [`Formulation`] fixes everything but the design: its [`Setting`] (task, robot and payload,
//! space and limit modes, motors, [`Layout`]), and with it the problem's constraint families
//! (`families/`, one file each) and its sparsity patterns, built once; `shortening.rs` derives
//! the formulations that shorten a free horizon. Its
//! [`Formulation::problem`] gives the [`TrajectoryProblem`] of one design r, which implements
//! [`crate::ipopt::Nlp`] with exact, hand-derived sparse derivatives by walking the families
//! node by node. A family reads the setting and, for one design, its [`DesignData`] (r, G(r)
//! and the controls' map to torques), never the whole problem: the modules below `families/`
//! (`setting.rs`, `design_data.rs`, `layout.rs`, `node.rs`, `terms.rs`) import nothing above
//! them. A formulation whose
//! solve would need more memory than the machine has available is refused before its patterns
//! are built ([`MemoryNeed`], `memory.rs`). Constraints and cost
//! terms on one node's variables may be added from outside the core ([`NodeConstraint`],
//! [`NodeCost`], `terms.rs`).

mod cost;
mod design_data;
mod error;
mod families;
mod formulation;
#[cfg(test)]
mod goal_tests;
mod grid;
mod hessian;
mod hold;
#[cfg(test)]
mod horizon_tests;
mod kind;
mod layout;
mod memory;
mod nlp;
mod node;
mod pose_rules;
#[cfg(test)]
mod pose_tests;
mod sensitivity;
mod setting;
mod shortening;
mod targets;
mod terms;
#[cfg(test)]
pub(crate) mod tests;
#[cfg(test)]
mod via_tests;
#[cfg(test)]
mod window_tests;

pub use crate::transmission::Space;
pub use cost::{CostTerms, Criterion};
pub use design_data::DesignData;
pub use error::FormulationError;
pub use families::elastic::{penalty_weights, relaxation, PenaltyWeights, Relaxation};
pub use families::FamilyId;
pub use formulation::{Formulation, Shaping};
pub use grid::Grid;
pub use hold::{margins, EndHold, HoldRows, StaticHold};
pub use kind::ProblemKind;
pub use layout::{BlockId, Layout, Nodes, RowBlock};
pub use memory::{available_bytes, MemoryNeed, BASE_BYTES, BYTES_PER_NONZERO};
pub use nlp::TrajectoryProblem;
pub use pose_rules::check_modes;
pub use sensitivity::cost_gradient;
pub use setting::{Setting, DEFAULT_HOLD_TOLERANCE_NM};
pub use targets::{Boundary, JointTarget, Targets, TcpTarget, UprightTarget};
pub use terms::{NodeConstraint, NodeContext, NodeCost};
