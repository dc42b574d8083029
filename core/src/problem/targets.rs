//! The task's via points, upright link and TCP goal (`motion.via`, `motion.upright`,
//! `motion.goal`; docs/model.md, section 6) resolved against the robot and the grid: each via
//! point on its node, the upright link on its body with its axis in the body's frame, a TCP goal
//! with the pose of the initial guess that reaches it. [`Targets::resolve`] lists every problem
//! it finds, each naming its field; the families `families/via.rs`, `families/upright.rs` and
//! `families/goal.rs` pose the rows, and a result measures them again ([`Targets::violations`]).

use super::error::FormulationError;
use crate::dynamics::{Dynamics, Workspace};
use crate::model::task::{Task, Via, ViaTime};
use crate::model::Robot;
use crate::text::number;
use nalgebra::{DMatrix, Vector3};

/// Joint angles the motion passes at a node: q_k within tol of q (bounds of the node's q).
#[derive(Clone, Debug, PartialEq)]
pub struct JointTarget {
    /// The node k, 0 < k < N.
    pub node: usize,
    /// The joint angles, rad (m for a prismatic joint).
    pub q: Vec<f64>,
    /// The tolerance on each joint, rad (m).
    pub tol_rad: f64,
}

/// A TCP position the motion passes at a node: |p(q_k) - point| <= tol.
#[derive(Clone, Debug, PartialEq)]
pub struct TcpTarget {
    /// The node k, 0 < k < N.
    pub node: usize,
    /// The point in the world, m.
    pub point: Vector3<f64>,
    /// The ball's radius, m.
    pub tol_m: f64,
}

impl TcpTarget {
    /// The row's value (|p - point|^2 - tol^2) / (2 tol) at the TCP's world position p, m: <= 0
    /// inside the ball, |p - point| - tol to the first order at its surface.
    pub fn row(&self, p: &Vector3<f64>) -> f64 {
        ((p - self.point).norm_squared() - self.tol_m * self.tol_m) / (2.0 * self.tol_m)
    }
}

/// A TCP goal: |p(q_N) - point| <= tol at the last node N, whose angles are otherwise free.
#[derive(Clone, Debug, PartialEq)]
pub struct GoalTarget {
    /// The ball as a TCP target (its `node` is the last node N).
    pub ball: TcpTarget,
    /// The pose the initial guess ends at: damped least squares from the start towards the
    /// point, within the joint limits ([`Dynamics::tcp_pose_near`]), rad.
    pub pose: Vec<f64>,
    /// How far that pose's TCP lies from the point, m (more than tol: the iteration found no
    /// pose inside the ball).
    pub distance_m: f64,
}

/// A link held upright: its axis's world z, w_z = (R_b(q) a)_z, at least cos(tol) at every node.
#[derive(Clone, Debug, PartialEq)]
pub struct UprightTarget {
    /// The link's name.
    pub link: String,
    /// The body it is fixed to, None for the base.
    pub body: Option<usize>,
    /// The unit axis in the body's frame.
    pub axis: Vector3<f64>,
    /// The largest angle from the vertical, rad.
    pub tol_rad: f64,
}

impl UprightTarget {
    /// The row's value (w_z - cos tol) / sin tol for the axis's world z `w_z`: >= 0 within the
    /// cone, tol - theta to the first order at its surface (theta the angle from the vertical).
    pub fn row(&self, w_z: f64) -> f64 {
        let (sin, cos) = self.tol_rad.sin_cos();
        (w_z - cos) / sin
    }

    /// The axis's world z at q and its gradient in q (per rad).
    pub fn z_and_gradient(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        q: &[f64],
    ) -> (f64, Vec<f64>) {
        let mut jacobian = DMatrix::zeros(3, q.len());
        dynamics.direction_jacobian(data, q, (self.body, &self.axis), &mut jacobian);
        let w = dynamics.direction_world(data, q, self.body, &self.axis);
        (w.z, jacobian.row(2).iter().copied().collect())
    }

    /// The angle of the axis from the world's +z at q, rad.
    pub fn tilt(&self, dynamics: &Dynamics, data: &mut Workspace, q: &[f64]) -> f64 {
        let w = dynamics.direction_world(data, q, self.body, &self.axis);
        w.z.clamp(-1.0, 1.0).acos()
    }
}

/// A via point that bounds two phases of a phased motion's grid (docs/model.md, section 6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Boundary {
    /// The via point's position in `motion.via`.
    pub via: usize,
    /// Its node k, 0 < k < N.
    pub node: usize,
    /// Its time: given, or a variable within its window.
    pub time: ViaTime,
}

/// The via points and the upright link of a task, resolved.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Targets {
    /// Every via point's node, in the order of `motion.via`.
    pub nodes: Vec<usize>,
    /// The via points as phase boundaries, in time order: every one where the motion is phased
    /// (a window, or a free horizon), none where it is not.
    pub boundaries: Vec<Boundary>,
    /// The joint via points.
    pub joints: Vec<JointTarget>,
    /// The TCP via points, by node ascending (at most one per node).
    pub tcp: Vec<TcpTarget>,
    /// The upright link.
    pub upright: Option<UprightTarget>,
    /// The TCP goal, None where the goal is joint angles.
    pub goal: Option<GoalTarget>,
}

impl Targets {
    /// The targets of `task` on `dynamics`'s robot and the task's grid, or every problem found,
    /// each naming its field: a via time or window off the inner nodes or out of order, a joint
    /// via point of the wrong length or outside the joint limits, two via points of one kind on
    /// one node, an upright link the URDF lacks or that the start or goal tilts beyond tol.
    pub fn resolve(task: &Task, dynamics: &Dynamics) -> Result<Targets, Vec<String>> {
        let (motion, robot) = (&task.motion, dynamics.robot());
        let mut problems = Vec::new();
        let mut targets = Targets::default();
        let phased = motion.phased();
        for (i, (via, node)) in motion.via.iter().zip(motion.via_nodes()).enumerate() {
            let node = match node {
                Ok(node) => node,
                Err(error) => {
                    problems.push(error.to_string());
                    continue;
                }
            };
            targets.nodes.push(node);
            if phased {
                let time = via.time();
                targets.boundaries.push(Boundary { via: i, node, time });
            }
            let taken = match via {
                Via::Joints(_) => targets.joints.iter().any(|t| t.node == node),
                Via::Tcp(_) => targets.tcp.iter().any(|t| t.node == node),
            };
            if taken {
                problems.push(format!(
                    "motion.via[{i}].t_s = {} falls on node {node} as an earlier via point of its \
                     kind does: merge them or give more motion.steps",
                    via.time().text()
                ));
                continue;
            }
            match via {
                Via::Joints(joints) => {
                    let field = format!("motion.via[{i}].q");
                    match joint_problems(&field, &joints.q, robot) {
                        Some(problem) => problems.push(problem),
                        None => targets.joints.push(JointTarget {
                            node,
                            q: joints.q.clone(),
                            tol_rad: joints.tol_rad,
                        }),
                    }
                }
                Via::Tcp(tcp) => targets.tcp.push(TcpTarget {
                    node,
                    point: Vector3::from(tcp.tcp),
                    tol_m: tcp.tol_m,
                }),
            }
        }
        targets.tcp.sort_by_key(|t| t.node);
        targets.goal = goal_target(task, dynamics);
        if let Some(upright) = &motion.upright {
            match upright_target(task, dynamics, upright) {
                Ok(target) => targets.upright = Some(target),
                Err(problem) => problems.push(problem),
            }
        }
        match problems.is_empty() {
            true => Ok(targets),
            false => Err(problems),
        }
    }

    /// Whether the task has neither via points nor an upright link nor a TCP goal.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
            && self.tcp.is_empty()
            && self.upright.is_none()
            && self.goal.is_none()
    }

    /// The pose the standard initial guess ends at: the task's goal angles, or a TCP goal's
    /// pose of the inverse kinematics, rad.
    pub fn goal_pose<'t>(&'t self, task: &'t Task) -> &'t [f64] {
        match (&self.goal, task.motion.goal.joints()) {
            (Some(goal), _) => &goal.pose,
            (None, Some(q)) => q,
            (None, None) => unreachable!("a TCP goal is resolved into Targets::goal"),
        }
    }

    /// The via points with a window: (position in `motion.via`, [t_a, t_b] in s), in time order.
    pub fn windows(&self) -> impl Iterator<Item = (usize, [f64; 2])> + '_ {
        (self.boundaries.iter()).filter_map(|b| match b.time {
            ViaTime::Within(window) => Some((b.via, window)),
            ViaTime::At(_) => None,
        })
    }

    /// The TCP via point at node k, if any.
    pub fn tcp_at(&self, k: usize) -> Option<&TcpTarget> {
        let i = self.tcp.binary_search_by_key(&k, |t| t.node).ok()?;
        Some(&self.tcp[i])
    }

    /// How far the trajectory `q` (a pose per node 0..=N) lies outside each kind of target:
    /// (`via_joints`, rad: the largest |q_k,i - q_i| beyond tol; `via_tcp`, m: the largest
    /// distance of the TCP beyond the ball; `goal_tcp`, m: the last node's TCP beyond the goal's
    /// ball; `upright`, rad: the largest tilt beyond tol), each where the task has targets of
    /// its kind.
    pub fn violations(&self, dynamics: &Dynamics, q: &[Vec<f64>]) -> Vec<(&'static str, f64)> {
        let mut data = dynamics.workspace();
        let mut found = Vec::new();
        if !self.joints.is_empty() {
            let beyond = (self.joints.iter()).flat_map(|t| {
                let at = &q[t.node];
                (t.q.iter().zip(at)).map(move |(want, got)| (got - want).abs() - t.tol_rad)
            });
            found.push(("via_joints", beyond.fold(0.0, f64::max)));
        }
        if !self.tcp.is_empty() {
            let beyond = (self.tcp.iter()).map(|t| {
                let p = dynamics.tcp_position(&mut data, &q[t.node]);
                (p - t.point).norm() - t.tol_m
            });
            found.push(("via_tcp", beyond.fold(0.0, f64::max)));
        }
        if let (Some(goal), Some(last)) = (&self.goal, q.last()) {
            let p = dynamics.tcp_position(&mut data, last);
            found.push((
                "goal_tcp",
                ((p - goal.ball.point).norm() - goal.ball.tol_m).max(0.0),
            ));
        }
        if let Some(upright) = &self.upright {
            let beyond = (q.iter()).map(|q| upright.tilt(dynamics, &mut data, q) - upright.tol_rad);
            found.push(("upright", beyond.fold(0.0, f64::max)));
        }
        found
    }
}

/// The TCP goal of `task` with the pose of its initial guess, None for a joint goal (or a
/// start of the wrong length, which the formulation refuses).
fn goal_target(task: &Task, dynamics: &Dynamics) -> Option<GoalTarget> {
    let goal = task.motion.goal.tcp()?;
    let start = &task.motion.start;
    if start.len() != dynamics.dof() {
        return None;
    }
    let point = Vector3::from(goal.tcp);
    let mut data = dynamics.workspace();
    let (pose, distance_m) = dynamics.tcp_pose_near(&mut data, start, (&point, goal.tol_m));
    Some(GoalTarget {
        ball: TcpTarget {
            node: task.motion.steps,
            point,
            tol_m: goal.tol_m,
        },
        pose,
        distance_m,
    })
}

/// What is wrong with a joint via point `q` of `field` on `robot`: its length, or a joint
/// outside its limits.
fn joint_problems(field: &str, q: &[f64], robot: &crate::model::Robot) -> Option<String> {
    let limits = robot.position_limits();
    if q.len() != limits.len() {
        return Some(format!(
            "{field} has {} values but the robot has {} moving joints",
            q.len(),
            limits.len()
        ));
    }
    let outside: Vec<String> = (q.iter().zip(limits).enumerate())
        .filter(|(_, (value, (lo, hi)))| !(lo..=hi).contains(value))
        .map(|(i, (value, (lo, hi)))| {
            format!(
                "{field}[{i}] = {} lies outside the joint limits [{}, {}] of {}",
                number(*value),
                number(*lo),
                number(*hi),
                robot.joint_names()[i]
            )
        })
        .collect();
    (!outside.is_empty()).then(|| outside.join("; "))
}

/// The upright link of `task` on its body, or why not: a link the URDF lacks, or a start or
/// goal pose (fixed by the task) that tilts it beyond tol.
fn upright_target(
    task: &Task,
    dynamics: &Dynamics,
    upright: &crate::model::task::Upright,
) -> Result<UprightTarget, String> {
    let chain = dynamics.robot().chain();
    let Some(frame) = chain.links.iter().find(|frame| frame.name == upright.link) else {
        return Err(format!(
            "motion.upright.link: '{}' is not a link of this URDF",
            upright.link
        ));
    };
    let target = UprightTarget {
        link: upright.link.clone(),
        body: frame.body,
        axis: frame.placement.rotation * Vector3::from(upright.unit_axis()),
        tol_rad: upright.tol_rad,
    };
    let mut data = dynamics.workspace();
    let motion = &task.motion;
    // A TCP goal's last pose is free: the row at node N-1 holds it, as the motion rests there.
    let goal = motion.goal.joints();
    let ends = [("start", Some(&motion.start[..])), ("goal", goal)];
    for (end, q) in ends.into_iter().filter_map(|(end, q)| Some((end, q?))) {
        if q.len() != dynamics.dof() {
            continue;
        }
        let tilt = target.tilt(dynamics, &mut data, q);
        if tilt > upright.tol_rad {
            return Err(format!(
                "motion.upright.tol_rad = {}: the {end} pose (motion.{end}) tilts link '{}' \
                 {} rad from the vertical, so no motion from it keeps the link upright",
                number(upright.tol_rad),
                upright.link,
                crate::text::rounded(tilt)
            ));
        }
    }
    Ok(target)
}

/// Ok where the task's start and joint goal each give one angle per joint of `robot`, within its
/// joint limits; else the error naming the field (`motion.goal[1]`) and the joint.
pub(super) fn check_end_poses(task: &Task, robot: &Robot) -> Result<(), FormulationError> {
    let n = robot.dof();
    let ends = [
        ("motion.start", Some(&task.motion.start[..])),
        ("motion.goal", task.motion.goal.joints()),
    ];
    for (name, pose) in ends
        .into_iter()
        .filter_map(|(name, pose)| Some((name, pose?)))
    {
        if pose.len() != n {
            return Err(FormulationError(format!(
                "task: {name} has {} values but the robot has {n} joints",
                pose.len()
            )));
        }
        for (i, (&value, &(lo, hi))) in pose.iter().zip(robot.position_limits()).enumerate() {
            if value < lo || value > hi {
                return Err(FormulationError(format!(
                    "task: {name}[{i}] = {value} lies outside the joint limits [{lo}, {hi}] of {}",
                    robot.joint_names()[i]
                )));
            }
        }
    }
    Ok(())
}
