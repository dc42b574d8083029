//! The inspection of a robot and its task before any solve (`codesign check`): the chain, the
//! TCP at the start and the goal, G at a design and its inverse, the static gravity torques at
//! both ends against each motor's own torque limit, the design space, and a verdict per check.

use codesign_core::dynamics::Dynamics;
use codesign_core::model::chain::JointKind;
use codesign_core::model::task::{Ends, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{EndHold, HoldRows, Space};
use codesign_core::text::{number, numbers, shown};
use codesign_core::transmission::{JointLimits, Transmission};
use nalgebra::DMatrix;
use serde::Serialize;
use std::fmt::Write as _;

/// One moving joint of the chain, from the base outward.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointReport {
    /// The joint's name in the URDF.
    pub name: String,
    /// How it moves: `revolute` (q in rad, its effort in N m) or `prismatic` (m, N).
    pub kind: JointKind,
    /// Its position limits (lower, upper), rad or m; infinite for a continuous joint.
    pub limits: (f64, f64),
    /// The mass it carries: its body and every body outboard, with the payload, kg.
    pub carries_kg: f64,
}

/// The static torques that hold the arm still at one pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HoldReport {
    /// The pose, `start` or `goal`.
    pub pose: String,
    /// Joint positions, rad (m for a prismatic joint).
    pub q: Vec<f64>,
    /// The TCP's position in the world, m.
    pub tcp_m: [f64; 3],
    /// Gravity torques g(q) at the joints, with the payload, N m (N at a prismatic joint).
    pub joint_torques_nm: Vec<f64>,
    /// The motor torques G^-T g(q) that hold the arm still, N m.
    pub motor_torques_nm: Vec<f64>,
}

/// One check and its verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// What was checked.
    pub check: String,
    /// Whether it passed.
    pub ok: bool,
    /// What was found.
    pub detail: String,
}

/// Everything `codesign check` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Inspection {
    /// The moving joints.
    pub joints: Vec<JointReport>,
    /// What reading the URDF locked or ignored, and why.
    pub notes: Vec<String>,
    /// The TCP's link.
    pub tcp_link: String,
    /// The payload, kg.
    pub payload_kg: f64,
    /// The design inspected.
    pub ratios: Vec<f64>,
    /// Bounds of each ratio.
    pub bounds: Vec<[f64; 2]>,
    /// The order constraints, as written.
    pub order: Vec<String>,
    /// G at the design (row = motor), when it is invertible; G(q) at the motion's start where a
    /// row is a linkage (the linkages' readings give it elsewhere).
    pub g: Option<Vec<Vec<f64>>>,
    /// G^-1 at the design (at the start where G depends on the pose).
    pub g_inverse: Option<Vec<Vec<f64>>>,
    /// Whether G depends on the pose (a row is a linkage): `g` is then G(q) at the start.
    pub g_at_start: bool,
    /// The static torques at the start and the goal.
    pub holds: Vec<HoldReport>,
    /// What the task's motion asks at its ends (`motion.ends`): under `paper` the hold is
    /// reported and no problem; none without a task.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ends: Option<Ends>,
    /// Each motor's torque limit, N m (motor i = row i of G; empty without a task).
    pub torque_limits_nm: Vec<f64>,
    /// Each motor's speed limit, rad/s (empty without a task).
    pub speed_limits_rad_s: Vec<f64>,
    /// Each motor's no-load speed, rad/s, where the task gives a torque-speed envelope.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub no_load_speeds_rad_s: Vec<f64>,
    /// Every check, in order.
    pub verdicts: Vec<Verdict>,
}

fn rows(matrix: &DMatrix<f64>) -> Vec<Vec<f64>> {
    matrix
        .row_iter()
        .map(|row| row.iter().copied().collect())
        .collect()
}

/// The mass each joint carries: its body and those outboard, with the payload, kg.
fn carried(robot: &Robot) -> Vec<f64> {
    let bodies = &robot.chain().bodies;
    let payload_body = robot.payload_point().body;
    (0..bodies.len())
        .map(|i| {
            let own: f64 = bodies[i..].iter().map(|b| b.mass.mass).sum();
            let payload = payload_body
                .filter(|&b| b >= i)
                .map_or(0.0, |_| robot.payload_kg());
            own + payload
        })
        .collect()
}

/// The moving joints of `robot` with their limits and the mass each carries.
fn joints(robot: &Robot) -> Vec<JointReport> {
    robot
        .joint_names()
        .iter()
        .zip(robot.position_limits())
        .zip(carried(robot))
        .enumerate()
        .map(|(j, ((name, &limits), carries_kg))| JointReport {
            name: name.clone(),
            kind: robot.joint_kind(j),
            limits,
            carries_kg,
        })
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
    /// Inspects `robot` (with the task's payload) and `task` at design `ratios` of
    /// `transmission`, judging the static hold at `hold_tolerance_nm`, N m (the task's
    /// `SolveSettings::constraint_tolerance`, as the solves judge it).
    pub fn of(
        task: &Task,
        robot: &Robot,
        (transmission, ratios): (&Transmission, &[f64]),
        hold_tolerance_nm: f64,
    ) -> Inspection {
        let joints = joints(robot);
        let mut inspection = Inspection {
            joints,
            notes: robot.notes().to_vec(),
            tcp_link: task.tcp.link.clone(),
            payload_kg: robot.payload_kg(),
            ratios: ratios.to_vec(),
            bounds: transmission.bounds().to_vec(),
            order: transmission
                .design_space()
                .order()
                .iter()
                .map(|c| c.to_string())
                .collect(),
            g: None,
            g_inverse: None,
            g_at_start: false,
            holds: Vec::new(),
            ends: Some(task.motion.ends),
            torque_limits_nm: task.motors.torque_limit_nm.values(transmission.dof()),
            speed_limits_rad_s: task.motors.speed_limit_rad_s.values(transmission.dof()),
            no_load_speeds_rad_s: task
                .motors
                .no_load_speed_rad_s
                .as_ref()
                .map_or_else(Vec::new, |speeds| speeds.values(transmission.dof())),
            verdicts: Vec::new(),
        };
        inspection.check_motion(task, robot);
        inspection.check_design(task, robot, (transmission, ratios), hold_tolerance_nm);
        inspection.check_envelope();
        inspection
    }

    /// Inspects a robot alone (no task): its chain and notes, with no design and no motion.
    pub fn of_robot(robot: &Robot) -> Inspection {
        let joints = joints(robot);
        Inspection {
            joints,
            notes: robot.notes().to_vec(),
            tcp_link: robot.tcp_link().to_owned(),
            payload_kg: robot.payload_kg(),
            ratios: Vec::new(),
            bounds: Vec::new(),
            order: Vec::new(),
            g: None,
            g_inverse: None,
            g_at_start: false,
            holds: Vec::new(),
            ends: None,
            torque_limits_nm: Vec::new(),
            speed_limits_rad_s: Vec::new(),
            no_load_speeds_rad_s: Vec::new(),
            verdicts: Vec::new(),
        }
    }

    /// Where the motors have a torque-speed envelope: the share of its torque limit each motor
    /// keeps at its speed limit, 1 - w_max / w_0, which must be positive (a motor with no torque
    /// left below its speed limit has data at odds with itself, e.g. a no-load speed in rpm
    /// where rad/s was meant would show as a share near 1, one too low as none).
    fn check_envelope(&mut self) {
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
        self.verdict("torque-speed envelope", problem, fine);
    }

    fn verdict(&mut self, check: &str, problem: Option<String>, fine: String) {
        self.verdicts.push(Verdict {
            check: check.to_owned(),
            ok: problem.is_none(),
            detail: problem.unwrap_or(fine),
        });
    }

    /// The start and goal: one angle per moving joint, inside the joint limits.
    fn check_motion(&mut self, task: &Task, robot: &Robot) {
        let limits = robot.position_limits();
        let mut problems = Vec::new();
        for (pose, q) in [("start", &task.motion.start), ("goal", &task.motion.goal)] {
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
        let problem = (!problems.is_empty()).then(|| problems.join("; "));
        self.verdict(
            "motion",
            problem,
            "start and goal within the joint limits".into(),
        );
    }

    /// The design in its space with an invertible G, and the motors holding the arm still at
    /// both ends.
    fn check_design(
        &mut self,
        task: &Task,
        robot: &Robot,
        (t, ratios): (&Transmission, &[f64]),
        hold_tolerance_nm: f64,
    ) {
        let dof = robot.dof();
        let poses_fit = task.motion.start.len() == dof && task.motion.goal.len() == dof;
        let dynamics = Dynamics::new(robot.clone());
        let mut data = dynamics.workspace();
        // G(r) for a constant transmission; G(q) at the start for a pose-dependent one.
        let start = &task.motion.start;
        let coupling = match (t.is_pose_dependent(), poses_fit) {
            (false, _) => t.coupling(ratios).map(Some),
            (true, true) => (t.coupling_at(ratios, (&dynamics, start), "the start")).map(Some),
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
                self.verdict("design", Some(error.to_string()), String::new());
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
        if !poses_fit {
            return;
        }
        // The motors' own limits: the actuation space's control limits.
        let limits = JointLimits::Box {
            lower: self.torque_limits_nm.iter().map(|l| -l).collect(),
            upper: self.torque_limits_nm.clone(),
        };
        for (pose, q) in [("start", &task.motion.start), ("goal", &task.motion.goal)] {
            let coupling = match t.coupling_at(ratios, (&dynamics, q), &format!("the {pose}")) {
                Ok(coupling) => coupling,
                Err(error) => {
                    self.verdict(
                        &format!("hold at {pose}"),
                        Some(error.to_string()),
                        String::new(),
                    );
                    continue;
                }
            };
            let end = EndHold::at(
                &dynamics,
                &coupling,
                (Space::Actuation, &limits),
                q,
                hold_tolerance_nm,
            );
            let tcp = dynamics.tcp_position(&mut data, q);
            let ends = task.motion.ends;
            let (problem, fine) =
                hold_verdict(&end, &self.torque_limits_nm, ends, hold_tolerance_nm);
            self.verdict(&format!("hold at {pose}"), problem, fine);
            self.holds.push(HoldReport {
                pose: pose.to_owned(),
                q: q.clone(),
                tcp_m: [tcp[0], tcp[1], tcp[2]],
                joint_torques_nm: end.joint_torques_nm,
                motor_torques_nm: end.motor_torques_nm,
            });
        }
    }

    /// The problems found, one a line; empty when every check passed.
    pub fn problems(&self) -> Vec<String> {
        self.verdicts
            .iter()
            .filter(|v| !v.ok)
            .map(|v| format!("{}: {}", v.check, v.detail))
            .collect()
    }

    /// The unit of the joints' gravity loads: "N m" when every joint turns, else one per joint
    /// ("(N m, N m, N)").
    fn effort_units(&self) -> String {
        let units: Vec<&str> = self.joints.iter().map(|j| j.kind.effort_unit()).collect();
        if units.iter().all(|&unit| unit == "N m") {
            "N m".into()
        } else {
            format!("({})", units.join(", "))
        }
    }

    /// Writes G and G^-1, one row a line ("G(q) at the start" where G depends on the pose).
    fn write_coupling(&self, text: &mut String) {
        let names = match self.g_at_start {
            true => ["G(q) at the start", "G(q)^-1 at the start"],
            false => ["G", "G^-1"],
        };
        for (name, matrix) in names.into_iter().zip([&self.g, &self.g_inverse]) {
            if let Some(matrix) = matrix {
                let _ = writeln!(text, "{name}:");
                for row in matrix {
                    let _ = writeln!(text, "  [{}]", four_places(row));
                }
            }
        }
    }

    /// The inspection as text, for a terminal.
    pub fn to_text(&self) -> String {
        let mut text = format!(
            "{} moving joints, TCP on link '{}', payload {} kg\n",
            self.joints.len(),
            shown(&self.tcp_link),
            self.payload_kg
        );
        for (i, joint) in self.joints.iter().enumerate() {
            let (lo, hi) = joint.limits;
            let _ = writeln!(
                text,
                "  joint {} '{}': limits [{lo:.4}, {hi:.4}] {}, carries {:.3} kg",
                i + 1,
                shown(&joint.name),
                joint.kind.unit(),
                joint.carries_kg
            );
        }
        for note in &self.notes {
            let _ = writeln!(text, "  note: {}", shown(note));
        }
        if !self.ratios.is_empty() {
            let _ = writeln!(
                text,
                "design r = ({}); bounds {:?}; order {}",
                four_places(&self.ratios),
                self.bounds,
                if self.order.is_empty() {
                    "none".to_owned()
                } else {
                    self.order.join(", ")
                }
            );
        }
        self.write_coupling(&mut text);
        if !self.torque_limits_nm.is_empty() {
            let _ = write!(
                text,
                "motor torque limits ({}) N m, speed limits ({}) rad/s",
                numbers(&self.torque_limits_nm),
                numbers(&self.speed_limits_rad_s)
            );
            if !self.no_load_speeds_rad_s.is_empty() {
                let speeds = numbers(&self.no_load_speeds_rad_s);
                let _ = write!(text, ", no-load speeds ({speeds}) rad/s");
            }
            text.push('\n');
        }
        for hold in &self.holds {
            let _ = writeln!(
                text,
                "{}: TCP ({}) m; gravity torques at the joints ({}) {}, at the motors ({}) N m",
                hold.pose,
                four_places(&hold.tcp_m),
                four_places(&hold.joint_torques_nm),
                self.effort_units(),
                four_places(&hold.motor_torques_nm)
            );
        }
        for verdict in &self.verdicts {
            let mark = if verdict.ok { "ok  " } else { "FAIL" };
            let _ = writeln!(text, "{mark} {}: {}", verdict.check, shown(&verdict.detail));
        }
        text
    }
}

/// `values` with four decimals, comma-separated; a value that rounds to zero is written 0,
/// never -0.
fn four_places(values: &[f64]) -> String {
    let shown = |v: f64| if v.abs() < 5e-5 { 0.0 } else { v };
    let texts: Vec<String> = values.iter().map(|&v| format!("{:.4}", shown(v))).collect();
    texts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::Inspection;
    use codesign_core::model::task::Task;
    use codesign_core::model::Robot;

    /// Without a task the TCP is on the URDF's tip link, and the inspection names that link,
    /// not another merged into the same body (a gripper's finger), wherever the URDF lists it.
    #[test]
    fn a_robot_alone_names_its_tip_link() {
        let dir = std::env::temp_dir().join(format!("codesign-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let source =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/urdf/gripper.urdf");
        let text = std::fs::read_to_string(source)
            .unwrap()
            .replace("\"link_4\"", "\"tcp\"");
        let tcp_joint = &text[text.find("  <joint name=\"tcp_joint\"").unwrap()..];
        let tcp_joint = &tcp_joint[..tcp_joint.find("</joint>\n").unwrap() + 9];
        let last = text
            .replace(tcp_joint, "")
            .replace("</robot>", &format!("{tcp_joint}</robot>"));
        for (name, urdf) in [("first.urdf", text.clone()), ("last.urdf", last)] {
            let path = dir.join(name);
            std::fs::write(&path, urdf).unwrap();
            let mut task = Task::built_in().unwrap();
            task.tcp.link = Robot::tip_link(&path).unwrap();
            assert_eq!(task.tcp.link, "tcp", "{name}");
            task.robot = Some(path);
            task.payload.at = task.tcp.clone();
            let robot = Robot::load(&task).unwrap();
            let inspection = Inspection::of_robot(&robot);
            assert_eq!(inspection.tcp_link, "tcp", "{name}");
            assert!(inspection.to_text().contains("TCP on link 'tcp'"), "{name}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
