//! The load held at rest (docs/model.md, section 6): at the start and the goal, the static
//! torques tau_s = g(q) (gravity with the payload, at v = a = 0) against the control limits of
//! the problem's space and torque mode. A property of the formulation, the design and the
//! payload, computed without IPOPT: one gravity evaluation per end. Always reported; a condition
//! of feasibility only where the task's `motion.ends` asks for it (`hold`, `rest`).

use super::formulation::Formulation;
use super::nlp::TrajectoryProblem;
use crate::dynamics::Dynamics;
use crate::transmission::Space;
use crate::transmission::{Coupling, Depth, DesignError, JointLimits, PoseError};
use serde::{Deserialize, Serialize};

/// What the rows of the control limits are, and so what a margin belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HoldRows {
    /// One row per motor: the actuation space, and the joint space in torque mode `exact`.
    Motors,
    /// One row per joint: the joint space's boxes of the modes `paper` and `interval`.
    Joints,
}

impl HoldRows {
    /// The rows of `limits`, the control limits of a problem in `space`.
    pub fn of(space: Space, limits: &JointLimits) -> HoldRows {
        match (space, limits) {
            (Space::Joint, JointLimits::Box { .. }) => HoldRows::Joints,
            _ => HoldRows::Motors,
        }
    }

    /// `motor` or `joint`.
    pub fn name(self) -> &'static str {
        match self {
            HoldRows::Motors => "motor",
            HoldRows::Joints => "joint",
        }
    }
}

/// The static torques at one end of the motion and how they sit in the control limits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EndHold {
    /// Whether every margin is at least minus the tolerance ([`StaticHold::tolerance_nm`]).
    pub holds: bool,
    /// The gravity torques g(q) at the joints, with the payload, N m.
    pub joint_torques_nm: Vec<f64>,
    /// The motor torques G^-T g(q) that hold the arm still, N m (motor i = row i of G).
    pub motor_torques_nm: Vec<f64>,
    /// Per row of the problem's control limits (see [`HoldRows`]): the limit minus |the row's
    /// static torque|, N m; positive inside, negative by what the row lacks.
    pub margins_nm: Vec<f64>,
}

/// The load held at rest at both ends of the motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StaticHold {
    /// Whether the hold is a condition of feasibility (`motion.ends` `hold` or `rest`); under
    /// `paper` it is reported and never judged.
    pub judged: bool,
    /// A margin down to minus this counts as held, N m: the solver's constraint tolerance
    /// ([`DEFAULT_HOLD_TOLERANCE_NM`]).
    pub tolerance_nm: f64,
    /// What the margins' rows are.
    pub rows: HoldRows,
    /// At the start pose.
    pub start: EndHold,
    /// At the goal pose.
    pub goal: EndHold,
    /// Whether the goal's entry is at a TCP goal's pose of the initial guess, before any solve
    /// (the solve chooses q_N): reported, never judged (absent: false, the goal's own pose or
    /// the solved q_N).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub goal_guessed: bool,
}

/// Each row of `limits` at control u: (value, lower, upper), N m. A box's rows are u's elements,
/// the linear rows those of M u within -+ the row's limit.
fn limit_rows(limits: &JointLimits, u: &[f64]) -> Vec<(f64, f64, f64)> {
    match limits {
        JointLimits::Box { lower, upper } => u
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(&v, (&lo, &hi))| (v, lo, hi))
            .collect(),
        JointLimits::Linear { matrix, limits } => {
            let mapped = matrix * nalgebra::DVector::from_column_slice(u);
            mapped
                .iter()
                .zip(limits)
                .map(|(&v, &limit)| (v, -limit, limit))
                .collect()
        }
    }
}

/// The margin of each row of `limits` at control u: the distance inside its interval, N m
/// (negative outside).
pub fn margins(limits: &JointLimits, u: &[f64]) -> Vec<f64> {
    limit_rows(limits, u)
        .into_iter()
        .map(|(v, lo, hi)| (hi - v).min(v - lo))
        .collect()
}

/// The control of a problem in `space` that applies joint torques `tau`: the motor torques
/// G^-T tau in actuation space, tau itself in joint space, N m.
fn control(space: Space, coupling: &Coupling, tau: &[f64]) -> Vec<f64> {
    match space {
        Space::Actuation => coupling.motor_torques(tau),
        Space::Joint => tau.to_vec(),
    }
}

/// The gravity torques g(q) of `dynamics` (with its payload) at pose q, N m.
fn gravity(dynamics: &Dynamics, q: &[f64]) -> Vec<f64> {
    let mut data = dynamics.workspace();
    let mut g = vec![0.0; dynamics.dof()];
    dynamics.gravity_torques(&mut data, q, &mut g);
    g
}

impl EndHold {
    /// The static torques of `dynamics` (with its payload) at pose q, rad, for the design of
    /// `coupling`, against `limits`, the control limits of a problem in `space`; a margin down
    /// to minus `tolerance_nm` holds.
    pub fn at(
        dynamics: &Dynamics,
        coupling: &Coupling,
        (space, limits): (Space, &JointLimits),
        q: &[f64],
        tolerance_nm: f64,
    ) -> EndHold {
        let tau = gravity(dynamics, q);
        let margins_nm = margins(limits, &control(space, coupling, &tau));
        EndHold {
            holds: margins_nm.iter().all(|m| *m >= -tolerance_nm),
            motor_torques_nm: coupling.motor_torques(&tau),
            joint_torques_nm: tau,
            margins_nm,
        }
    }

    /// What the rows lack in all, sum of max(0, -margin), N m.
    pub fn deficit_nm(&self) -> f64 {
        self.margins_nm.iter().map(|m| (-m).max(0.0)).sum()
    }

    /// Each row that does not hold within `tolerance_nm`, as `motor 2 needs 2.794 N m (limit
    /// 1.7)` (`rows` names them; every mode's limits are symmetric, so a row's limit is |its
    /// torque| + its margin).
    pub fn shortfalls(&self, rows: HoldRows, tolerance_nm: f64) -> Vec<String> {
        let torques = match rows {
            HoldRows::Motors => &self.motor_torques_nm,
            HoldRows::Joints => &self.joint_torques_nm,
        };
        self.margins_nm
            .iter()
            .zip(torques)
            .enumerate()
            .filter(|(_, (margin, _))| **margin < -tolerance_nm)
            .map(|(i, (margin, torque))| {
                let limit = torque.abs() + margin;
                format!(
                    "{} {} needs {} N m (limit {})",
                    rows.name(),
                    i + 1,
                    crate::text::number(significant(torque.abs(), 4)),
                    crate::text::number(significant(limit, 12))
                )
            })
            .collect()
    }
}

/// `x` rounded to `digits` significant digits: a torque to 4 (0.0025 does not print as 0.000),
/// a limit recovered as |torque| + margin to 12, so that 1.7 prints as 1.7 and not as its
/// neighbour of rounding.
fn significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

impl StaticHold {
    /// Whether the load is held at both ends.
    pub fn holds(&self) -> bool {
        self.start.holds && self.goal.holds
    }

    /// What both ends lack in all, N m (0 when held).
    pub fn deficit_nm(&self) -> f64 {
        self.start.deficit_nm() + self.goal.deficit_nm()
    }

    /// Why the load is not held, naming the end and the rows, e.g. `cannot hold the load at rest
    /// at the start: motor 2 needs 2.794 N m (limit 1.7)`; none when it is held. Judged or not:
    /// [`StaticHold::failure`] is the verdict's.
    pub fn reason(&self) -> Option<String> {
        self.reason_of(true)
    }

    /// [`StaticHold::reason`], of the start alone unless `goal`.
    fn reason_of(&self, goal: bool) -> Option<String> {
        let ends: Vec<String> = [("start", &self.start), ("goal", &self.goal)]
            .into_iter()
            .take(if goal { 2 } else { 1 })
            .filter(|(_, end)| !end.holds)
            .map(|(name, end)| {
                format!(
                    "cannot hold the load at rest at the {name}: {}",
                    end.shortfalls(self.rows, self.tolerance_nm).join(", ")
                )
            })
            .collect();
        (!ends.is_empty()).then(|| ends.join("; "))
    }

    /// Why the design is infeasible by the hold: [`StaticHold::reason`] where the hold is
    /// judged (of the start alone where the goal's pose is a guess), else none.
    pub fn failure(&self) -> Option<String> {
        self.reason_of(!self.goal_guessed).filter(|_| self.judged)
    }

    /// Why the design is infeasible by the hold at the start alone, judged as
    /// [`StaticHold::failure`]: what no start of a solve can change where the goal's pose is
    /// the solve's choice (a TCP goal).
    pub fn start_failure(&self) -> Option<String> {
        self.reason_of(false).filter(|_| self.judged)
    }

    /// What the judged hold lacks, N m: [`StaticHold::deficit_nm`] where the hold is judged
    /// (the start's alone where the goal's pose is a guess), else 0 (it is no constraint of
    /// the problem).
    pub fn judged_deficit_nm(&self) -> f64 {
        match (self.judged, self.goal_guessed) {
            (false, _) => 0.0,
            (true, true) => self.start.deficit_nm(),
            (true, false) => self.deficit_nm(),
        }
    }
}

impl TrajectoryProblem<'_> {
    /// The load held at rest at the task's start and goal, against this problem's control
    /// limits ([`TrajectoryProblem::control_limits`]); a TCP goal's at the pose of the initial
    /// guess, not judged ([`StaticHold::goal_guessed`]).
    pub fn static_hold(&self) -> StaticHold {
        let [_, goal] = self.end_couplings();
        let guessed = self.formulation().setting().targets().goal.is_some();
        self.hold_with_goal((self.formulation().setting().goal_pose(), goal), guessed)
    }

    /// The same with the goal at the solved last pose `q_n`, rad (for a TCP goal, whose pose
    /// the solve chooses; the task's goal itself otherwise), or why the linkages do not close
    /// there.
    pub fn static_hold_at(&self, q_n: &[f64]) -> Result<StaticHold, PoseError> {
        let f = self.formulation();
        if f.setting().targets().goal.is_none() {
            return Ok(self.static_hold());
        }
        let mut data = f.dynamics().workspace();
        let at = (f.transmission()).at_pose(
            self.ratios(),
            (f.dynamics(), &mut data),
            q_n,
            Depth::First,
        )?;
        Ok(self.hold_with_goal((q_n, &at.coupling), false))
    }

    /// The hold at the task's start and at `goal`, its pose and G there.
    fn hold_with_goal(&self, goal: (&[f64], &Coupling), guessed: bool) -> StaticHold {
        let f = self.formulation();
        let motion = &f.task().motion;
        let tolerance_nm = f.hold_tolerance_nm();
        let [start, _] = self.end_couplings();
        let end = |q: &[f64], coupling: &Coupling| {
            let limits = self.control_limits_with(coupling);
            EndHold::at(
                self.dynamics(),
                coupling,
                (f.space(), &limits),
                q,
                tolerance_nm,
            )
        };
        StaticHold {
            judged: motion.ends.judges_hold(),
            tolerance_nm,
            rows: HoldRows::of(f.space(), &self.control_limits_with(start)),
            start: end(&motion.start, start),
            goal: end(goal.0, goal.1),
            goal_guessed: guessed,
        }
    }
}

impl Formulation {
    /// The load held at rest at design `ratios` (see [`TrajectoryProblem::static_hold`]), or why
    /// the design is not valid.
    pub fn static_hold(&self, ratios: &[f64]) -> Result<StaticHold, DesignError> {
        Ok(self.problem(ratios)?.static_hold())
    }

    /// The largest payload, kg, that design `ratios` holds at rest at both ends: None when it
    /// does not hold even 0 kg, infinite when no payload is too heavy. The static torques are
    /// affine in the payload mass m, u_s(m) = u_0 + m u_1 (gravity is linear in the masses), so
    /// each row's interval bounds m in closed form; u_1 is the difference of the controls at 1 kg
    /// and 0 kg. The formulation's own payload is ignored.
    pub fn hold_capacity(&self, ratios: &[f64]) -> Result<Option<f64>, DesignError> {
        let problem = self.problem(ratios)?;
        let robot = self.dynamics().robot();
        // With the parts the links carry at this design.
        let parts = self.setting().carried().mass_properties(ratios);
        let empty = Dynamics::new(robot.with_payload(0.0)).with_carried(&parts);
        let unit = Dynamics::new(robot.with_payload(1.0)).with_carried(&parts);
        let rows_at = |dynamics: &Dynamics, q: &[f64], coupling: &Coupling| {
            let u = control(self.space(), coupling, &gravity(dynamics, q));
            limit_rows(&problem.control_limits_with(coupling), &u)
        };
        let motion = &self.task().motion;
        let mut largest = f64::INFINITY;
        // A TCP goal's pose is the solve's choice: the start alone bounds the payload.
        let goal = motion.goal.joints();
        let ends = [Some(&motion.start[..]), goal].into_iter();
        let ends = ends
            .zip(problem.end_couplings())
            .filter_map(|(q, g)| Some((q?, g)));
        for (q, coupling) in ends {
            for ((value, lo, hi), (at_unit, _, _)) in rows_at(&empty, q, coupling)
                .into_iter()
                .zip(rows_at(&unit, q, coupling))
            {
                if (hi - value).min(value - lo) < -self.hold_tolerance_nm() {
                    return Ok(None);
                }
                let slope = at_unit - value;
                if slope > 0.0 {
                    largest = largest.min((hi - value) / slope);
                } else if slope < 0.0 {
                    largest = largest.min((lo - value) / slope);
                }
            }
        }
        Ok(Some(largest.max(0.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::{LimitMode, LimitModes};
    use crate::model::Robot;
    use crate::problem::DEFAULT_HOLD_TOLERANCE_NM;
    use crate::testing;

    /// The repository's task carrying `payload_kg` in `space` with torque mode `torque`.
    fn formulation(payload_kg: f64, space: Space, torque: LimitMode) -> Formulation {
        let mut task = testing::task();
        task.payload.mass_kg = payload_kg;
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque,
            speed: task.limit_modes.speed,
        };
        Formulation::new(&task, robot, space, modes).unwrap()
    }

    /// G^-T tau at the original design (6, 3, 1, 1), by hand from G^T u = tau:
    /// u3 + u4 = tau3, u3 - u4 = tau4, 3 u2 + u3 + u4 = tau2, 6 u1 + 3 u2 + u3 + u4 = tau1.
    fn motors_at_original(tau: &[f64]) -> Vec<f64> {
        vec![
            (tau[0] - tau[1]) / 6.0,
            (tau[1] - tau[2]) / 3.0,
            (tau[2] + tau[3]) / 2.0,
            (tau[2] - tau[3]) / 2.0,
        ]
    }

    fn close(a: &[f64], b: &[f64], tolerance: f64) {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= tolerance, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn static_torques_are_gravity_and_the_payload_adds_its_weight_through_the_tcp() {
        let original = testing::task().transmission.original;
        let empty = formulation(0.0, Space::Actuation, LimitMode::Paper);
        let loaded = formulation(2.0, Space::Actuation, LimitMode::Paper);
        let (q0, q1) = (
            empty.static_hold(&original).unwrap().start,
            loaded.static_hold(&original).unwrap().start,
        );
        // The motors' torques are G^-T g(q), G^-T by hand.
        close(
            &q1.motor_torques_nm,
            &motors_at_original(&q1.joint_torques_nm),
            1e-12,
        );
        // The payload (2 kg at the TCP point) adds m |gravity| dp_z/dq: the gradient of its
        // potential energy, here by central differences of the TCP's height.
        let dynamics = loaded.dynamics();
        let mut data = dynamics.workspace();
        let start = &loaded.task().motion.start;
        let step = 1e-6;
        for i in 0..4 {
            let (mut up, mut down) = (start.clone(), start.clone());
            up[i] += step;
            down[i] -= step;
            let dz = (dynamics.tcp_position(&mut data, &up)[2]
                - dynamics.tcp_position(&mut data, &down)[2])
                / (2.0 * step);
            let added = q1.joint_torques_nm[i] - q0.joint_torques_nm[i];
            assert!(
                (added - 2.0 * 9.81 * dz).abs() < 1e-7,
                "joint {i}: {added} vs {dz}"
            );
        }
    }

    #[test]
    fn margins_are_each_modes_limit_less_the_static_torque() {
        let original = testing::task().transmission.original;
        let tau = formulation(1.0, Space::Joint, LimitMode::Paper)
            .static_hold(&original)
            .unwrap()
            .goal
            .joint_torques_nm;
        let motors = motors_at_original(&tau);
        let less = |limits: [f64; 4], x: &[f64]| -> Vec<f64> {
            limits.iter().zip(x).map(|(l, v)| l - v.abs()).collect()
        };
        // Actuation space and joint space in mode `exact`: each motor's 1.7 N m.
        for (space, mode) in [
            (Space::Actuation, LimitMode::Paper),
            (Space::Joint, LimitMode::Exact),
        ] {
            let hold = formulation(1.0, space, mode)
                .static_hold(&original)
                .unwrap();
            assert_eq!(hold.rows, HoldRows::Motors);
            close(&hold.goal.margins_nm, &less([1.7; 4], &motors), 1e-12);
        }
        // The joint boxes of section 5 at (6, 3, 1, 1): `paper` 18.7, 8.5, 3.4, 0 and
        // `interval` 18.7, 8.5, 3.4, 3.4 N m.
        for (mode, limits) in [
            (LimitMode::Paper, [18.7, 8.5, 3.4, 0.0]),
            (LimitMode::Interval, [18.7, 8.5, 3.4, 3.4]),
        ] {
            let hold = formulation(1.0, Space::Joint, mode)
                .static_hold(&original)
                .unwrap();
            assert_eq!(hold.rows, HoldRows::Joints);
            close(&hold.goal.margins_nm, &less(limits, &tau), 1e-12);
            let within = |end: &EndHold| {
                end.margins_nm
                    .iter()
                    .all(|m| *m >= -DEFAULT_HOLD_TOLERANCE_NM)
            };
            assert_eq!(hold.holds(), within(&hold.start) && within(&hold.goal));
        }
        // Mode `paper` gives joint 4 a limit of 0 N m. At the goal its gravity torque is
        // 4.8e-8 N m, within the solver's tolerance: held. At the start it is 0.0025 N m: not.
        let hold = formulation(1.0, Space::Joint, LimitMode::Paper)
            .static_hold(&original)
            .unwrap();
        let joint_4 = |end: &EndHold| end.joint_torques_nm[3].abs();
        assert!(
            joint_4(&hold.goal) < 1e-7 && hold.goal.holds,
            "{:?}",
            hold.goal
        );
        assert!((joint_4(&hold.start) - 0.002541).abs() < 1e-6 && !hold.start.holds);
    }

    #[test]
    fn the_hold_bound_is_where_the_least_margin_reaches_zero() {
        let original = testing::task().transmission.original;
        for space in [Space::Actuation, Space::Joint] {
            let unloaded = formulation(0.0, space, LimitMode::Exact);
            let bound = unloaded.hold_capacity(&original).unwrap().unwrap();
            assert!(bound.is_finite() && bound > 0.0, "{space}: {bound}");
            let at = |kg: f64| {
                unloaded
                    .with_payload(kg)
                    .unwrap()
                    .static_hold(&original)
                    .unwrap()
            };
            let held = at(bound);
            let least = [&held.start, &held.goal]
                .iter()
                .flat_map(|end| end.margins_nm.iter().copied())
                .fold(f64::INFINITY, f64::min);
            assert!(held.holds() && least.abs() < 1e-9, "{space}: {least}");
            let over = at(bound + 0.01);
            assert!(!over.holds(), "{space}");
            assert!(over.deficit_nm() > 0.0);
            let reason = over.reason().unwrap();
            assert!(
                reason.starts_with("cannot hold the load at rest at the "),
                "{reason}"
            );
            assert!(reason.contains("motor "), "{reason}");
            // Deficits grow with the payload.
            assert!(at(bound + 1.0).deficit_nm() > over.deficit_nm());
        }
    }

    #[test]
    fn no_payload_is_held_when_the_unloaded_arm_is_not() {
        let mut task = testing::task();
        task.motors.torque_limit_nm = crate::model::task::PerMotor::All(0.01);
        let robot = Robot::load(&task).unwrap();
        let f = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
        let original = task.transmission.original.clone();
        assert_eq!(f.hold_capacity(&original), Ok(None));
        let hold = f.static_hold(&original).unwrap();
        assert!(!hold.start.holds && !hold.goal.holds);
        let reason = hold.reason().unwrap();
        assert!(
            reason.contains("at the start: motor ")
                && reason.contains("; cannot hold the load at rest at the goal: "),
            "{reason}"
        );
        assert!(reason.contains("(limit 0.01)"), "{reason}");
    }
}
