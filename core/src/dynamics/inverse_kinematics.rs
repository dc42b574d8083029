//! A small inverse kinematics of the TCP's position: damped least squares from a given pose,
//! within the joint limits. It gives a pose for an initial guess (a TCP goal's, docs/model.md,
//! section 6), not a constraint of any problem.

use super::{Dynamics, Workspace};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// The damping lambda of the least squares at the start, m: a step keeps
/// |J dq - e|^2 + lambda^2 |dq|^2 least.
const DAMPING_M: f64 = 0.05;

/// The largest damping, m: where a step this short brings the TCP no nearer, the iteration
/// stops.
const MAX_DAMPING_M: f64 = 10.0;

/// The largest step of one iteration, rad (m for a prismatic joint), over all joints.
const MAX_STEP: f64 = 0.3;

/// The iterations at most.
const MAX_ITERATIONS: usize = 500;

impl Dynamics {
    /// A pose near `start` (rad) whose TCP lies as near `target` (world frame, m) as the
    /// iteration finds, within the joint limits: damped least squares,
    /// dq = J^T (J J^T + lambda^2 I)^-1 (target - p(q)), each step at most [`MAX_STEP`] and
    /// clamped into the limits, taken where it brings the TCP nearer (lambda then halved, down
    /// to [`DAMPING_M`] / 10), else retried with lambda four times larger, until the TCP is
    /// within `tol_m` of the target (the first pose the iteration finds there) or lambda passes
    /// [`MAX_DAMPING_M`]. Returns the pose and its TCP's distance from the target, m.
    pub fn tcp_pose_near(
        &self,
        data: &mut Workspace,
        start: &[f64],
        (target, tol_m): (&Vector3<f64>, f64),
    ) -> (Vec<f64>, f64) {
        let limits = self.robot().position_limits();
        let mut q: Vec<f64> = (start.iter().zip(limits))
            .map(|(&value, &(lo, hi))| value.clamp(lo, hi))
            .collect();
        let mut jacobian = DMatrix::zeros(3, q.len());
        let mut distance = (target - self.tcp_position(data, &q)).norm();
        let mut damping = DAMPING_M;
        for _ in 0..MAX_ITERATIONS {
            if distance <= tol_m || damping > MAX_DAMPING_M {
                break;
            }
            let error = target - self.tcp_position(data, &q);
            self.tcp_jacobian(data, &q, &mut jacobian);
            let square = &jacobian * jacobian.transpose() + Matrix3::identity() * damping.powi(2);
            let Some(solved) = square.try_inverse() else {
                break;
            };
            let mut step: DVector<f64> = jacobian.transpose() * (solved * error);
            let largest = step.amax();
            if largest > MAX_STEP {
                step *= MAX_STEP / largest;
            }
            let next: Vec<f64> = (q.iter().zip(step.iter()).zip(limits))
                .map(|((value, dq), &(lo, hi))| (value + dq).clamp(lo, hi))
                .collect();
            let reached = (target - self.tcp_position(data, &next)).norm();
            if reached < distance {
                (q, distance) = (next, reached);
                damping = (damping / 2.0).max(DAMPING_M / 10.0);
            } else {
                damping *= 4.0;
            }
        }
        (q, distance)
    }
}

#[cfg(test)]
mod tests {
    use crate::dynamics::Dynamics;
    use crate::model::task::Task;
    use crate::model::Robot;

    /// From the built-in task's start, the pose it finds puts the TCP on the goal's TCP, within
    /// the joint limits; a point beyond the reach ends the iteration short of it, within the
    /// limits, by at least its distance beyond the reach.
    #[test]
    fn the_pose_near_the_start_reaches_a_point_of_the_arm_within_its_limits() {
        let task = Task::built_in().unwrap();
        let dynamics = Dynamics::new(Robot::load(&task).unwrap());
        let mut data = dynamics.workspace();
        let goal = task.motion.goal.joints().unwrap();
        let target = dynamics.tcp_position(&mut data, goal);
        let start = &task.motion.start;
        let (q, distance) = dynamics.tcp_pose_near(&mut data, start, (&target, 1e-6));
        assert!(distance <= 1e-6, "{distance}");
        assert!((dynamics.tcp_position(&mut data, &q) - target).norm() <= 1e-6);
        let limits = dynamics.robot().position_limits();
        assert!((q.iter().zip(limits)).all(|(v, (lo, hi))| (lo..=hi).contains(&v)));
        let far = target * 10.0;
        let (q, short) = dynamics.tcp_pose_near(&mut data, start, (&far, 1e-3));
        let (centre, radius) = dynamics.robot().reach().unwrap();
        assert!(short >= (far - centre).norm() - radius - 1e-9, "{short}");
        assert!((dynamics.tcp_position(&mut data, &q) - far).norm() == short);
        assert!((q.iter().zip(limits)).all(|(v, (lo, hi))| (lo..=hi).contains(&v)));
    }
}
