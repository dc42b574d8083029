//! Where each variable and constraint of the trajectory NLP lives.
//!
//! Variables are grouped by node for a banded structure: node k < N holds
//! `[q_k, v_k, a_k, u_k]` (4n numbers), the last node N holds `[q_N, v_N]`. Constraint rows are
//! grouped the same way: node k < N holds the inverse dynamics (n rows), the velocity and position
//! integration (n rows each), then, when the problem has them, the linear limit rows: the motor
//! speed rows (nodes 1..N-1, where v is free), the motor torque rows (joint space, nodes 0..N-1)
//! and the torque-speed envelope's rows P then M, n each (nodes 1..N-1: at node 0, where v_0 = 0,
//! they are the torque limit).
//!
//! The elastic kind (docs/model.md, section 14) appends its slack columns after all of these:
//! the torque deficits `[s+_k, s-_k]` of every node k < N (2n each), then the speed excesses
//! `[e+_k, e-_k]` of every speed-row node 0 < k < N (2n each). Its rows are the hard kind's,
//! except that it always has speed rows (in modes `paper` and `interval` they replace the box
//! bounds on v, so that the slacks can relax them).

use super::ProblemKind;
use crate::transmission::Side;

/// Which linear limit rows a problem has beside its dynamics and integration rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinearRows {
    /// Motor speeds (or, in the elastic kind's box modes, joint speeds) as rows, nodes 0 < k < N.
    pub speed: bool,
    /// Motor torques G^-T u_k as rows (joint space, torque mode `exact`), nodes k < N.
    pub torque: bool,
    /// The torque-speed envelope's rows P and M (the task's `motors.no_load_speed_rad_s`), nodes
    /// 0 < k < N.
    pub envelope: bool,
}

/// Index arithmetic of one problem shape (dof n, steps N, which linear limits exist).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Degrees of freedom n.
    pub dof: usize,
    /// Number of intervals N.
    pub steps: usize,
    /// Whether motor speeds are limited by linear rows |G v_k| <= w (speed mode `exact`).
    pub speed_rows: bool,
    /// Whether motor torques are limited by linear rows |G^-T u_k| <= tau (joint space, `exact`).
    pub torque_rows: bool,
    /// Whether the motors' torque-speed envelope is held by linear rows.
    pub envelope_rows: bool,
    /// Hard or elastic: whether the slack columns exist.
    pub kind: ProblemKind,
    row_base: Vec<usize>,
}

impl Layout {
    /// The layout of a problem of `kind` with `dof` joints, `steps` intervals and the linear
    /// limit rows `rows`.
    pub fn new(dof: usize, steps: usize, rows: LinearRows, kind: ProblemKind) -> Layout {
        let mut row_base = Vec::with_capacity(steps + 1);
        let mut row = 0;
        for k in 0..steps {
            row_base.push(row);
            row += 3 * dof;
            if rows.speed && k > 0 {
                row += dof;
            }
            if rows.torque {
                row += dof;
            }
            if rows.envelope && k > 0 {
                row += 2 * dof;
            }
        }
        row_base.push(row);
        Layout {
            dof,
            steps,
            speed_rows: rows.speed,
            torque_rows: rows.torque,
            envelope_rows: rows.envelope,
            kind,
            row_base,
        }
    }

    /// Which linear limit rows the layout has.
    pub fn rows(&self) -> LinearRows {
        LinearRows {
            speed: self.speed_rows,
            torque: self.torque_rows,
            envelope: self.envelope_rows,
        }
    }

    /// Number of variables: 4nN + 2n, plus the slacks of the elastic kind.
    pub fn num_variables(&self) -> usize {
        self.trajectory_variables() + self.deficit_slacks() + self.excess_slacks()
    }

    /// Number of the trajectory's own variables (all but the slacks): 4nN + 2n.
    fn trajectory_variables(&self) -> usize {
        4 * self.dof * self.steps + 2 * self.dof
    }

    /// Number of torque-deficit slacks: 2nN in the elastic kind.
    fn deficit_slacks(&self) -> usize {
        match self.kind {
            ProblemKind::Hard => 0,
            ProblemKind::Elastic => 2 * self.dof * self.steps,
        }
    }

    /// Number of speed-excess slacks: 2n(N-1) in the elastic kind with speed rows.
    fn excess_slacks(&self) -> usize {
        match self.kind {
            ProblemKind::Elastic if self.speed_rows => 2 * self.dof * (self.steps - 1),
            _ => 0,
        }
    }

    /// Columns [s+, s-] of the torque-deficit slacks of the dynamics row (k, i), k in 0..N, in
    /// the elastic kind.
    pub fn deficit_slack(&self, k: usize, i: usize) -> Option<[usize; 2]> {
        let base = self.trajectory_variables() + 2 * self.dof * k;
        (self.kind == ProblemKind::Elastic && k < self.steps)
            .then(|| [base + i, base + self.dof + i])
    }

    /// Columns [e+, e-] of the speed-excess slacks of the speed row (k, i), 0 < k < N, in the
    /// elastic kind.
    pub fn excess_slack(&self, k: usize, i: usize) -> Option<[usize; 2]> {
        self.speed_row(k, i)?;
        (self.kind == ProblemKind::Elastic).then(|| {
            let base = self.trajectory_variables() + self.deficit_slacks() + 2 * self.dof * (k - 1);
            [base + i, base + self.dof + i]
        })
    }

    /// The slack columns (empty in the hard kind).
    pub fn slacks(&self) -> std::ops::Range<usize> {
        self.trajectory_variables()..self.num_variables()
    }

    /// Number of constraint rows.
    pub fn num_constraints(&self) -> usize {
        self.row_base[self.steps]
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

    /// Row of the inverse-dynamics residual RNEA(q_k, v_k, a_k)[i] - tau_k[i].
    pub fn dynamics_row(&self, k: usize, i: usize) -> usize {
        self.row_base[k] + i
    }

    /// Row of v_{k+1}[i] - v_k[i] - h a_k[i].
    pub fn velocity_row(&self, k: usize, i: usize) -> usize {
        self.row_base[k] + self.dof + i
    }

    /// Row of q_{k+1}[i] - q_k[i] - h v_{k+1}[i].
    pub fn position_row(&self, k: usize, i: usize) -> usize {
        self.row_base[k] + 2 * self.dof + i
    }

    /// Row of (G v_k)[i], the motor speed, when it exists (speed rows, 0 < k < N).
    pub fn speed_row(&self, k: usize, i: usize) -> Option<usize> {
        (self.speed_rows && k > 0 && k < self.steps).then(|| self.row_base[k] + 3 * self.dof + i)
    }

    /// Row of (G^-T u_k)[i], the motor torque, when it exists (torque rows, k < N).
    pub fn torque_row(&self, k: usize, i: usize) -> Option<usize> {
        let speed = if self.speed_rows && k > 0 {
            self.dof
        } else {
            0
        };
        (self.torque_rows && k < self.steps).then(|| self.row_base[k] + 3 * self.dof + speed + i)
    }

    /// Row `side` of motor i's torque-speed envelope at node k, when it exists (envelope rows,
    /// 0 < k < N): the node's P rows, then its M rows, after its other limit rows.
    pub fn envelope_row(&self, k: usize, i: usize, side: Side) -> Option<usize> {
        (self.envelope_rows && k > 0 && k < self.steps).then(|| {
            let before = usize::from(self.speed_rows) + usize::from(self.torque_rows);
            let offset = match side {
                Side::Plus => 0,
                Side::Minus => self.dof,
            };
            self.row_base[k] + (3 + before) * self.dof + offset + i
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variable and row index is used exactly once.
    #[test]
    fn indices_cover_without_overlap() {
        let flags = [false, true];
        let shapes = flags.into_iter().flat_map(|speed| {
            flags.into_iter().flat_map(move |torque| {
                flags.map(|envelope| LinearRows {
                    speed,
                    torque,
                    envelope,
                })
            })
        });
        for (shape, kind) in shapes
            .flat_map(|shape| [ProblemKind::Hard, ProblemKind::Elastic].map(|kind| (shape, kind)))
        {
            let layout = Layout::new(3, 5, shape, kind);
            assert_eq!(layout.rows(), shape);
            let mut columns = vec![0; layout.num_variables()];
            let mut rows = vec![0; layout.num_constraints()];
            for k in 0..=layout.steps {
                for i in 0..layout.dof {
                    columns[layout.q(k, i)] += 1;
                    columns[layout.v(k, i)] += 1;
                    if k < layout.steps {
                        columns[layout.a(k, i)] += 1;
                        columns[layout.u(k, i)] += 1;
                        rows[layout.dynamics_row(k, i)] += 1;
                        rows[layout.velocity_row(k, i)] += 1;
                        rows[layout.position_row(k, i)] += 1;
                    }
                    for slack in [layout.deficit_slack(k, i), layout.excess_slack(k, i)] {
                        slack.into_iter().flatten().for_each(|c| columns[c] += 1);
                    }
                    layout
                        .speed_row(k, i)
                        .into_iter()
                        .for_each(|r| rows[r] += 1);
                    layout
                        .torque_row(k, i)
                        .into_iter()
                        .for_each(|r| rows[r] += 1);
                    Side::BOTH
                        .into_iter()
                        .filter_map(|side| layout.envelope_row(k, i, side))
                        .for_each(|r| rows[r] += 1);
                }
            }
            assert!(columns.iter().all(|&c| c == 1), "{kind:?} {columns:?}");
            assert_eq!(layout.slacks().is_empty(), kind == ProblemKind::Hard);
            assert!(rows.iter().all(|&c| c == 1), "{shape:?}: {rows:?}");
            let envelope_rows = (1..layout.steps)
                .filter(|&k| layout.envelope_row(k, 0, Side::Plus).is_some())
                .count();
            assert_eq!(envelope_rows, if shape.envelope { 4 } else { 0 });
        }
    }
}
