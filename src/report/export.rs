//! A solution resampled at a controller's rate (`codesign solve --export FILE.csv --rate HZ`,
//! Python's `Solution.resample`): the joints' and the motors' positions, speeds, accelerations,
//! torques and currents on a uniform grid, interpolated as the transcription integrates
//! (docs/guide/results.md, "Exporting a trajectory for a controller").
//!
//! Over each interval [t_k, t_k+1) the accelerations and the controls are constant, as in the
//! problem. The speeds follow v(t) = v_k + (t - t_k) a_k, the exact solution of dv/dt = a_k, and
//! the positions q(t) = q_k + (t - t_k) v_k+1, the exact solution of dq/dt = v_k+1: the two
//! integration rows v_k+1 = v_k + h a_k and q_k+1 = q_k + h v_k+1, each read as the law of its
//! interval. At the nodes the columns are the solution's own values.

use super::trajectory::{joint_labels, motor_labels};
use codesign_core::model::chain::JointKind;
use codesign_core::problem::{Formulation, TrajectoryProblem};
use codesign_core::solve::{Trajectory, TrajectoryResult};
use codesign_core::transmission::PoseError;
use std::fmt;

/// The most rows an export holds (with the built-in arm's 34 columns, about 55 MB in memory and
/// 150 MB of text): beyond, `--rate` asks for more than a controller's table of one motion.
pub const MAX_ROWS: usize = 200_000;

/// A time within this many intervals of a node is that node: `i / rate` and `k h` computed in
/// floating point differ by a few units in the last place where they name the same instant.
const AT_NODE: f64 = 1e-9;

/// The trajectory on a uniform grid of times, one column per quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Resampled {
    /// The columns' names with their units (`time_s`, `q_shoulder_rad`, ..), in order.
    pub names: Vec<String>,
    /// The columns, each with one value per time, in the order of `names`.
    pub columns: Vec<Vec<f64>>,
}

/// Why a solution could not be resampled.
#[derive(Clone, Debug, PartialEq)]
pub enum ExportError {
    /// The rate is no rate of a grid this export makes; why, in words.
    Rate(String),
    /// The solution cannot be resampled (no interval, or a design its transmission refuses);
    /// why, in words.
    Solution(String),
    /// A linkage of the transmission does not close at the pose interpolated at this time, s.
    Pose {
        /// The time of the pose, s.
        time_s: f64,
        /// Why.
        error: PoseError,
    },
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExportError::Rate(why) => f.write_str(why),
            ExportError::Solution(why) => write!(f, "the solution {why}"),
            ExportError::Pose { time_s, error } => {
                write!(f, "at the pose interpolated at t = {time_s} s, {error}")
            }
        }
    }
}

impl std::error::Error for ExportError {}

/// The number of rows of a grid at `rate_hz` over a motion of `duration_s`: the times i / rate
/// from 0 up to the duration; why not where the rate is not finite and positive or the grid
/// would hold more than [`MAX_ROWS`].
pub fn grid_rows(rate_hz: f64, duration_s: f64) -> Result<usize, ExportError> {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(ExportError::Rate(
            "the rate must be a finite number of samples per second above 0".into(),
        ));
    }
    let intervals = (duration_s * rate_hz * (1.0 + AT_NODE)).floor();
    if intervals >= MAX_ROWS as f64 {
        return Err(ExportError::Rate(format!(
            "over the motion's {duration_s} s it gives {} rows, more than the {MAX_ROWS} an \
             export holds; lower the rate",
            intervals + 1.0
        )));
    }
    Ok(intervals as usize + 1)
}

/// Where time `t` (s) falls among the nodes at `time` (s, ascending; k h, or the phases' times
/// of a motion with via windows): the node k and the time since it, s; exactly 0 at a node
/// (within [`AT_NODE`] of its interval), and at the last node only there.
fn locate(time: &[f64], t: f64) -> (usize, f64) {
    let steps = time.len() - 1;
    let k = (time[..steps].partition_point(|&node| node <= t)).saturating_sub(1);
    let x = (t - time[k]) / (time[k + 1] - time[k]);
    if x.abs() <= AT_NODE {
        return (k, 0.0);
    }
    if (x - 1.0).abs() <= AT_NODE {
        return (k + 1, 0.0);
    }
    (k, t - time[k])
}

/// One sample's joint state: positions and speeds by the integration rows' laws, and the
/// interval's accelerations and joint torques held.
struct Sample {
    q: Vec<f64>,
    v: Vec<f64>,
    interval: usize,
}

/// The joint state at time `t` (s) on trajectory `t`'s nodes (module doc).
fn sample(trajectory: &Trajectory, t: f64) -> Sample {
    let (k, s) = locate(&trajectory.time, t);
    let steps = trajectory.time.len() - 1;
    let interval = k.min(steps - 1);
    if s == 0.0 {
        let (q, v) = (trajectory.q[k].clone(), trajectory.v[k].clone());
        return Sample { q, v, interval };
    }
    let (q_k, v_k, v_next, a_k) = (
        &trajectory.q[k],
        &trajectory.v[k],
        &trajectory.v[k + 1],
        &trajectory.a[k],
    );
    let q = q_k.iter().zip(v_next).map(|(q, v)| q + s * v).collect();
    let v = v_k.iter().zip(a_k).map(|(v, a)| v + s * a).collect();
    Sample { q, v, interval }
}

/// `name` as part of a column's name: every character but ASCII letters, digits and `_`
/// replaced by `_`.
fn column_part(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// `labels` as parts of columns' names ([`column_part`]), each followed by its 1-based index
/// where two would otherwise read alike.
fn column_parts(labels: &[String]) -> Vec<String> {
    let parts: Vec<String> = labels.iter().map(|l| column_part(l)).collect();
    let repeated = (1..parts.len()).any(|i| parts[..i].contains(&parts[i]));
    match repeated {
        true => (parts.into_iter().enumerate())
            .map(|(i, part)| format!("{part}_{}", i + 1))
            .collect(),
        false => parts,
    }
}

/// The columns' names: time, then per joint q, v, a, tau, then per motor q_u, v_u, tau_u and,
/// with the motors' torque constants, the current i_u; each with its unit (a prismatic
/// joint's in m, m/s, m/s^2 and N).
fn column_names(
    formulation: &Formulation,
    result: &TrajectoryResult,
    currents: bool,
) -> Vec<String> {
    let robot = formulation.dynamics().robot();
    let joints = column_parts(&joint_labels(formulation, result));
    let motors = motor_labels(formulation.task(), formulation.motor_torque_limits().len());
    let motors = column_parts(&motors);
    let joint_units = |j: usize| match robot.joint_kind(j) {
        JointKind::Prismatic => ["m", "m_s", "m_s2", "N"],
        _ => ["rad", "rad_s", "rad_s2", "Nm"],
    };
    let mut names = vec!["time_s".to_owned()];
    for (quantity, symbol) in ["q", "v", "a", "tau"].into_iter().enumerate() {
        let units = (0..joints.len()).map(joint_units);
        let columns = joints.iter().zip(units);
        names.extend(columns.map(|(joint, unit)| format!("{symbol}_{joint}_{}", unit[quantity])));
    }
    let mut motor_columns = vec![("q_u", "rad"), ("v_u", "rad_s"), ("tau_u", "Nm")];
    motor_columns.extend(currents.then_some(("i_u", "A")));
    for (symbol, unit) in motor_columns {
        names.extend(
            motors
                .iter()
                .map(|motor| format!("{symbol}_{motor}_{unit}")),
        );
    }
    names
}

/// `result`'s trajectory, solved for `formulation`, at `rate_hz` samples per second from 0 to
/// the motion's end: the joints' positions and speeds as the integration rows integrate them
/// (module doc), the interval's accelerations, joint torques, motor torques and currents
/// (tau_u / k_t, where the task gives k_t) held over it (the last interval's at the last node),
/// the motors' angles gamma(q(t)) and speeds G(q(t)) v(t).
pub fn resample(
    formulation: &Formulation,
    result: &TrajectoryResult,
    rate_hz: f64,
) -> Result<Resampled, ExportError> {
    let trajectory = &result.trajectory;
    let duration = trajectory.time.last().copied().unwrap_or(0.0);
    let rows = grid_rows(rate_hz, duration)?;
    if trajectory.a.is_empty() || trajectory.time.len() != trajectory.a.len() + 1 {
        return Err(ExportError::Solution(
            "holds no interval, or not one fewer than its nodes".into(),
        ));
    }
    let problem = formulation
        .problem(&result.ratios)
        .map_err(|e| ExportError::Solution(format!("has a design its task refuses: {e}")))?;
    let motors = trajectory.motor_torque.first().map_or(0, Vec::len);
    let torque_constants = (formulation.task().motors.torque_constant_nm_per_a)
        .as_ref()
        .map(|k_t| k_t.values(motors));
    let names = column_names(formulation, result, torque_constants.is_some());
    let mut columns = vec![Vec::with_capacity(rows); names.len()];
    for i in 0..rows {
        let t = i as f64 / rate_hz;
        let row = sample_row(&problem, trajectory, t, torque_constants.as_deref())
            .map_err(|error| ExportError::Pose { time_s: t, error })?;
        columns
            .iter_mut()
            .zip(row)
            .for_each(|(c, value)| c.push(value));
    }
    Ok(Resampled { names, columns })
}

/// The row of time `t` (s) in the order of [`column_names`].
fn sample_row(
    problem: &TrajectoryProblem<'_>,
    trajectory: &Trajectory,
    t: f64,
    torque_constants: Option<&[f64]>,
) -> Result<Vec<f64>, PoseError> {
    let Sample { q, v, interval } = sample(trajectory, t);
    let angles = problem.motor_angles(&q)?;
    let speeds = problem.actuation_at(&q)?.coupling().motor_speeds(&v);
    let motor_torque = &trajectory.motor_torque[interval];
    let mut row = vec![t];
    row.extend(q.iter().chain(&v));
    row.extend(
        trajectory.a[interval]
            .iter()
            .chain(&trajectory.joint_torque[interval]),
    );
    row.extend(angles.iter().chain(&speeds).chain(motor_torque));
    if let Some(k_t) = torque_constants {
        row.extend(motor_torque.iter().zip(k_t).map(|(tau, k)| tau / k));
    }
    Ok(row)
}

impl Resampled {
    /// The number of rows (times).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// The table as CSV text: a header of the columns' names, then one line per time, each
    /// number written with the fewest digits that read back as the same f64.
    pub fn to_csv(&self) -> String {
        let mut text = self.names.join(",");
        text.push('\n');
        for i in 0..self.rows() {
            let cells: Vec<String> = self.columns.iter().map(|c| c[i].to_string()).collect();
            text.push_str(&cells.join(","));
            text.push('\n');
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_placed_on_the_nodes_they_name_and_in_the_intervals_between() {
        // 50 intervals over 0.8 s, as the built-in task, and the times of a 1 kHz grid.
        let time: Vec<f64> = (0..=50).map(|k| k as f64 * (0.8 / 50.0)).collect();
        assert_eq!(locate(&time, 0.0), (0, 0.0));
        assert_eq!(locate(&time, 112.0 / 1000.0), (7, 0.0));
        assert_eq!(locate(&time, 800.0 / 1000.0), (50, 0.0));
        let (k, s) = locate(&time, 117.0 / 1000.0);
        assert_eq!(k, 7);
        assert!((s - 0.005).abs() < 1e-15);
        // The phases of a via point's window: steps of 0.1, 0.15 and 0.3 s.
        let phased = [0.0, 0.1, 0.2, 0.35, 0.5, 0.8];
        assert_eq!(locate(&phased, 0.35), (3, 0.0));
        assert_eq!(locate(&phased, 0.2 + 1e-12), (2, 0.0));
        assert_eq!(locate(&phased, 0.5 - 1e-12), (4, 0.0));
        assert_eq!(locate(&phased, 0.8), (5, 0.0));
        let (k, s) = locate(&phased, 0.6);
        assert_eq!(k, 4);
        assert!((s - 0.1).abs() < 1e-15);
        assert_eq!(grid_rows(1000.0, 0.8), Ok(801));
        assert_eq!(grid_rows(30.0, 0.8), Ok(25));
        assert!(grid_rows(0.1, 0.8) == Ok(1));
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(grid_rows(bad, 0.8), Err(ExportError::Rate(_))));
        }
        assert!(grid_rows(MAX_ROWS as f64 / 0.8, 0.8).is_err());
    }

    #[test]
    fn names_become_columns_that_read_apart() {
        let labels = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<Vec<_>>();
        assert_eq!(
            column_parts(&labels(&["motor 1", "wrist-2", "é"])),
            ["motor_1", "wrist_2", "_"]
        );
        assert_eq!(
            column_parts(&labels(&["a b", "a_b", "c"])),
            ["a_b_1", "a_b_2", "c_3"]
        );
    }
}
