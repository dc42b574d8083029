//! Where, turning one joint at a time within its limits, a linkage's loop opens or closes again
//! and where its ratio to that joint changes sign (a dead point): the joint angles `check`
//! names, found on a grid and refined by bisection.

use super::{Linkage, Variables};
use crate::dynamics::{Dynamics, Workspace};
use std::f64::consts::PI;

/// Poses of the grid along each joint's range.
const SAMPLES: usize = 1001;

/// Bisections of a grid step: 2.6 rad / 1000 / 2^40, far below any angle worth naming.
const BISECTIONS: usize = 40;

/// What changes at a [`Crossing`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// The loop stops closing as the joint's angle grows.
    Opens,
    /// The loop closes again as the joint's angle grows.
    Closes,
    /// The ratio dq_u/dq of the joint changes sign: a dead point.
    RatioSign,
}

/// A joint angle at which a linkage's geometry changes, the other joints where the sweep held
/// them.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// The joint turned (index in the chain).
    pub joint: usize,
    /// What changes there.
    pub change: Change,
    /// The joint's angle, rad (m for a prismatic joint).
    pub angle: f64,
}

impl Crossing {
    /// In words, the joint named by `names` (the chain's joint names), its angle to 1e-4.
    pub fn text(&self, names: &[String]) -> String {
        // Rounded first, so that -1e-12 is written 0.0000 (-0 + 0 is 0).
        let angle = (self.angle * 1e4).round() / 1e4 + 0.0;
        let (joint, angle) = (&names[self.joint], format!("{angle:.4}"));
        match self.change {
            Change::Opens => format!("its loop opens at {joint} = {angle}"),
            Change::Closes => format!("its loop closes again at {joint} = {angle}"),
            Change::RatioSign => format!(
                "its ratio to joint {joint} changes sign at {joint} = {angle} (a dead point)"
            ),
        }
    }
}

/// A reading along the sweep: the ratio to the joint turned, None where the loop is open.
type Reading = Option<f64>;

impl Linkage {
    /// Turns each joint the linkage spans over its limits (a joint without finite limits: one
    /// turn), the other joints at `pose`, at design `r`, and returns where the loop opens or
    /// closes again and where the ratio to that joint changes sign, in the order found.
    pub fn sweep(&self, dynamics: &Dynamics, r: &[f64], pose: &[f64]) -> Vec<Crossing> {
        let mut data = dynamics.workspace();
        let limits = dynamics.robot().position_limits();
        let mut crossings = Vec::new();
        for joint in self.joints() {
            let (low, high) = match limits[joint] {
                (low, high) if low.is_finite() && high.is_finite() => (low, high),
                _ => (-PI, PI),
            };
            let mut q = pose.to_vec();
            let mut read = |angle: f64| {
                q[joint] = angle;
                self.ratio_to(dynamics, &mut data, (&q, r), joint)
            };
            let step = (high - low) / (SAMPLES - 1) as f64;
            let mut before = (low, read(low));
            for k in 1..SAMPLES {
                let angle = low + step * k as f64;
                let after = (angle, read(angle));
                if let Some(change) = change(before.1, after.1) {
                    let angle = bisect(&mut read, (before, after), change);
                    crossings.push(Crossing {
                        joint,
                        change,
                        angle,
                    });
                }
                before = after;
            }
        }
        crossings
    }

    /// The ratio dq_u/dq_joint at pose `q` and design `r`, None where the loop is open.
    fn ratio_to(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
        joint: usize,
    ) -> Reading {
        let variables = Variables {
            joints: self.joints(),
            parameters: Vec::new(),
        };
        let shape = variables.shape(1);
        let angle = self
            .angle(dynamics, data, (q, r), &variables, &shape)
            .ok()?;
        Some(angle.derivative(&[joint - variables.joints.start]))
    }
}

/// What changes from reading `before` to reading `after`, if anything.
fn change(before: Reading, after: Reading) -> Option<Change> {
    match (before, after) {
        (Some(_), None) => Some(Change::Opens),
        (None, Some(_)) => Some(Change::Closes),
        (Some(a), Some(b)) if a * b < 0.0 => Some(Change::RatioSign),
        _ => None,
    }
}

/// The angle between the two readings where `what` happens, to [`BISECTIONS`] halvings.
fn bisect(
    read: &mut impl FnMut(f64) -> Reading,
    ((mut low, mut below), (mut high, _)): ((f64, Reading), (f64, Reading)),
    what: Change,
) -> f64 {
    for _ in 0..BISECTIONS {
        let middle = 0.5 * (low + high);
        let reading = read(middle);
        if change(below, reading) == Some(what) {
            high = middle;
        } else {
            (low, below) = (middle, reading);
        }
    }
    0.5 * (low + high)
}
