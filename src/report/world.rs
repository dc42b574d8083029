//! What a solve's plots and its poses share: the title of a design's plots and the world axes
//! of the TCP's path.

use codesign_core::model::task::{SoftInterval, Task};
use codesign_core::problem::Formulation;
use codesign_core::solve::{Trajectory, TrajectoryResult};

/// What every plot of a solve is of: the space, the design and the payload; for an infeasible
/// design, `INFEASIBLE` and why after them, so that no plot of it passes for a feasible one.
pub(crate) fn plot_title(formulation: &Formulation, result: &TrajectoryResult) -> String {
    let ratios: Vec<String> = result.ratios.iter().map(|r| format!("{r:.3}")).collect();
    let design = format!(
        "{} space, r = ({}), payload {} kg",
        formulation.space(),
        ratios.join(", "),
        formulation.task().payload.mass_kg
    );
    match (result.feasible, &result.reason) {
        (true, _) => design,
        (false, Some(reason)) => format!("{design}; INFEASIBLE: {reason}"),
        (false, None) => format!("{design}; INFEASIBLE"),
    }
}

/// An axis of the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorldAxis {
    /// World x.
    X,
    /// World y.
    Y,
    /// World z.
    Z,
}

impl WorldAxis {
    /// The axis' index in a world vector: 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            WorldAxis::X => 0,
            WorldAxis::Y => 1,
            WorldAxis::Z => 2,
        }
    }

    /// The axis' name, `x`, `y` or `z`.
    pub fn name(self) -> &'static str {
        match self {
            WorldAxis::X => "x",
            WorldAxis::Y => "y",
            WorldAxis::Z => "z",
        }
    }

    /// The trajectory's TCP coordinates along the axis, m (x is empty in files written before
    /// it was recorded).
    pub(super) fn of(self, t: &Trajectory) -> &[f64] {
        match self {
            WorldAxis::X => &t.tcp_x,
            WorldAxis::Y => &t.tcp_y,
            WorldAxis::Z => &t.tcp_z,
        }
    }

    /// The task's Cartesian box along the axis, when it has one.
    pub(super) fn interval(self, task: &Task) -> Option<&SoftInterval> {
        let b = &task.cartesian_box;
        match self {
            WorldAxis::X => b.x.as_ref(),
            WorldAxis::Y => b.y.as_ref(),
            WorldAxis::Z => b.z.as_ref(),
        }
    }
}

/// The world plane the TCP's path moves most in, as (horizontal, vertical) axes of its plot:
/// the two axes over which the path extends furthest (max - min), in x, y, z order; of axes
/// that extend equally, x is left out first, then y. A path in the world's y-z plane (the
/// built-in arm's) gives (y, z).
pub fn path_plane(t: &Trajectory) -> (WorldAxis, WorldAxis) {
    let extent = |axis: WorldAxis| {
        let (lo, hi) = axis
            .of(t)
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        if hi >= lo {
            hi - lo
        } else {
            0.0
        }
    };
    let (x, y, z) = (
        extent(WorldAxis::X),
        extent(WorldAxis::Y),
        extent(WorldAxis::Z),
    );
    if x <= y && x <= z {
        (WorldAxis::Y, WorldAxis::Z)
    } else if y <= z {
        (WorldAxis::X, WorldAxis::Z)
    } else {
        (WorldAxis::X, WorldAxis::Y)
    }
}
