//! How far a solution is from satisfying each constraint family: the problem's residuals
//! evaluated again on the trajectory read back, independently of IPOPT's own measures
//! ([`Violations::of`]).

use super::keyed::Violations;
use super::trajectory::Trajectory;
use crate::model::task::Motion;
use crate::problem::{Formulation, TrajectoryProblem};
use crate::transmission::{Envelope, JointLimits};

/// The largest |value|, 0 for none.
pub(super) fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m: f64, v| m.max(v.abs()))
}

/// How far `value` lies outside [lower, upper].
fn outside(value: f64, lower: f64, upper: f64) -> f64 {
    (lower - value).max(value - upper).max(0.0)
}

impl Violations {
    /// The violations of `problem`'s constraint families at x, whose trajectory is `trajectory`:
    /// the built-in families' measured again on the trajectory, then each added family's (the
    /// distance of its rows from their bounds at x), under its own name.
    pub(super) fn of(
        problem: &TrajectoryProblem<'_>,
        x: &[f64],
        trajectory: &Trajectory,
    ) -> Violations {
        let mut violations = Violations::built_in(problem, x, trajectory);
        for (name, largest) in problem.added_violations(x).iter() {
            violations.push(name, largest);
        }
        violations
    }

    /// The built-in families' violations, measured on `trajectory`.
    fn built_in(problem: &TrajectoryProblem<'_>, x: &[f64], trajectory: &Trajectory) -> Violations {
        let f = problem.formulation();
        let layout = f.layout();
        let n = layout.dof;
        let steps: Vec<f64> = (0..layout.steps).map(|k| f.step_at(x, k)).collect();
        let limits = f.dynamics().robot().position_limits();
        let speed = problem.speed_limits();
        let control = problem.control_limits();
        // Through G(q_k) at each node: the motor speeds and torques the trajectory records.
        let posed = f.transmission().is_pose_dependent();
        let motor_limits = |values: &[Vec<f64>], limits: &[f64]| {
            (values.iter().flat_map(|row| row.iter().zip(limits)))
                .map(|(&value, &limit)| outside(value, -limit, limit))
                .fold(0.0, f64::max)
        };
        let mut violations = Violations::default();
        violations.push("dynamics", dynamics_residual(problem, trajectory));
        violations.push("integration", integration_residual(&steps, trajectory));
        violations.push("boundary", boundary_residual(&f.task().motion, trajectory));
        violations.push(
            "joint_position",
            trajectory
                .q
                .iter()
                .flat_map(|q| {
                    q.iter()
                        .zip(limits)
                        .map(|(&q, &(lo, hi))| outside(q, lo, hi))
                })
                .fold(0.0, f64::max),
        );
        violations.push(
            "speed_limits",
            match posed {
                true => motor_limits(&trajectory.motor_speed, f.motor_speed_limits()),
                false => (trajectory.v.iter())
                    .map(|v| limit_violation(&speed, v))
                    .fold(0.0, f64::max),
            },
        );
        violations.push(
            "control_limits",
            match posed {
                true => motor_limits(&trajectory.motor_torque, f.motor_torque_limits()),
                false => (0..layout.steps)
                    .map(|k| limit_violation(&control, &x[layout.u(k, 0)..layout.u(k, 0) + n]))
                    .fold(0.0, f64::max),
            },
        );
        violations.push("cartesian_box", box_violation(problem, trajectory));
        for (name, beyond) in f
            .setting()
            .targets()
            .violations(f.dynamics(), &trajectory.q)
        {
            violations.push(name, beyond);
        }
        if let Some(least) = least_envelope_margin(f, trajectory) {
            violations.push("motor_envelope", (-least.margin_nm).max(0.0));
        }
        violations
    }
}

/// Where a trajectory comes closest to its motors' torque-speed envelope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeMargin {
    /// tau_max,i (1 - |w_i|/w_0,i) - |tau_u,i| there, N m: negative by what the motor lacks.
    pub margin_nm: f64,
    /// The motor (0-based, row of G).
    pub motor: usize,
    /// The node k.
    pub node: usize,
}

/// The envelope margin of every motor at the nodes 0 < k < N of `trajectory` (those with
/// envelope rows; at node 0, v_0 = 0 and the envelope is the torque limit), with motor torques u
/// (actuation space) or G^-T u (joint space) and motor speeds G v as the trajectory records them.
pub fn envelope_margins<'a>(
    envelope: &'a Envelope,
    trajectory: &'a Trajectory,
) -> impl Iterator<Item = EnvelopeMargin> + 'a {
    let nodes = trajectory.motor_torque.iter().zip(&trajectory.motor_speed);
    nodes
        .enumerate()
        .skip(1)
        .flat_map(move |(node, (torques, speeds))| {
            (0..envelope.motors()).map(move |motor| EnvelopeMargin {
                margin_nm: envelope.margin(motor, torques[motor], speeds[motor]),
                motor,
                node,
            })
        })
}

/// The least of [`envelope_margins`] under the formulation's envelope; None without an
/// envelope or without such nodes.
pub fn least_envelope_margin(
    formulation: &Formulation,
    trajectory: &Trajectory,
) -> Option<EnvelopeMargin> {
    envelope_margins(formulation.envelope()?, trajectory).reduce(|least, next| {
        if next.margin_nm < least.margin_nm {
            next
        } else {
            least
        }
    })
}

/// The largest |RNEA(q, v, a) - tau| over the intervals, N m.
fn dynamics_residual(problem: &TrajectoryProblem<'_>, trajectory: &Trajectory) -> f64 {
    let dynamics = problem.dynamics();
    let mut data = dynamics.workspace();
    let mut rnea = vec![0.0; dynamics.dof()];
    let mut largest = 0.0;
    for (k, (a, tau)) in trajectory
        .a
        .iter()
        .zip(&trajectory.joint_torque)
        .enumerate()
    {
        dynamics.rnea(&mut data, &trajectory.q[k], &trajectory.v[k], a, &mut rnea);
        largest = f64::max(largest, max_abs(rnea.iter().zip(tau).map(|(r, t)| r - t)));
    }
    largest
}

/// The largest semi-implicit Euler residual over the intervals (each with its step h_k, s in
/// `steps`), rad/s or rad.
fn integration_residual(steps: &[f64], trajectory: &Trajectory) -> f64 {
    let (q, v) = (&trajectory.q, &trajectory.v);
    let mut largest: f64 = 0.0;
    for (k, (a, h)) in trajectory.a.iter().zip(steps).enumerate() {
        for i in 0..a.len() {
            largest = largest
                .max((v[k + 1][i] - v[k][i] - h * a[i]).abs())
                .max((q[k + 1][i] - q[k][i] - h * v[k + 1][i]).abs());
        }
    }
    largest
}

/// The largest distance of the first and last states from the task's start and goal at rest
/// (a TCP goal's last pose is free: its ball is `goal_tcp` of the violations), and under `ends`
/// `rest` of the accelerations at nodes 0 and N-1 from zero (at N-1 under a TCP goal too).
fn boundary_residual(motion: &Motion, trajectory: &Trajectory) -> f64 {
    let last = trajectory.q.len() - 1;
    let mut largest: f64 = 0.0;
    let goal = motion.goal.joints();
    let rests = [motion.ends.rests(), motion.ends.rests() || goal.is_none()];
    let ends = [trajectory.a.first(), trajectory.a.last()];
    for a in (ends.into_iter().zip(rests)).filter_map(|(a, rests)| a.filter(|_| rests)) {
        largest = largest.max(max_abs(a.iter().copied()));
    }
    for (k, pose) in [(0, Some(&motion.start[..])), (last, goal)] {
        let off = pose.map_or(0.0, |pose| {
            max_abs(trajectory.q[k].iter().zip(pose).map(|(q, p)| q - p))
        });
        largest = largest
            .max(off)
            .max(max_abs(trajectory.v[k].iter().copied()));
    }
    largest
}

/// The TCP's largest distance outside the soft Cartesian box over the nodes, m.
fn box_violation(problem: &TrajectoryProblem<'_>, trajectory: &Trajectory) -> f64 {
    let f = problem.formulation();
    let dynamics = f.dynamics();
    let mut data = dynamics.workspace();
    let b = &f.task().cartesian_box;
    let mut largest: f64 = 0.0;
    for q in &trajectory.q {
        let tcp = dynamics.tcp_position(&mut data, q);
        for (axis, interval) in [&b.x, &b.y, &b.z].into_iter().enumerate() {
            if let Some(interval) = interval {
                largest = largest.max(outside(tcp[axis], interval.range[0], interval.range[1]));
            }
        }
    }
    largest
}

/// How far a joint-space vector lies outside `limits`.
fn limit_violation(limits: &JointLimits, values: &[f64]) -> f64 {
    match limits {
        JointLimits::Box { lower, upper } => values
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(&v, (&lo, &hi))| outside(v, lo, hi))
            .fold(0.0, f64::max),
        JointLimits::Linear { matrix, limits } => {
            let mapped = matrix * nalgebra::DVector::from_column_slice(values);
            mapped
                .iter()
                .zip(limits)
                .map(|(m, limit)| outside(*m, -limit, *limit))
                .fold(0.0, f64::max)
        }
    }
}
