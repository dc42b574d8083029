//! What a gradient descent lowers at one design: the merit, its gradient in r, the optimal cost
//! where the design is feasible, and the solutions that warm-start the solves near it.

use codesign_core::solve::StartPoint;
use serde::{Deserialize, Serialize};

/// What a descent uses of one design's solves (docs/model.md, section 12).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Merit {
    /// The merit: the optimal cost J* (flat penalty), or the elastic problem's optimal penalised
    /// objective (graded penalty), which is J* where the design is feasible; over a task's
    /// several motions their weighted sum, or the worst weighted one.
    pub value: f64,
    /// Its gradient with respect to the ratios (the exact sensitivity of the solves; over
    /// several motions the weighted sum of theirs, or the active motion's).
    pub gradient: Vec<f64>,
    /// The optimal cost J*, when the design is feasible.
    pub feasible_cost: Option<f64>,
    /// The solves' raw solutions, one per problem of the merit (the one problem, or each motion
    /// in the task's order), to start the solves of designs near it from.
    pub starts: Vec<StartPoint>,
}
