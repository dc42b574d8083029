//! The Hessian of the Lagrangian obj_factor J + lambda . c, node by node and block by block.
//!
//! Node k's variables [q_k, v_k, a_k, u_k] couple only among themselves, so the Hessian is block
//! diagonal by node. Within a node the lower triangle has five blocks (see [`Block`]): the
//! constraint families' rows, weighted by their multipliers, give q-q, v-q, v-v and a-q (today
//! the dynamics rows alone: a-v and a-a vanish since RNEA is linear in a with a coefficient free
//! of v); the cost gives q-q, the v-v diagonal and the u-u diagonal. The integration and limit
//! rows are linear and add nothing. Transmission losses, a nonlinear function of RNEA and v in
//! the dynamics rows, add the a-v and a-a blocks, which only their formulations store.
//!
//! The entries are stored row by row of the node's lower triangle (a v row holds its v-q part,
//! then its v-v part); the structure and the values are produced from the same entry list, so
//! they always agree.

use super::cost::Cost;
use super::families::{added, Families, NodeSecondOrder};
use super::layout::Layout;
use super::node::NodeEval;
use super::setting::Setting;
use super::terms::{AddedTerms, NodeContext};
use crate::dynamics::{Dynamics, Workspace};
use crate::transmission::Actuation;
use nalgebra::DMatrix;

/// A block of one node's Lagrangian Hessian, by the variables it couples (row, column).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Block {
    /// d^2/dq dq, lower triangle: cost (w_q, box penalty) and dynamics.
    PositionPosition,
    /// d^2/dv dq, full: dynamics.
    VelocityPosition,
    /// d^2/dv dv, lower triangle: cost (w_v, diagonal) and dynamics.
    VelocityVelocity,
    /// d^2/da dq, full: dynamics.
    AccelerationPosition,
    /// d^2/da dv, full: dynamics with transmission losses.
    AccelerationVelocity,
    /// d^2/da da, lower triangle: dynamics with transmission losses.
    AccelerationAcceleration,
    /// d^2/du dq, full: the rows G(q)^T u and G(q)^-T u of a pose-dependent transmission.
    ControlPosition,
    /// d^2/du dv, full: terms added from outside the core.
    ControlVelocity,
    /// d^2/du da, full: terms added from outside the core.
    ControlAcceleration,
    /// d^2/du du: cost (w_u) on the diagonal, the lower triangle with added terms.
    ControlControl,
}

/// One stored entry of a node's Hessian: its block and (row, column) within the block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Entry {
    block: Block,
    i: usize,
    j: usize,
}

impl Entry {
    /// The entry's (row, column) among all variables at node k.
    fn position(&self, layout: &Layout, k: usize) -> (usize, usize) {
        let Entry { block, i, j } = *self;
        match block {
            Block::PositionPosition => (layout.q(k, i), layout.q(k, j)),
            Block::VelocityPosition => (layout.v(k, i), layout.q(k, j)),
            Block::VelocityVelocity => (layout.v(k, i), layout.v(k, j)),
            Block::AccelerationPosition => (layout.a(k, i), layout.q(k, j)),
            Block::AccelerationVelocity => (layout.a(k, i), layout.v(k, j)),
            Block::AccelerationAcceleration => (layout.a(k, i), layout.a(k, j)),
            Block::ControlPosition => (layout.u(k, i), layout.q(k, j)),
            Block::ControlVelocity => (layout.u(k, i), layout.v(k, j)),
            Block::ControlAcceleration => (layout.u(k, i), layout.a(k, j)),
            Block::ControlControl => (layout.u(k, i), layout.u(k, j)),
        }
    }

    /// The entry's (row, column) within the node's variables [q, v, a, u] (4n).
    fn in_node(&self, n: usize) -> (usize, usize) {
        let Entry { block, i, j } = *self;
        let (row, column) = match block {
            Block::PositionPosition => (0, 0),
            Block::VelocityPosition => (n, 0),
            Block::VelocityVelocity => (n, n),
            Block::AccelerationPosition => (2 * n, 0),
            Block::AccelerationVelocity => (2 * n, n),
            Block::AccelerationAcceleration => (2 * n, 2 * n),
            Block::ControlPosition => (3 * n, 0),
            Block::ControlVelocity => (3 * n, n),
            Block::ControlAcceleration => (3 * n, 2 * n),
            Block::ControlControl => (3 * n, 3 * n),
        };
        (row + i, column + j)
    }
}

/// The stored entries of one node's Hessian (n joints), row by row of its lower triangle; the
/// a rows over v and a only with transmission `losses`, the u rows over q only where the
/// transmission depends on the `pose`; with `full` (terms added from outside the core), every
/// entry of the lower triangle.
pub(super) fn node_entries(n: usize, losses: bool, pose: bool, full: bool) -> Vec<Entry> {
    let (losses, pose) = (losses || full, pose || full);
    let mut entries = Vec::new();
    let mut push = |block, i, j| entries.push(Entry { block, i, j });
    for i in 0..n {
        (0..=i).for_each(|j| push(Block::PositionPosition, i, j));
    }
    for i in 0..n {
        (0..n).for_each(|j| push(Block::VelocityPosition, i, j));
        (0..=i).for_each(|j| push(Block::VelocityVelocity, i, j));
    }
    for i in 0..n {
        (0..n).for_each(|j| push(Block::AccelerationPosition, i, j));
        if losses {
            (0..n).for_each(|j| push(Block::AccelerationVelocity, i, j));
            (0..=i).for_each(|j| push(Block::AccelerationAcceleration, i, j));
        }
    }
    for i in 0..n {
        if pose {
            (0..n).for_each(|j| push(Block::ControlPosition, i, j));
        }
        if full {
            (0..n).for_each(|j| push(Block::ControlVelocity, i, j));
            (0..n).for_each(|j| push(Block::ControlAcceleration, i, j));
            (0..i).for_each(|j| push(Block::ControlControl, i, j));
        }
        push(Block::ControlControl, i, i);
    }
    entries
}

/// The Hessian's structure: every node's `entries`, node by node.
pub(super) fn pattern(layout: &Layout, entries: &[Entry]) -> Vec<(usize, usize)> {
    (0..layout.steps)
        .flat_map(|k| entries.iter().map(move |entry| entry.position(layout, k)))
        .collect()
}

/// What a node's Hessian sums, of one formulation: its setting, its constraint families and the
/// terms added from outside the core.
pub(super) struct Parts<'p> {
    pub(super) setting: &'p Setting,
    /// The design's dynamics (with the parts the links carry at r).
    pub(super) dynamics: &'p Dynamics,
    /// Each interval's step h_k at the point evaluated, s.
    pub(super) steps_s: Vec<f64>,
    pub(super) families: &'p Families,
    pub(super) added: &'p AddedTerms,
}

/// A node's variables: (q_k, v_k, a_k) and u_k.
pub(super) type NodeVariables<'x> = ((&'x [f64], &'x [f64], &'x [f64]), &'x [f64]);

/// The blocks of one node's Hessian, evaluated: the cost's and the constraint rows'.
#[derive(Clone, Debug)]
pub(super) struct NodeHessian {
    /// The sum over the node's rows of lambda . their Hessian in (q, v, a), 3n x 3n.
    dynamics: DMatrix<f64>,
    /// The same sum's u-q block, n x n (row = control, column = joint).
    mixed: DMatrix<f64>,
    /// Scratch of one family's terms, 3n x 3n.
    scratch: DMatrix<f64>,
    /// The cost's q-q block, n x n.
    cost_position: DMatrix<f64>,
    /// The cost's v-v diagonal and u-u diagonal (per control).
    cost_velocity: f64,
    cost_control: Vec<f64>,
    /// The TCP's Hessians, scratch of the cost's q-q block.
    tcp_hessians: [DMatrix<f64>; 3],
    /// The added constraints' terms (under their multipliers) and the added cost terms', over
    /// the node's [q, v, a, u], 4n x 4n; None without added terms.
    added: Option<(DMatrix<f64>, DMatrix<f64>)>,
}

impl NodeHessian {
    /// Room for the blocks of a node of n joints.
    pub(super) fn zeros(n: usize) -> NodeHessian {
        NodeHessian {
            dynamics: DMatrix::zeros(3 * n, 3 * n),
            mixed: DMatrix::zeros(n, n),
            scratch: DMatrix::zeros(3 * n, 3 * n),
            cost_position: DMatrix::zeros(n, n),
            cost_velocity: 0.0,
            cost_control: vec![0.0; n],
            tcp_hessians: [
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
            ],
            added: None,
        }
    }

    /// Evaluates the blocks of `parts` at node k's (q, v, a), with the node's evaluation
    /// `node`, the design's `actuation` and every row's multiplier `lambda`.
    pub(super) fn evaluate(
        &mut self,
        (parts, k, data): (&Parts<'_>, usize, &mut Workspace),
        cost: &Cost<'_>,
        ((q, v, a), u): NodeVariables<'_>,
        (node, actuation): (&NodeEval, &Actuation),
        lambda: &[f64],
    ) {
        let (layout, dynamics) = (parts.setting.layout(), parts.dynamics);
        self.dynamics.fill(0.0);
        self.mixed.fill(0.0);
        for (id, family) in parts.families {
            let Some(rows) = layout.rows_at(*id, k) else {
                continue;
            };
            let terms = NodeSecondOrder {
                k,
                dynamics,
                node,
                actuation,
                data: &mut *data,
                state: (q, v, a),
                multipliers: &lambda[rows],
                scratch: &mut self.scratch,
            };
            family.hessian(terms, (&mut self.dynamics, &mut self.mixed));
        }
        cost.position_hessian(
            (dynamics, data),
            q,
            node,
            &mut self.tcp_hessians,
            &mut self.cost_position,
        );
        self.cost_velocity = cost.velocity_hessian();
        for (i, value) in self.cost_control.iter_mut().enumerate() {
            *value = cost.control_hessian(i);
        }
        if !parts.added.is_empty() {
            let mut node = NodeContext {
                k,
                steps: layout.steps,
                step_s: parts.steps_s[k],
                q,
                v,
                a,
                u,
                dynamics,
                workspace: data,
            };
            self.added = Some(added_terms((layout, parts.added), &mut node, lambda));
        }
    }

    /// The cost's part of `entry` (the added terms' aside).
    fn cost(&self, entry: &Entry) -> f64 {
        let Entry { block, i, j } = *entry;
        match block {
            Block::PositionPosition => self.cost_position[(i, j)],
            Block::VelocityVelocity if i == j => self.cost_velocity,
            Block::VelocityPosition
            | Block::VelocityVelocity
            | Block::AccelerationPosition
            | Block::AccelerationVelocity
            | Block::AccelerationAcceleration
            | Block::ControlPosition
            | Block::ControlVelocity
            | Block::ControlAcceleration => 0.0,
            Block::ControlControl if i == j => self.cost_control[i],
            Block::ControlControl => 0.0,
        }
    }

    /// The constraint rows' part of `entry` (none is quadratic in u).
    fn dynamics(&self, entry: &Entry) -> f64 {
        let Entry { block, i, j } = *entry;
        let n = self.cost_position.nrows();
        match block {
            Block::PositionPosition => self.dynamics[(i, j)],
            Block::VelocityPosition => self.dynamics[(n + i, j)],
            Block::VelocityVelocity => self.dynamics[(n + i, n + j)],
            Block::AccelerationPosition => self.dynamics[(2 * n + i, j)],
            Block::AccelerationVelocity => self.dynamics[(2 * n + i, n + j)],
            Block::AccelerationAcceleration => self.dynamics[(2 * n + i, 2 * n + j)],
            Block::ControlPosition => self.mixed[(i, j)],
            Block::ControlVelocity | Block::ControlAcceleration | Block::ControlControl => 0.0,
        }
    }

    /// Writes the Lagrangian's value of each of `entries`, obj_factor * cost + dynamics, into
    /// `values` in order.
    pub(super) fn write(&self, entries: &[Entry], obj_factor: f64, values: &mut [f64]) {
        let n = self.cost_position.nrows();
        for (value, entry) in values.iter_mut().zip(entries) {
            *value = obj_factor * self.cost(entry) + self.dynamics(entry);
            if let Some((rows, cost)) = &self.added {
                let at = entry.in_node(n);
                *value += obj_factor * cost[at] + rows[at];
            }
        }
    }
}

/// The added constraints' terms at `node` under their multipliers in `lambda`, and the added
/// cost terms', 4n x 4n each (lower triangles).
fn added_terms(
    (layout, added): (&Layout, &AddedTerms),
    node: &mut NodeContext<'_>,
    lambda: &[f64],
) -> (DMatrix<f64>, DMatrix<f64>) {
    let size = 4 * layout.dof;
    let (mut rows, mut cost) = (DMatrix::zeros(size, size), DMatrix::zeros(size, size));
    for (i, constraint) in added.constraints.iter().enumerate() {
        if let Some(row) = layout.first_row(added::block(i), node.k) {
            constraint.hessian(node, &lambda[row..row + constraint.rows()], &mut rows);
        }
    }
    for term in &added.costs {
        term.hessian(node, &mut cost);
    }
    (rows, cost)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::ProblemKind;

    /// The entries run row by row through a node's lower triangle: q and v rows up to the
    /// diagonal, a rows over q, the u diagonal (the order IPOPT has always been given).
    #[test]
    fn node_entries_run_row_by_row_through_the_lower_triangle() {
        let n = 4;
        let layout = Layout::new(n, 3, &[], ProblemKind::Hard, &[]);
        let base = layout.q(1, 0);
        let mut expected = Vec::new();
        for i in 0..2 * n {
            expected.extend((0..=i).map(|j| (base + i, base + j)));
        }
        for i in 2 * n..3 * n {
            expected.extend((0..n).map(|j| (base + i, base + j)));
        }
        expected.extend((3 * n..4 * n).map(|i| (base + i, base + i)));
        let entries: Vec<_> = node_entries(n, false, false, false)
            .iter()
            .map(|entry| entry.position(&layout, 1))
            .collect();
        assert_eq!(entries, expected);
    }
}
