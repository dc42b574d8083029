//! The constraint families of the trajectory NLP (docs/model.md, section 6), one file each.
//!
//! A family owns everything of one kind of constraint: the rows it adds at a node (a
//! [`RowBlock`] the [`Layout`] places), the bounds it puts on rows and variables, its values,
//! its Jacobian entries (the structure and the values from one routine), its terms of the
//! Lagrangian's Hessian and its terms of the design sensitivity dJ*/dr. The NLP adapter
//! (`nlp.rs`) and the sensitivity (`sensitivity.rs`) only walk the formulation's families, in
//! the order of [`FamilyId::ALL`]: the order of their rows within a node, of their Jacobian
//! entries and of their terms. Adding a family is a new file here and its entry in that list
//! (and in `build` below). A constraint added from outside the core
//! ([`crate::problem::NodeConstraint`]) joins the list after them, as an `added::Added`.
//! What the families share, the [`Family`] trait and what its visits
//! read, is in `family.rs`, which they import; nothing here is imported back.
//!
//! The static hold at the ends is no row of the NLP but a check before it (`../hold.rs`).

pub(super) mod added;
mod dynamics;
pub(super) mod elastic;
mod ends;
mod envelope;
mod family;
mod goal;
mod integration;
mod joint_limits;
mod motor_load;
pub(super) use motor_load::{own_torques, speed_term_torques, speed_terms};
mod motor_speed;
mod motor_torque;
mod posed_loss;
mod strokes;
mod upright;
mod via;

pub use family::FamilyId;
pub(super) use family::{
    jacobian_count, jacobian_pattern, visit_jacobian, visit_wide_hessian, At, DesignDerivative,
    Families, Family, LoadDerivative, NodeSecondOrder, Place, Shape,
};

use super::layout::BlockId;
use std::sync::Arc;

/// The family `id` for `shape`, None where the shape has none: with [`FamilyId::ALL`], the list
/// a new family joins.
fn build(id: FamilyId, shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    match id {
        FamilyId::Dynamics => dynamics::of(shape),
        FamilyId::Integration => integration::of(shape),
        FamilyId::MotorSpeed => motor_speed::of(shape),
        FamilyId::MotorTorque => motor_torque::of(shape),
        FamilyId::Envelope => envelope::of(shape),
        FamilyId::JointLimits => joint_limits::of(shape),
        FamilyId::Ends => ends::of(shape),
        FamilyId::Strokes => strokes::of(shape),
        FamilyId::Via => via::of(shape),
        FamilyId::Goal => goal::of(shape),
        FamilyId::Upright => upright::of(shape),
        FamilyId::Slacks => elastic::of(shape),
    }
}

/// The families of `shape`, in order, keyed by their row blocks.
pub(super) fn of(shape: &Shape<'_>) -> Vec<(BlockId, Arc<dyn Family>)> {
    FamilyId::ALL
        .into_iter()
        .filter_map(|id| build(id, shape).map(|family| (id.into(), family)))
        .collect()
}
