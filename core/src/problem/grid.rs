//! [`Grid`]: the times of the nodes (docs/model.md, section 6). The grid is split into phases at
//! its boundaries: node 0 at t = 0, the via points of a phased motion at their nodes, and node N
//! at T. A boundary's time is a constant (0, a via time t_s, a fixed T) or a problem-wide
//! variable (a via's t_v within its window, a free T). In phase j, from boundary node k_j to
//! k_(j+1), every interval has the step
//!
//! ```text
//! h_k = (t_(j+1) - t_j) / (k_(j+1) - k_j),   k_j <= k < k_(j+1),
//! ```
//!
//! affine in the problem-wide variables: its first derivatives are the constants
//! +-1/(k_(j+1) - k_j) and its second derivatives 0. Without a phased via point the grid has one
//! phase, h = T/N. The node times are t_k = t_j + (k - k_j) h_k.

use super::layout::{Layout, WideVariable};
use super::targets::Boundary;
use crate::model::task::{Horizon, ViaTime};

/// The time of a phase boundary, s.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Time {
    /// A constant.
    Fixed(f64),
    /// The problem-wide variable in this column.
    Column(usize),
}

impl Time {
    /// Its value at the primal point x, s.
    fn at(self, x: &[f64]) -> f64 {
        match self {
            Time::Fixed(t) => t,
            Time::Column(column) => x[column],
        }
    }
}

/// The node times of a problem: its phase boundaries (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// (node, time) of each boundary, nodes ascending from 0 to N.
    boundaries: Vec<(usize, Time)>,
    /// The phase of each interval k < N: the index of its first boundary.
    phase: Vec<usize>,
}

impl Grid {
    /// The grid of `layout`'s problem with `horizon` and the phase boundaries `boundaries`, in
    /// time order (none where the motion is not phased).
    pub(super) fn new(layout: &Layout, horizon: Horizon, boundaries: &[Boundary]) -> Grid {
        let end = match (layout.horizon(), horizon) {
            (Some(column), _) => Time::Column(column),
            (None, horizon) => Time::Fixed(horizon.initial_s()),
        };
        let inner = boundaries.iter().map(|b| {
            let time = match (b.time, layout.wide(WideVariable::ViaTime(b.via))) {
                (ViaTime::Within(_), Some(column)) => Time::Column(column),
                (time, _) => Time::Fixed(time.span().0),
            };
            (b.node, time)
        });
        let steps = layout.steps;
        let mut all = vec![(0, Time::Fixed(0.0))];
        all.extend(inner);
        all.push((steps, end));
        let phase = (0..steps)
            .map(|k| all.partition_point(|&(node, _)| node <= k) - 1)
            .collect();
        Grid {
            boundaries: all,
            phase,
        }
    }

    /// The first and the last boundary of interval k's phase, with the phase's intervals.
    fn phase_of(&self, k: usize) -> ((usize, Time), (usize, Time), f64) {
        let j = self.phase[k];
        let (start, end) = (self.boundaries[j], self.boundaries[j + 1]);
        (start, end, (end.0 - start.0) as f64)
    }

    /// The step h_k of interval k at the primal point x, s.
    pub fn step(&self, x: &[f64], k: usize) -> f64 {
        let ((_, start), (_, end), intervals) = self.phase_of(k);
        (end.at(x) - start.at(x)) / intervals
    }

    /// The derivatives of h_k in the problem-wide variables, (column, dh_k/dcolumn): at most
    /// two, constants (h_k is affine in them).
    pub fn step_gradient(&self, k: usize) -> impl Iterator<Item = (usize, f64)> {
        let ((_, start), (_, end), intervals) = self.phase_of(k);
        let column = |time: Time, sign: f64| match time {
            Time::Column(column) => Some((column, sign / intervals)),
            Time::Fixed(_) => None,
        };
        column(start, -1.0).into_iter().chain(column(end, 1.0))
    }

    /// Each node's time t_k at the primal point x, k = 0..=N, s.
    pub fn times(&self, x: &[f64]) -> Vec<f64> {
        let steps = self.phase.len();
        let mut times = Vec::with_capacity(steps + 1);
        for k in 0..steps {
            let ((node, start), ..) = self.phase_of(k);
            times.push(start.at(x) + (k - node) as f64 * self.step(x, k));
        }
        let (_, end) = self.boundaries[self.boundaries.len() - 1];
        times.push(end.at(x));
        times
    }

    /// The duration T at the primal point x, s.
    pub fn horizon(&self, x: &[f64]) -> f64 {
        self.boundaries[self.boundaries.len() - 1].1.at(x)
    }

    /// Whether every step is the same constant (one phase between fixed times).
    pub fn is_uniform(&self) -> bool {
        self.boundaries.len() == 2 && self.step_gradient(0).next().is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::kind::ProblemKind;

    /// A window's time and a free T split 6 intervals into phases of 2, 1 and 3 intervals whose
    /// steps and node times follow the boundaries, with the derivatives of central differences.
    #[test]
    fn the_steps_follow_the_phase_boundaries_with_their_derivatives() {
        let wide = [WideVariable::Horizon, WideVariable::ViaTime(1)];
        let layout = Layout::new(1, 6, &[], ProblemKind::Hard, &wide);
        let boundaries = [
            Boundary {
                via: 0,
                node: 2,
                time: ViaTime::At(0.2),
            },
            Boundary {
                via: 1,
                node: 3,
                time: ViaTime::Within([0.25, 0.4]),
            },
        ];
        let free = Horizon::Free {
            min_s: 0.5,
            max_s: 1.0,
        };
        let grid = Grid::new(&layout, free, &boundaries);
        let (t, v) = (layout.horizon().unwrap(), layout.wide(wide[1]).unwrap());
        let mut x = vec![0.0; layout.num_variables()];
        (x[t], x[v]) = (0.9, 0.3);
        let times = grid.times(&x);
        let expected = [0.0, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9];
        for (got, want) in times.iter().zip(expected) {
            assert!((got - want).abs() < 1e-15, "{times:?}");
        }
        assert_eq!(grid.horizon(&x), 0.9);
        assert!(!grid.is_uniform());
        for k in 0..6 {
            let exact: Vec<(usize, f64)> = grid.step_gradient(k).collect();
            for column in [t, v] {
                let shifted = |by: f64| {
                    let mut y = x.clone();
                    y[column] += by;
                    grid.step(&y, k)
                };
                let central = (shifted(1e-6) - shifted(-1e-6)) / 2e-6;
                let found = exact
                    .iter()
                    .find(|(c, _)| *c == column)
                    .map_or(0.0, |e| e.1);
                assert!((central - found).abs() < 1e-8, "k {k} column {column}");
            }
        }
        let fixed = Layout::new(1, 4, &[], ProblemKind::Hard, &[]);
        let uniform = Grid::new(&fixed, Horizon::Fixed(0.8), &[]);
        assert!(uniform.is_uniform());
        assert!((uniform.times(&x[..fixed.num_variables()])[3] - 0.6).abs() < 1e-15);
    }
}
