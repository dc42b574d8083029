//! A linkage over a grid of poses within the limits of the joints it spans: where its loop
//! closes, its ratio and measure there, and the joint positions at which its loop opens or its
//! ratio changes sign (a dead point), each of which `check` names.

use super::reading;
use codesign_core::dynamics::{Dynamics, Workspace};
use codesign_core::model::Robot;
use codesign_core::text::{rounded as number, shown};
use codesign_core::transmission::linkage::{Linkage, Variables};
use serde::Serialize;
use std::f64::consts::PI;

/// Poses sampled over the joint range of a linkage, at most: a grid over the joints it spans.
const RANGE_SAMPLES: f64 = 4096.0;

/// A row's ratio below this share of its largest over the range is reported as near a dead
/// point.
const NEAR_ZERO_SHARE: f64 = 0.02;

/// The dead points a warning lists before it counts the rest.
const LISTED: usize = 4;

/// One linkage over a grid of poses within its joints' limits.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RangeReading {
    /// Poses sampled.
    pub samples: usize,
    /// Poses where the loop did not close.
    pub open: usize,
    /// Per spanned joint, the intervals of its position (rad, or m) over which the loop fails
    /// to close at some sampled pose, from one sample to another; empty where it always closes.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub open_within: Vec<Vec<[f64; 2]>>,
    /// Over the poses where it closed; None if it closed at none.
    pub closed: Option<ClosedRange>,
    /// Where the ratio to a spanned joint changes sign between two neighbouring poses of the
    /// grid.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub dead_points: Vec<DeadPoint>,
}

/// A linkage's readings over the poses where it closed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClosedRange {
    /// The smallest and largest ratio per spanned joint.
    pub ratio_min: Vec<f64>,
    /// See `ratio_min`.
    pub ratio_max: Vec<f64>,
    /// The smallest and largest length (m) or crank angle (rad).
    pub measure_range: [f64; 2],
}

/// Where a linkage's ratio to one joint changes sign: its motor passes a dead point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeadPoint {
    /// The spanned joint whose ratio changes sign, by name.
    pub joint: String,
    /// The spanned joints' positions there (rad, or m), that joint's interpolated linearly in
    /// the ratio between the two poses of the grid on either side.
    pub at: Vec<f64>,
}

/// The grid of poses over the joints a linkage spans: `per_joint` positions per joint, evenly
/// spaced within its limits (a continuous joint: one turn); the first joint varies fastest.
struct Grid {
    values: Vec<Vec<f64>>,
    per_joint: usize,
}

impl Grid {
    fn new(robot: &Robot, linkage: &Linkage) -> Grid {
        let span = linkage.joints().len();
        let per_joint = (RANGE_SAMPLES.powf(1.0 / span.max(1) as f64).floor() as usize).max(3);
        let values = (linkage.joints())
            .map(|joint| {
                let (low, high) = robot.position_limits()[joint];
                let (low, high) = match low.is_finite() && high.is_finite() {
                    true => (low, high),
                    false => (-PI, PI),
                };
                (0..per_joint)
                    .map(|i| low + (high - low) * i as f64 / (per_joint - 1) as f64)
                    .collect()
            })
            .collect();
        Grid { values, per_joint }
    }

    fn samples(&self) -> usize {
        self.per_joint.pow(self.values.len() as u32)
    }

    /// The grid index of spanned joint `k` in `sample`.
    fn index(&self, sample: usize, k: usize) -> usize {
        sample / self.per_joint.pow(k as u32) % self.per_joint
    }

    /// The spanned joints' positions at `sample`.
    fn pose(&self, sample: usize) -> Vec<f64> {
        (self.values.iter().enumerate())
            .map(|(k, values)| values[self.index(sample, k)])
            .collect()
    }

    /// The next sample along spanned joint `k`, if `sample` is not the last along it.
    fn next_along(&self, sample: usize, k: usize) -> Option<usize> {
        (self.index(sample, k) + 1 < self.per_joint).then(|| sample + self.per_joint.pow(k as u32))
    }
}

/// The readings over a grid within the spanned joints' limits, the other joints at `start`
/// (they do not move the linkage), at design `design`.
pub(super) fn over_range(
    (dynamics, data): (&Dynamics, &mut Workspace),
    (start, design): (&[f64], &[f64]),
    linkage: &Linkage,
    variables: &Variables,
) -> RangeReading {
    let grid = Grid::new(dynamics.robot(), linkage);
    let joints = linkage.joints();
    let mut q = start.to_vec();
    let ratios: Vec<Option<Vec<f64>>> = (0..grid.samples())
        .map(|sample| {
            q[joints.clone()].copy_from_slice(&grid.pose(sample));
            let reading = reading(dynamics, data, linkage, &q, design, variables).ok()?;
            let (ratio, measure) = reading;
            Some(ratio.into_iter().chain([measure]).collect())
        })
        .collect();
    let span = joints.len();
    let closed = ratios.iter().flatten().fold(None, |range, reading| {
        let mut range = range.unwrap_or_else(|| ClosedRange {
            ratio_min: vec![f64::INFINITY; span],
            ratio_max: vec![f64::NEG_INFINITY; span],
            measure_range: [f64::INFINITY, f64::NEG_INFINITY],
        });
        for (k, value) in reading[..span].iter().enumerate() {
            range.ratio_min[k] = range.ratio_min[k].min(*value);
            range.ratio_max[k] = range.ratio_max[k].max(*value);
        }
        range.measure_range[0] = range.measure_range[0].min(reading[span]);
        range.measure_range[1] = range.measure_range[1].max(reading[span]);
        Some(range)
    });
    let names = &dynamics.robot().joint_names()[joints];
    RangeReading {
        samples: grid.samples(),
        open: ratios.iter().filter(|r| r.is_none()).count(),
        open_within: open_within(&grid, &ratios),
        closed,
        dead_points: dead_points(&grid, &ratios, names),
    }
}

/// Per spanned joint, the runs of its grid positions at which some sample did not close, as
/// intervals; empty where every sample closed.
fn open_within(grid: &Grid, ratios: &[Option<Vec<f64>>]) -> Vec<Vec<[f64; 2]>> {
    if ratios.iter().all(Option::is_some) {
        return Vec::new();
    }
    (grid.values.iter().enumerate())
        .map(|(k, values)| {
            let mut open = vec![false; grid.per_joint];
            for (sample, _) in ratios.iter().enumerate().filter(|(_, r)| r.is_none()) {
                open[grid.index(sample, k)] = true;
            }
            let mut runs: Vec<[f64; 2]> = Vec::new();
            for (i, _) in open.iter().enumerate().filter(|(_, &o)| o) {
                match runs.last_mut() {
                    Some(run) if i > 0 && open[i - 1] => run[1] = values[i],
                    _ => runs.push([values[i], values[i]]),
                }
            }
            runs
        })
        .collect()
}

/// Where the ratio to each spanned joint changes sign between a closed sample and the next
/// closed one along that joint.
fn dead_points(grid: &Grid, ratios: &[Option<Vec<f64>>], names: &[String]) -> Vec<DeadPoint> {
    let mut found = Vec::new();
    for (k, name) in names.iter().enumerate() {
        for (sample, reading) in ratios.iter().enumerate() {
            let Some(next) = grid.next_along(sample, k) else {
                continue;
            };
            let (Some(here), Some(there)) = (reading, &ratios[next]) else {
                continue;
            };
            let (a, b) = (here[k], there[k]);
            if (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0) {
                let mut at = grid.pose(sample);
                let step = grid.pose(next)[k] - at[k];
                at[k] += step * a / (a - b);
                found.push(DeadPoint {
                    joint: name.clone(),
                    at,
                });
            }
        }
    }
    found
}

/// The warnings a designer needs: loops open, ratios through zero, strokes left, with the joint
/// positions where they happen; `robot` names the spanned joints and their units.
pub(super) fn warnings(linkage: &Linkage, range: &RangeReading, robot: &Robot) -> Vec<String> {
    let joints: Vec<usize> = linkage.joints().collect();
    let name = |j: usize| shown(&robot.joint_names()[j]);
    let unit = |j: usize| robot.joint_kind(j).unit();
    let mut warnings = Vec::new();
    if range.open > 0 {
        let within: Vec<String> = (joints.iter().zip(&range.open_within))
            .map(|(&j, runs)| {
                let runs: Vec<String> = (runs.iter())
                    .map(|[low, high]| format!("[{}, {}]", number(*low), number(*high)))
                    .collect();
                format!("{} in {} {}", name(j), runs.join(" and "), unit(j))
            })
            .collect();
        warnings.push(format!(
            "the loop does not close at {} of {} poses within the joint limits: for {}",
            range.open,
            range.samples,
            within.join("; ")
        ));
    }
    let Some(closed) = &range.closed else {
        return warnings;
    };
    for (k, &joint) in joints.iter().enumerate() {
        let (low, high) = (closed.ratio_min[k], closed.ratio_max[k]);
        let largest = low.abs().max(high.abs());
        if low < 0.0 && high > 0.0 {
            warnings.push(format!(
                "its ratio to joint {} changes sign within the joint limits ({} to {}): the \
                 motor passes a dead point {}",
                name(joint),
                number(low),
                number(high),
                where_sign_changes(range, &robot.joint_names()[joint], &joints, robot)
            ));
        } else if low.abs().min(high.abs()) < NEAR_ZERO_SHARE * largest {
            warnings.push(format!(
                "its ratio to joint {} falls to {} within the joint limits, near a dead point \
                 (largest {})",
                name(joint),
                number(if low.abs() < high.abs() { low } else { high }),
                number(largest)
            ));
        }
    }
    if let Some([min, max]) = linkage.stroke() {
        let [shortest, longest] = closed.measure_range;
        if shortest < min || longest > max {
            warnings.push(format!(
                "its length runs from {} to {} m within the joint limits, beyond its stroke \
                 [{}, {}] m",
                number(shortest),
                number(longest),
                number(min),
                number(max)
            ));
        }
    }
    warnings
}

/// `near elbow = -1.2 rad and elbow = 1.2 rad`: the first dead points of the ratio to `joint`
/// (all spanned joints' positions where it spans several), and how many more; or, where the
/// sign changes only across poses where the loop does not close, that.
fn where_sign_changes(
    range: &RangeReading,
    joint: &str,
    joints: &[usize],
    robot: &Robot,
) -> String {
    let points: Vec<&DeadPoint> = (range.dead_points.iter())
        .filter(|point| point.joint == joint)
        .collect();
    if points.is_empty() {
        return "across poses where the loop does not close".into();
    }
    let pose = |point: &DeadPoint| {
        let parts: Vec<String> = (joints.iter().zip(&point.at))
            .map(|(&j, value)| {
                let name = shown(&robot.joint_names()[j]);
                format!("{name} = {} {}", number(*value), robot.joint_kind(j).unit())
            })
            .collect();
        match parts.len() {
            1 => parts.concat(),
            _ => format!("({})", parts.join(", ")),
        }
    };
    let mut listed: Vec<String> = points.iter().take(LISTED).map(|p| pose(p)).collect();
    let more = points.len().saturating_sub(LISTED);
    let last = match more {
        0 => listed.pop().unwrap_or_default(),
        _ => format!("{more} more"),
    };
    match listed.is_empty() {
        true => format!("near {last}"),
        false => format!("near {} and {last}", listed.join(", ")),
    }
}
