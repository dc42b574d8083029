//! The checks of an inspection, each a [`Verdict`]: the motion in the joint limits, the design
//! and G at the start, the hold at both ends, the motors' envelope, the limit modes a solve
//! poses with the transmission, and the TCP against the soft Cartesian box at both ends. A
//! finding a solve refuses, or that leaves its result meaningless, is an error; one it solves
//! through is a warning.

use super::{rows, HoldReport, Inspection, Severity, Verdict};
use codesign_core::dynamics::Dynamics;
use codesign_core::model::task::{Ends, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{available_bytes, check_modes, EndHold, Formulation, HoldRows, Space};
use codesign_core::text::{number, numbers, rounded};
use codesign_core::transmission::{JointLimits, Transmission};

/// What a check found where it did not pass.
pub(super) struct Finding {
    severity: Severity,
    detail: String,
}

impl Finding {
    pub(super) fn error(detail: impl ToString) -> Finding {
        Finding {
            severity: Severity::Error,
            detail: detail.to_string(),
        }
    }

    pub(super) fn warning(detail: impl ToString) -> Finding {
        Finding {
            severity: Severity::Warning,
            detail: detail.to_string(),
        }
    }
}

/// Whether the start and the goal each have one position per moving joint.
fn poses_fit(task: &Task, dynamics: &Dynamics) -> bool {
    let dof = dynamics.robot().dof();
    end_poses(task).iter().all(|(_, q)| q.len() == dof)
}

/// The start and the goal by name, rad: the goal where it is joint angles (`check` gives a TCP
/// goal's pose of the initial guess in its place).
fn end_poses(task: &Task) -> Vec<(&'static str, &[f64])> {
    let goal = task.motion.goal.joints().map(|q| ("goal", q));
    [Some(("start", &task.motion.start[..])), goal]
        .into_iter()
        .flatten()
        .collect()
}

/// The verdict on the static torques `end` against each motor's own limit in `limits`, N m:
/// the motors over their limits by more than `tolerance_nm` (the task's `constr_viol_tol`, as the
/// solves judge it), or every torque beside its limit. Under `ends` `paper` the hold
/// is no condition, so a shortfall is told among the fine lines.
fn hold_verdict(
    end: &EndHold,
    limits: &[f64],
    ends: Ends,
    tolerance_nm: f64,
) -> (Option<String>, String) {
    let shortfall = (!end.holds).then(|| {
        format!(
            "{}: the motors cannot hold the load still",
            end.shortfalls(HoldRows::Motors, tolerance_nm).join(", ")
        )
    });
    if let (Some(shortfall), false) = (&shortfall, ends.judges_hold()) {
        return (
            None,
            format!("{shortfall} (not required: motion.ends is paper)"),
        );
    }
    let problem = shortfall;
    let torques: Vec<String> = end
        .motor_torques_nm
        .iter()
        .map(|m| format!("{:.3}", m.abs()))
        .collect();
    let fine = format!(
        "motor torques ({}) N m within the motors' limits ({}) N m",
        torques.join(", "),
        numbers(limits)
    );
    (problem, fine)
}

impl Inspection {
    /// Records check `check`: the finding where it did not pass, else what it found fine.
    pub(super) fn verdict(&mut self, check: &str, finding: Option<Finding>, fine: String) {
        let (severity, detail) = match finding {
            Some(Finding { severity, detail }) => (Some(severity), detail),
            None => (None, fine),
        };
        self.verdicts.push(Verdict {
            check: check.to_owned(),
            ok: severity.is_none(),
            severity,
            detail,
        });
    }

    /// The start and goal: one angle per moving joint, inside the joint limits.
    pub(super) fn check_motion(&mut self, task: &Task, robot: &Robot) {
        let limits = robot.position_limits();
        let mut problems = Vec::new();
        for (pose, q) in end_poses(task) {
            if q.len() != limits.len() {
                problems.push(format!(
                    "motion.{pose} has {} angles for {} moving joints",
                    q.len(),
                    limits.len()
                ));
                continue;
            }
            for (i, (&angle, &(lo, hi))) in q.iter().zip(limits).enumerate() {
                if !(lo..=hi).contains(&angle) {
                    problems.push(format!(
                        "motion.{pose}[{i}] = {angle} {} is outside joint '{}' [{lo}, {hi}]",
                        robot.joint_kind(i).unit(),
                        robot.joint_names()[i]
                    ));
                }
            }
        }
        let problem = (!problems.is_empty()).then(|| Finding::error(problems.join("; ")));
        self.verdict(
            "motion",
            problem,
            "start and goal within the joint limits".into(),
        );
    }

    /// The design in its space with an invertible G, and the motors holding the arm still at
    /// both ends.
    pub(super) fn check_design(
        &mut self,
        (task, dynamics, t): (&Task, &Dynamics, &Transmission),
        ratios: &[f64],
        hold_tolerance_nm: f64,
    ) {
        let poses_fit = poses_fit(task, dynamics);
        // G(r) for a constant transmission; G(q) at the start for a pose-dependent one.
        let start = &task.motion.start;
        let coupling = match (t.is_pose_dependent(), poses_fit) {
            (false, _) => t.coupling(ratios).map(Some),
            (true, true) => (t.coupling_at(ratios, (dynamics, start), "the start")).map(Some),
            // No pose to take G(q) at: the design space alone.
            (true, false) => t.check_design(ratios).map(|()| None),
        };
        let coupling = match coupling {
            Ok(Some(coupling)) => coupling,
            Ok(None) => {
                self.verdict("design", None, "inside the design space".into());
                return;
            }
            Err(error) => {
                self.verdict("design", Some(Finding::error(error)), String::new());
                return;
            }
        };
        let fine = match t.is_pose_dependent() {
            true => "inside the design space, G(q) invertible at the start",
            false => "inside the design space, G invertible",
        };
        self.verdict("design", None, fine.into());
        self.g_at_start = t.is_pose_dependent();
        self.g = Some(rows(coupling.matrix()));
        self.g_inverse = Some(rows(coupling.inverse()));
        if poses_fit {
            self.check_holds((task, dynamics, t), ratios, hold_tolerance_nm);
        }
    }

    /// The motors holding the arm still at the start and the goal, against their own limits
    /// (the actuation space's control limits), where G is read at both.
    fn check_holds(
        &mut self,
        (task, dynamics, t): (&Task, &Dynamics, &Transmission),
        ratios: &[f64],
        hold_tolerance_nm: f64,
    ) {
        let mut data = dynamics.workspace();
        let limits = JointLimits::Box {
            lower: self.torque_limits_nm.iter().map(|l| -l).collect(),
            upper: self.torque_limits_nm.clone(),
        };
        for (pose, q) in end_poses(task) {
            let coupling = match t.coupling_at(ratios, (dynamics, q), &format!("the {pose}")) {
                Ok(coupling) => coupling,
                Err(error) => {
                    self.verdict(
                        &format!("hold at {pose}"),
                        Some(Finding::error(error)),
                        String::new(),
                    );
                    continue;
                }
            };
            let end = EndHold::at(
                dynamics,
                &coupling,
                (Space::Actuation, &limits),
                q,
                hold_tolerance_nm,
            );
            let tcp = dynamics.tcp_position(&mut data, q);
            let ends = task.motion.ends;
            let (problem, fine) =
                hold_verdict(&end, &self.torque_limits_nm, ends, hold_tolerance_nm);
            self.verdict(
                &format!("hold at {pose}"),
                problem.map(Finding::error),
                fine,
            );
            self.holds.push(HoldReport {
                pose: pose.to_owned(),
                q: q.to_vec(),
                tcp_m: [tcp[0], tcp[1], tcp[2]],
                joint_torques_nm: end.joint_torques_nm,
                motor_torques_nm: end.motor_torques_nm,
            });
        }
    }

    /// Where the motors have a torque-speed envelope: the share of its torque limit each motor
    /// keeps at its speed limit, 1 - w_max / w_0, which must be positive (a motor with no torque
    /// left below its speed limit has data at odds with itself, e.g. a no-load speed in rpm
    /// where rad/s was meant would show as a share near 1, one too low as none).
    pub(super) fn check_envelope(&mut self) {
        if self.no_load_speeds_rad_s.is_empty() {
            return;
        }
        let speeds = self
            .speed_limits_rad_s
            .iter()
            .zip(&self.no_load_speeds_rad_s);
        let kept: Vec<f64> = speeds.clone().map(|(w_max, w0)| 1.0 - w_max / w0).collect();
        let problems: Vec<String> = speeds
            .enumerate()
            .filter(|(_, (w_max, w0))| w0 <= w_max)
            .map(|(i, (w_max, w0))| {
                format!(
                    "motor {}'s no-load speed {} rad/s is not above its speed limit {} rad/s: \
                     it has no torque left before that limit",
                    i + 1,
                    number(*w0),
                    number(*w_max)
                )
            })
            .collect();
        let shares: Vec<String> = kept.iter().map(|k| format!("{:.0}%", 100.0 * k)).collect();
        let fine = format!(
            "at its speed limit each motor keeps ({}) of its torque limit",
            shares.join(", ")
        );
        let problem = (!problems.is_empty()).then(|| problems.join("; "));
        self.verdict("torque-speed envelope", problem.map(Finding::error), fine);
    }

    /// The limit modes against the transmission, judged by the rule every solve applies
    /// ([`check_modes`], in its words), in both spaces: an error where either refuses them (the
    /// torque mode is the joint space's alone, so a task whose joint space is refused is wrong
    /// in a field).
    pub(super) fn check_limit_modes(&mut self, task: &Task, t: &Transmission) {
        let modes = &task.limit_modes;
        let refusal = |space: Space| check_modes(t, space, modes).err().map(|e| e.to_string());
        let detail = match (refusal(Space::Actuation), refusal(Space::Joint)) {
            (None, None) => None,
            (None, Some(joint)) => {
                Some(format!("a solve in the joint space refuses them: {joint}"))
            }
            (Some(actuation), Some(joint)) if joint != actuation => Some(format!(
                "a solve in the actuation space refuses them: {actuation}; one in the joint \
                 space: {joint}"
            )),
            (Some(refusal), _) => Some(refusal),
        };
        let fine = format!(
            "torque \"{}\", speed \"{}\": posed in both spaces",
            modes.torque.name(),
            modes.speed.name()
        );
        self.verdict("limit modes", detail.map(Finding::error), fine);
    }

    /// The memory one solve needs (the larger of the two spaces' estimates, where they can be
    /// posed) against what the machine has available, refused in a solve's words.
    pub(super) fn check_memory(&mut self, task: &Task, robot: &Robot) {
        let need =
            |space| Formulation::memory_need_of(task, robot.clone(), space, task.limit_modes).ok();
        let Some(need) = [Space::Joint, Space::Actuation]
            .into_iter()
            .filter_map(need)
            .max_by_key(|need| need.bytes)
        else {
            return;
        };
        let refusal = need.refusal(available_bytes(), task.motion.steps, robot.dof());
        // The memory available is left out when it fits: it changes from one call to the next.
        let fine = format!("one solve needs about {} MiB", need.bytes.div_ceil(1 << 20));
        self.verdict("memory", refusal.map(Finding::error), fine);
    }

    /// The TCP at the start and the goal against the soft Cartesian box (`cartesian_box`), where
    /// the task has one: a TCP outside it is a warning, as the box is a penalty in J that no
    /// motion avoids near that end, not a limit a solve refuses.
    pub(super) fn check_box(&mut self, task: &Task, dynamics: &Dynamics) {
        let b = &task.cartesian_box;
        let axes: Vec<(usize, &str, [f64; 2])> = [("x", &b.x), ("y", &b.y), ("z", &b.z)]
            .into_iter()
            .enumerate()
            .filter_map(|(i, (axis, interval))| interval.as_ref().map(|s| (i, axis, s.range)))
            .collect();
        if axes.is_empty() || !poses_fit(task, dynamics) {
            return;
        }
        let mut data = dynamics.workspace();
        let mut outside = Vec::new();
        for (pose, q) in end_poses(task) {
            let tcp = dynamics.tcp_position(&mut data, q);
            for &(i, axis, [low, high]) in &axes {
                let (by, side) = match (low - tcp[i], tcp[i] - high) {
                    (below, _) if below > 0.0 => (below, "below"),
                    (_, above) if above > 0.0 => (above, "above"),
                    _ => continue,
                };
                outside.push(format!(
                    "the TCP at the {pose} lies {} m {side} cartesian_box.{axis}.range [{}, {}]",
                    rounded(by),
                    number(low),
                    number(high)
                ));
            }
        }
        let finding = (!outside.is_empty()).then(|| {
            Finding::warning(format!(
                "{}: no design and no motion keeps the soft box's term out of J there",
                outside.join("; ")
            ))
        });
        let fine = "the TCP at the start and the goal inside the Cartesian box".to_owned();
        self.verdict("box", finding, fine);
    }
}
