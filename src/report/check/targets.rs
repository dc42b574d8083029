//! The checks of a task's via points and upright link (`motion.via`, `motion.upright`;
//! docs/model.md, section 6) before any solve: what a solve refuses ([`Targets::resolve`]: a
//! time or a window off the grid's inner nodes, windows out of order or overlapping, joint
//! angles outside the joint limits, a link the URDF lacks, a start or goal that tilts the link beyond its tolerance),
//! and a TCP via point out of the arm's reach, which no motion passes.

use super::{Finding, Inspection};
use codesign_core::dynamics::Dynamics;
use codesign_core::model::task::{Task, Via};
use codesign_core::problem::Targets;
use codesign_core::text::{number, rounded};

impl Inspection {
    /// The via points and the upright link, where the task has them: an error for each problem
    /// a solve refuses, and for each TCP via point farther from the first joint than the arm
    /// reaches ([`codesign_core::model::Robot::reach`]) by more than its tolerance.
    pub(super) fn check_targets(&mut self, task: &Task, dynamics: &Dynamics) {
        let motion = &task.motion;
        if motion.via.is_empty() && motion.upright.is_none() {
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
        if let Some(link) = motion.upright.as_ref().map(|u| &u.link) {
            let fine = format!("link '{link}' upright at the start and the goal");
            let finding = (!upright.is_empty()).then(|| Finding::error(upright.join("; ")));
            self.verdict("upright", finding, fine);
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
