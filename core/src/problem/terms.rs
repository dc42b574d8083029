//! Terms added to a trajectory problem from outside the core: constraints and cost terms on the
//! variables of one node, [`NodeConstraint`] and [`NodeCost`], added to a formulation with
//! [`Formulation::with_constraint`](super::Formulation::with_constraint) and
//! [`Formulation::with_cost`](super::Formulation::with_cost).
//!
//! A term sees node k < N: its joint positions q_k (rad), speeds v_k (rad/s), accelerations
//! a_k (rad/s^2) and controls u_k (N m), the step h_k of its interval and the robot's dynamics, and gives its
//! values with exact first and second derivatives over the node's 4n variables, ordered
//! [q_k, v_k, a_k, u_k]. A term must not depend on the design r: dJ*/dr takes none of its terms.
//! Its rows are hard in both kinds of problem, and a result reports each constraint's largest
//! violation and each cost term's value under the term's name.

use super::design_data::DesignData;
use super::layout::Layout;
use crate::dynamics::{Dynamics, Workspace};
use crate::solve::Keyed;
use nalgebra::DMatrix;
use std::fmt;
use std::sync::Arc;

/// What a term reads at one node.
pub struct NodeContext<'a> {
    /// The node k, 0 <= k < N.
    pub k: usize,
    /// The number of intervals N.
    pub steps: usize,
    /// The step h_k of the interval from node k, s (T/N unless the via points split the grid
    /// into phases).
    pub step_s: f64,
    /// Joint positions q_k, rad (m for a prismatic joint).
    pub q: &'a [f64],
    /// Joint speeds v_k, rad/s.
    pub v: &'a [f64],
    /// Joint accelerations a_k, rad/s^2.
    pub a: &'a [f64],
    /// Controls u_k, N m: joint torques in the joint space, motor torques in the actuation space.
    pub u: &'a [f64],
    /// The robot's dynamics and kinematics (with its payload).
    pub dynamics: &'a Dynamics,
    /// A workspace of `dynamics`, for its evaluations at this node.
    pub workspace: &'a mut Workspace,
}

/// Constraint rows on one node's variables, lower <= c(q_k, v_k, a_k, u_k) <= upper, at every
/// node k < N.
///
/// Derivatives are over the node's variables [q, v, a, u] (4n columns).
pub trait NodeConstraint: fmt::Debug + Send + Sync {
    /// Its name: the key of its largest violation in a result.
    fn name(&self) -> &str;

    /// Its number of rows at each node.
    fn rows(&self) -> usize;

    /// Sets the bounds of its rows at node k of N (`f64::INFINITY` for none); `lower` and
    /// `upper` hold [`NodeConstraint::rows`] entries.
    fn bounds(&self, k: usize, steps: usize, lower: &mut [f64], upper: &mut [f64]);

    /// Writes its rows' values.
    fn values(&self, node: &mut NodeContext<'_>, values: &mut [f64]);

    /// Writes its Jacobian, rows x 4n (zeroed before the call).
    fn jacobian(&self, node: &mut NodeContext<'_>, jacobian: &mut DMatrix<f64>);

    /// Adds sum_r multipliers[r] times the Hessian of row r, 4n x 4n, into `hessian` (its lower
    /// triangle is read).
    fn hessian(&self, node: &mut NodeContext<'_>, multipliers: &[f64], hessian: &mut DMatrix<f64>);
}

/// A term of the cost, summed over the nodes k < N.
///
/// Derivatives are over the node's variables [q, v, a, u] (4n entries).
pub trait NodeCost: fmt::Debug + Send + Sync {
    /// Its name: the key of its value among a result's cost terms.
    fn name(&self) -> &str;

    /// Its value at the node.
    fn value(&self, node: &mut NodeContext<'_>) -> f64;

    /// Adds its gradient (4n) into `gradient`.
    fn gradient(&self, node: &mut NodeContext<'_>, gradient: &mut [f64]);

    /// Adds its Hessian (4n x 4n) into `hessian` (its lower triangle is read).
    fn hessian(&self, node: &mut NodeContext<'_>, hessian: &mut DMatrix<f64>);
}

/// The constraints and cost terms added to a formulation, in the order added.
#[derive(Clone, Debug, Default)]
pub(super) struct AddedTerms {
    pub(super) constraints: Vec<Arc<dyn NodeConstraint>>,
    pub(super) costs: Vec<Arc<dyn NodeCost>>,
}

impl AddedTerms {
    /// Whether there are none.
    pub(super) fn is_empty(&self) -> bool {
        self.constraints.is_empty() && self.costs.is_empty()
    }
}

/// How far `value` lies outside [lower, upper].
fn outside(value: f64, lower: f64, upper: f64) -> f64 {
    (lower - value).max(value - upper).max(0.0)
}

/// Runs `f` on node k of the primal point x of the problem of `design`, with its dynamics (the
/// parts the links carry at r included), in a workspace of its own.
pub(super) fn at_node<R>(
    design: &DesignData<'_>,
    x: &[f64],
    k: usize,
    f: impl FnOnce(&mut NodeContext<'_>) -> R,
) -> R {
    let setting = design.setting();
    let layout = setting.layout();
    let (q, v, a) = layout.node_state(x, k);
    let mut workspace = design.dynamics().workspace();
    f(&mut NodeContext {
        k,
        steps: layout.steps,
        step_s: setting.step_at(x, k),
        q,
        v,
        a,
        u: layout.controls(x, k),
        dynamics: design.dynamics(),
        workspace: &mut workspace,
    })
}

/// The added cost terms' sum at x.
pub(super) fn cost(design: &DesignData<'_>, terms: &[Arc<dyn NodeCost>], x: &[f64]) -> f64 {
    let steps = design.setting().layout().steps;
    let node_sum = |node: &mut NodeContext<'_>| terms.iter().map(|t| t.value(node)).sum::<f64>();
    (0..steps).map(|k| at_node(design, x, k, node_sum)).sum()
}

/// Each added cost term's value at x, summed over the nodes, under its name.
pub(super) fn costs(design: &DesignData<'_>, terms: &[Arc<dyn NodeCost>], x: &[f64]) -> Keyed {
    let mut sums = vec![0.0; terms.len()];
    for k in 0..design.setting().layout().steps {
        at_node(design, x, k, |node| {
            for (sum, term) in sums.iter_mut().zip(terms) {
                *sum += term.value(node);
            }
        });
    }
    let mut values = Keyed::default();
    for (term, sum) in terms.iter().zip(sums) {
        values.push(term.name(), sum);
    }
    values
}

/// Adds the added cost terms' gradient at x into `gradient` (over every variable).
pub(super) fn add_cost_gradient(
    design: &DesignData<'_>,
    terms: &[Arc<dyn NodeCost>],
    x: &[f64],
    gradient: &mut [f64],
) {
    let layout = design.setting().layout();
    if terms.is_empty() {
        return;
    }
    let mut node_gradient = vec![0.0; 4 * layout.dof];
    for k in 0..layout.steps {
        node_gradient.fill(0.0);
        at_node(design, x, k, |node| {
            terms
                .iter()
                .for_each(|term| term.gradient(node, &mut node_gradient))
        });
        for (c, column) in node_columns(layout, k).enumerate() {
            gradient[column] += node_gradient[c];
        }
    }
}

/// Each added constraint's largest violation at x, under its name.
pub(super) fn violations(
    design: &DesignData<'_>,
    constraints: &[Arc<dyn NodeConstraint>],
    x: &[f64],
) -> Keyed {
    let mut largest = Keyed::default();
    let steps = design.setting().layout().steps;
    for constraint in constraints {
        let rows = constraint.rows();
        let (mut values, mut lower, mut upper) =
            (vec![0.0; rows], vec![0.0; rows], vec![0.0; rows]);
        let mut worst = 0.0_f64;
        for k in 0..steps {
            constraint.bounds(k, steps, &mut lower, &mut upper);
            at_node(design, x, k, |node| constraint.values(node, &mut values));
            for r in 0..rows {
                worst = worst.max(outside(values[r], lower[r], upper[r]));
            }
        }
        largest.push(constraint.name(), worst);
    }
    largest
}

/// Node k's variables' columns in the order [q, v, a, u].
pub(super) fn node_columns(layout: &Layout, k: usize) -> impl Iterator<Item = usize> + '_ {
    let n = layout.dof;
    (0..4 * n).map(move |c| match c / n {
        0 => layout.q(k, c % n),
        1 => layout.v(k, c % n),
        2 => layout.a(k, c % n),
        _ => layout.u(k, c % n),
    })
}
