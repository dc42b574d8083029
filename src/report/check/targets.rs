//! The checks of a task's via points and upright link (`motion.via`, `motion.upright`;
//! docs/model.md, section 6) before any solve: what a solve refuses ([`Targets::resolve`]: a
//! time or a window off the grid's inner nodes, windows out of order or overlapping, joint
//! angles outside the joint limits, a link the URDF lacks, a start or goal that tilts the link
//! beyond its tolerance), a TCP via point or goal out of the arm's reach, which no motion passes,
//! and a TCP goal that the inverse kinematics of the initial guess does not reach.

use super::{Finding, Inspection};
use codesign_core::dynamics::Dynamics;
use codesign_core::model::task::{Goal, Task, TcpGoal, Via};
use codesign_core::problem::Targets;
use codesign_core::text::{number, rounded};
use nalgebra::Vector3;
use std::borrow::Cow;

/// `task` with a TCP goal replaced by the pose of the initial guess that reaches it (damped
/// least squares from the start, [`Dynamics::tcp_pose_near`]), for the checks that read the goal
/// as a pose; `task` itself for a joint goal (or a start of the wrong length).
pub(super) fn goal_posed<'t>(task: &'t Task, dynamics: &Dynamics) -> Cow<'t, Task> {
    let (Some(goal), true) = (
        task.motion.goal.tcp(),
        task.motion.start.len() == dynamics.dof(),
    ) else {
        return Cow::Borrowed(task);
    };
    let mut posed = task.clone();
    posed.motion.goal = Goal::Joints(guess(task, dynamics, goal).0);
    Cow::Owned(posed)
}

/// The pose of the initial guess for the TCP goal `goal` and its TCP's distance from the point, m.
fn guess(task: &Task, dynamics: &Dynamics, goal: &TcpGoal) -> (Vec<f64>, f64) {
    let point = Vector3::from(goal.tcp);
    let mut data = dynamics.workspace();
    dynamics.tcp_pose_near(&mut data, &task.motion.start, (&point, goal.tol_m))
}

impl Inspection {
    /// The via points and the upright link, where the task has them: an error for each problem
    /// a solve refuses, and for each TCP via point farther from the first joint than the arm
    /// reaches ([`codesign_core::model::Robot::reach`]) by more than its tolerance.
    pub(super) fn check_targets(&mut self, task: &Task, dynamics: &Dynamics) {
        let motion = &task.motion;
        if motion.via.is_empty() && motion.upright.is_none() && motion.goal.tcp().is_none() {
            return;
        }
        let problems = Targets::resolve(task, dynamics).err().unwrap_or_default();
        let (upright, mut via): (Vec<String>, Vec<String>) =
            (problems.into_iter()).partition(|problem| problem.starts_with("motion.upright"));
        via.extend(out_of_reach(task, dynamics));
        if !motion.via.is_empty() {
            let fine = format!(
                "{} via point(s) on inner nodes of the grid, within the joint limits and the \
                 arm's reach",
                motion.via.len()
            );
            let finding = (!via.is_empty()).then(|| Finding::error(via.join("; ")));
            self.verdict("via", finding, fine);
        }
        if let Some(goal) = motion.goal.tcp() {
            self.check_tcp_goal(task, dynamics, goal);
        }
        if let Some(link) = motion.upright.as_ref().map(|u| &u.link) {
            let fine = format!("link '{link}' upright at the start and the goal");
            let finding = (!upright.is_empty()).then(|| Finding::error(upright.join("; ")));
            self.verdict("upright", finding, fine);
        }
    }
}

impl Inspection {
    /// A TCP goal: an error where it lies beyond the arm's reach by more than its tolerance
    /// (no motion ends there), a warning where the inverse kinematics from the start finds no
    /// pose inside its ball (the guess then ends short of it; a local method, so the point may
    /// still be reached by the solve).
    fn check_tcp_goal(&mut self, task: &Task, dynamics: &Dynamics, goal: &TcpGoal) {
        let robot = dynamics.robot();
        let first = robot.joint_names().first().cloned().unwrap_or_default();
        let point = Vector3::from(goal.tcp);
        let beyond = robot.reach().and_then(|(centre, radius)| {
            let distance = (point - centre).norm();
            (distance > radius + goal.tol_m).then(|| {
                Finding::error(format!(
                    "motion.goal.tcp lies {} m from joint '{first}''s origin, beyond the arm's \
                     reach of at most {} m (the lengths of its links summed) by more than \
                     tol_m = {} m: no motion ends there",
                    rounded(distance),
                    rounded(radius),
                    number(goal.tol_m)
                ))
            })
        });
        let fits = task.motion.start.len() == dynamics.dof();
        let (finding, fine) = match (beyond, fits) {
            (Some(finding), _) => (Some(finding), String::new()),
            (None, false) => return,
            (None, true) => {
                let (_, distance) = guess(task, dynamics, goal);
                let short = (distance > goal.tol_m).then(|| {
                    Finding::warning(format!(
                        "motion.goal.tcp: the inverse kinematics from the start (damped least \
                         squares within the joint limits) found no pose within tol_m = {} m; \
                         its nearest lies {} m from the point, where the initial guess ends: \
                         the point may be out of reach",
                        number(goal.tol_m),
                        rounded(distance)
                    ))
                });
                let fine = format!(
                    "the TCP goal within the arm's reach; the initial guess ends {} m from it",
                    rounded(distance)
                );
                (short, fine)
            }
        };
        self.verdict("goal", finding, fine);
    }

    /// A TCP goal's hold at the goal, checked at the pose of the initial guess: a shortfall
    /// there is a warning, as the solve chooses its own last pose (at rest, so that its hold is
    /// the problem's own rows).
    pub(super) fn guessed_goal_hold(&mut self) {
        let held = self
            .verdicts
            .iter_mut()
            .filter(|v| v.check == "hold at goal");
        for verdict in held {
            verdict.detail = format!(
                "{} (at the pose of the initial guess for the TCP goal: the solve chooses its \
                 own)",
                verdict.detail
            );
            if verdict.severity == Some(super::Severity::Error) {
                verdict.severity = Some(super::Severity::Warning);
            }
        }
    }
}

/// Each TCP via point of `task` that lies beyond the arm's reach by more than its tolerance, in
/// words naming its field.
fn out_of_reach(task: &Task, dynamics: &Dynamics) -> Vec<String> {
    let robot = dynamics.robot();
    let Some((centre, radius)) = robot.reach() else {
        return Vec::new();
    };
    let first = robot.joint_names().first().cloned().unwrap_or_default();
    let points = task.motion.via.iter().enumerate();
    let tcp = points.filter_map(|(i, via)| match via {
        Via::Tcp(tcp) => Some((i, tcp)),
        Via::Joints(_) => None,
    });
    tcp.filter_map(|(i, via)| {
        let distance = (nalgebra::Vector3::from(via.tcp) - centre).norm();
        (distance > radius + via.tol_m).then(|| {
            format!(
                "motion.via[{i}].tcp lies {} m from joint '{first}''s origin, beyond the arm's \
                 reach of at most {} m (the lengths of its links summed) by more than tol_m = {} \
                 m: no motion passes it",
                rounded(distance),
                rounded(radius),
                number(via.tol_m)
            )
        })
    })
    .collect()
}
