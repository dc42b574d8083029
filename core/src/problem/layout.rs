//! Where each variable and constraint of the trajectory NLP lives.
//!
//! Variables are grouped by node for a banded structure: node k < N holds
//! `[q_k, v_k, a_k, u_k]` (4n numbers), the last node N holds `[q_N, v_N]`. Constraint rows are
//! grouped the same way: node k < N holds the row blocks of the formulation's constraint
//! families (`families/`, each block keyed by its family's [`BlockId`]) in the families' order, each present at every node k < N, only at
//! the inner nodes 0 < k < N (where v is free), or at the nodes it lists ([`Nodes`]). The layout knows the blocks' sizes, not what
//! their rows mean: that is each family's own file.
//!
//! Problem-wide variables ([`WideVariable`]: the free horizon T, the times of the via points
//! with a window) follow the node blocks, in the order given.
//!
//! The elastic kind (docs/model.md, section 14) appends its slack columns after the
//! trajectory's: for each relaxed block in the families' order, for each node where it is
//! present, a pair `[+, -]` per row (2 columns per row). Today the dynamics rows (the torque
//! deficits s+, s-) and the motor speed rows (the speed excesses e+, e-) are relaxed.

use super::kind::ProblemKind;
use std::sync::Arc;

/// The key of a row block: the position of its family in the families' order
/// (`FamilyId as usize`, which converts into it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BlockId(pub usize);

/// A variable of the whole problem, beside the node blocks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WideVariable {
    /// The duration T of a free horizon, s (the step is h = T/N on an unphased grid).
    Horizon,
    /// The time t_v of the via point at this position in `motion.via`, s, within its window.
    ViaTime(usize),
}

/// The nodes k < N where a row block has its rows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Nodes {
    /// Every node k < N.
    Every,
    /// The inner nodes 0 < k < N (where v is free).
    Inner,
    /// The nodes listed, ascending and each once (a via point's node).
    Listed(Arc<[usize]>),
}

/// The rows one constraint family holds at a node.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RowBlock {
    /// Rows per node where the block is present.
    pub per_node: usize,
    /// The nodes where it is present.
    pub nodes: Nodes,
    /// Relaxed by a slack pair per row in the elastic kind.
    pub relaxed: bool,
}

impl RowBlock {
    /// Whether the block has rows at node k of a problem with `steps` intervals.
    fn present(&self, k: usize, steps: usize) -> bool {
        k < steps
            && match &self.nodes {
                Nodes::Every => true,
                Nodes::Inner => k > 0,
                Nodes::Listed(nodes) => nodes.binary_search(&k).is_ok(),
            }
    }

    /// The position of node k among the nodes where the block is present.
    fn ordinal(&self, k: usize) -> usize {
        match &self.nodes {
            Nodes::Every => k,
            Nodes::Inner => k - 1,
            Nodes::Listed(nodes) => nodes.partition_point(|&node| node < k),
        }
    }

    /// Number of nodes where the block is present.
    fn nodes(&self, steps: usize) -> usize {
        match &self.nodes {
            Nodes::Every => steps,
            Nodes::Inner => steps.saturating_sub(1),
            Nodes::Listed(nodes) => nodes.iter().filter(|&&k| k < steps).count(),
        }
    }
}

/// Index arithmetic of one problem shape (dof n, steps N, the families' row blocks, the kind).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Degrees of freedom n.
    pub dof: usize,
    /// Number of intervals N.
    pub steps: usize,
    /// Hard or elastic: whether the slack columns exist.
    pub kind: ProblemKind,
    /// Each block's rows by key, None where a family has no rows.
    blocks: Vec<Option<RowBlock>>,
    /// The number of rows before each node k <= N (the last: the number of rows).
    row_base: Vec<usize>,
    /// Each block's first row at each node k < N (node-major, `blocks.len()` per node).
    offsets: Vec<Option<usize>>,
    /// Each relaxed block's first slack column (elastic kind).
    slack_base: Vec<Option<usize>>,
    /// The problem-wide variables, in the order of their columns after the node blocks.
    wide: Vec<WideVariable>,
    variables: usize,
}

impl Layout {
    /// The layout of a problem of `kind` with `dof` joints, `steps` intervals, the row blocks
    /// `blocks`, given in the families' order, and the problem-wide variables `wide`.
    pub fn new(
        dof: usize,
        steps: usize,
        blocks: &[(BlockId, RowBlock)],
        kind: ProblemKind,
        wide: &[WideVariable],
    ) -> Layout {
        let keys = blocks.iter().map(|(id, _)| id.0 + 1).max().unwrap_or(0);
        let mut by_key = vec![None; keys];
        for (id, block) in blocks {
            by_key[id.0] = Some(block.clone());
        }
        let mut row_base = Vec::with_capacity(steps + 1);
        let mut offsets = vec![None; keys * steps];
        let mut row = 0;
        for k in 0..steps {
            row_base.push(row);
            for (id, block) in blocks {
                if block.present(k, steps) {
                    offsets[k * keys + id.0] = Some(row);
                    row += block.per_node;
                }
            }
        }
        row_base.push(row);
        let mut slack_base = vec![None; keys];
        let mut column = 4 * dof * steps + 2 * dof + wide.len();
        if kind == ProblemKind::Elastic {
            for (id, block) in blocks.iter().filter(|(_, block)| block.relaxed) {
                slack_base[id.0] = Some(column);
                column += 2 * block.per_node * block.nodes(steps);
            }
        }
        Layout {
            dof,
            steps,
            kind,
            blocks: by_key,
            row_base,
            offsets,
            slack_base,
            wide: wide.to_vec(),
            variables: column,
        }
    }

    /// The row block of key `id`, None where its family has no rows.
    pub fn block(&self, id: impl Into<BlockId>) -> Option<RowBlock> {
        self.blocks.get(id.into().0).cloned().flatten()
    }

    /// Number of variables: 4nN + 2n, the problem-wide ones, and the slacks of the elastic kind.
    pub fn num_variables(&self) -> usize {
        self.variables
    }

    /// Number of the trajectory's own variables (all but the slacks): 4nN + 2n.
    fn trajectory_variables(&self) -> usize {
        4 * self.dof * self.steps + 2 * self.dof
    }

    /// The slack columns (empty in the hard kind).
    pub fn slacks(&self) -> std::ops::Range<usize> {
        self.trajectory_variables() + self.wide.len()..self.num_variables()
    }

    /// The column of the problem-wide variable `variable`, where the problem has it.
    pub fn wide(&self, variable: WideVariable) -> Option<usize> {
        let position = self.wide.iter().position(|&v| v == variable)?;
        Some(self.trajectory_variables() + position)
    }

    /// Whether the problem has problem-wide variables (the rows that read them read the point).
    pub fn has_wide(&self) -> bool {
        !self.wide.is_empty()
    }

    /// The column of the free horizon T, where the horizon is free.
    pub fn horizon(&self) -> Option<usize> {
        self.wide(WideVariable::Horizon)
    }

    /// Number of constraint rows.
    pub fn num_constraints(&self) -> usize {
        self.row_base[self.steps]
    }

    /// The first row of block `id` at node k, where it has one.
    pub fn first_row(&self, id: impl Into<BlockId>, k: usize) -> Option<usize> {
        let (keys, id) = (self.blocks.len(), id.into().0);
        if k >= self.steps || id >= keys {
            return None;
        }
        self.offsets[k * keys + id]
    }

    /// The rows of block `id` at node k, where it has any.
    pub fn rows_at(&self, id: impl Into<BlockId>, k: usize) -> Option<std::ops::Range<usize>> {
        let id = id.into();
        let first = self.first_row(id, k)?;
        Some(first..first + self.blocks[id.0].as_ref()?.per_node)
    }

    /// Row j of block `id` at node k, where it has one.
    pub fn row(&self, id: impl Into<BlockId>, k: usize, j: usize) -> Option<usize> {
        self.first_row(id, k).map(|row| row + j)
    }

    /// Columns [+, -] of the slack pair of row j of block `id` at node k, in the elastic kind
    /// where the block is relaxed.
    pub fn slack(&self, id: impl Into<BlockId>, k: usize, j: usize) -> Option<[usize; 2]> {
        let id = id.into();
        let block = self.block(id)?;
        let base = self.slack_base[id.0]?;
        block.present(k, self.steps).then(|| {
            let start = base + 2 * block.per_node * block.ordinal(k);
            [start + j, start + block.per_node + j]
        })
    }

    fn node(&self, k: usize) -> usize {
        4 * self.dof * k
    }

    /// Column of q_k[i], k in 0..=N.
    pub fn q(&self, k: usize, i: usize) -> usize {
        self.node(k) + i
    }

    /// Column of v_k[i], k in 0..=N.
    pub fn v(&self, k: usize, i: usize) -> usize {
        self.node(k) + self.dof + i
    }

    /// Column of a_k[i], k in 0..N.
    pub fn a(&self, k: usize, i: usize) -> usize {
        self.node(k) + 2 * self.dof + i
    }

    /// Column of u_k[i], k in 0..N.
    pub fn u(&self, k: usize, i: usize) -> usize {
        self.node(k) + 3 * self.dof + i
    }

    /// (q_k, v_k, a_k) within the primal point x, k in 0..N.
    pub fn node_state<'x>(&self, x: &'x [f64], k: usize) -> (&'x [f64], &'x [f64], &'x [f64]) {
        let n = self.dof;
        (
            &x[self.q(k, 0)..self.q(k, 0) + n],
            &x[self.v(k, 0)..self.v(k, 0) + n],
            &x[self.a(k, 0)..self.a(k, 0) + n],
        )
    }

    /// The controls u_k within the primal point x, k in 0..N.
    pub fn controls<'x>(&self, x: &'x [f64], k: usize) -> &'x [f64] {
        &x[self.u(k, 0)..self.u(k, 0) + self.dof]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::FamilyId;

    /// Every variable and row index is used exactly once, whichever blocks are present and
    /// relaxed, in both kinds.
    #[test]
    fn indices_cover_without_overlap() {
        let n = 3;
        let all = [
            (FamilyId::Dynamics, n, false, true),
            (FamilyId::Integration, 2 * n, false, false),
            (FamilyId::MotorSpeed, n, true, true),
            (FamilyId::MotorTorque, n, false, false),
            (FamilyId::Envelope, 2 * n, true, false),
        ];
        for mask in 0..(1 << all.len()) {
            let blocks: Vec<(BlockId, RowBlock)> = all
                .iter()
                .enumerate()
                .filter(|(b, _)| mask & (1 << b) != 0)
                .map(|(_, &(family, per_node, inner_only, relaxed))| {
                    let block = RowBlock {
                        per_node,
                        nodes: if inner_only {
                            Nodes::Inner
                        } else {
                            Nodes::Every
                        },
                        relaxed,
                    };
                    (family.into(), block)
                })
                .collect();
            for kind in [ProblemKind::Hard, ProblemKind::Elastic] {
                let layout = Layout::new(n, 5, &blocks, kind, &[]);
                let mut columns = vec![0; layout.num_variables()];
                let mut rows = vec![0; layout.num_constraints()];
                for k in 0..=layout.steps {
                    for i in 0..n {
                        columns[layout.q(k, i)] += 1;
                        columns[layout.v(k, i)] += 1;
                        if k < layout.steps {
                            columns[layout.a(k, i)] += 1;
                            columns[layout.u(k, i)] += 1;
                        }
                    }
                    for (family, block) in &blocks {
                        let family = *family;
                        for j in 0..block.per_node {
                            layout
                                .row(family, k, j)
                                .into_iter()
                                .for_each(|r| rows[r] += 1);
                            let slack = layout.slack(family, k, j);
                            slack.into_iter().flatten().for_each(|c| columns[c] += 1);
                        }
                    }
                }
                assert!(columns.iter().all(|&c| c == 1), "{kind:?} {columns:?}");
                let relaxed = blocks.iter().any(|(_, block)| block.relaxed);
                let elastic = kind == ProblemKind::Elastic;
                assert_eq!(layout.slacks().is_empty(), !(elastic && relaxed));
                assert!(rows.iter().all(|&c| c == 1), "{blocks:?}: {rows:?}");
            }
        }
    }

    /// The blocks of the hard problem of the paper's modes in actuation space sit as they
    /// always have: per node the dynamics rows, then the integration rows.
    #[test]
    fn dynamics_then_integration_rows_per_node() {
        let blocks = [
            (
                FamilyId::Dynamics.into(),
                RowBlock {
                    per_node: 4,
                    nodes: Nodes::Every,
                    relaxed: true,
                },
            ),
            (
                FamilyId::Integration.into(),
                RowBlock {
                    per_node: 8,
                    nodes: Nodes::Every,
                    relaxed: false,
                },
            ),
        ];
        let layout = Layout::new(4, 3, &blocks, ProblemKind::Hard, &[]);
        assert_eq!(layout.row(FamilyId::Dynamics, 1, 2), Some(14));
        assert_eq!(layout.row(FamilyId::Integration, 1, 0), Some(16));
        assert_eq!(layout.num_constraints(), 36);
        assert_eq!(layout.slack(FamilyId::Dynamics, 1, 2), None);
    }
}
