//! The inspection of a robot and its task before any solve (`codesign check`, Python's
//! `Task.check`): the chain, the TCP at the start and the goal, G at a design and its inverse,
//! the static gravity torques at both ends against each motor's own torque limit, the design
//! space, the limit modes, the linkages' readings, the via points, the upright link and a TCP
//! goal (its pose the initial guess's, by inverse kinematics, where a check needs one), and a
//! verdict per check, each finding an error (a solve refuses the task, or its result would mean
//! nothing) or a warning; a task with several motions is inspected motion by motion (`motions`).

mod motions;
mod targets;
mod verdicts;

pub use motions::{MotionInspection, TaskInspection};
use verdicts::Finding;

use codesign_core::dynamics::Dynamics;
use codesign_core::model::carried::{CarriedMassAt, CarriedModel};
use codesign_core::model::catalogue::Catalogue;
use codesign_core::model::chain::JointKind;
use codesign_core::model::task::{Ends, Task};
use codesign_core::model::Robot;
use codesign_core::text::{number, numbers, rounded, shown};
use codesign_core::transmission::Transmission;

use super::mechanism::{linkage_reports, linkages_text, LinkageReport};
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

/// The catalogue motor a task chose for one motor (`motors.parts`), with the numbers of the part
/// that are no figures of the motor model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartReport {
    /// The part's name in its catalogue.
    pub name: String,
    /// The catalogue file, as the task's reading joined it.
    pub catalogue: String,
    /// Its mass, kg, where the catalogue gives it.
    pub mass_kg: Option<f64>,
    /// Its continuous torque, N m (given, or k_t times the continuous current), where known.
    pub continuous_torque_nm: Option<f64>,
}

/// The chosen parts of `task`, motor i's at index i; empty where it chooses none. A catalogue
/// is read again for the numbers the task does not hold; one that cannot be read now (it was
/// when the task was) leaves them out.
fn part_reports(task: &Task) -> Vec<PartReport> {
    let Some(parts) = task.motors.parts.as_ref() else {
        return Vec::new();
    };
    parts
        .iter()
        .map(|part| {
            let catalogue = Catalogue::load(&part.catalogue).ok();
            let motor = catalogue.as_ref().and_then(|c| c.motor(&part.name));
            PartReport {
                name: part.name.clone(),
                catalogue: part.catalogue.display().to_string(),
                mass_kg: motor.and_then(|m| m.mass_kg),
                continuous_torque_nm: motor.and_then(|m| m.continuous_torque()),
            }
        })
        .collect()
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

/// How much a finding weighs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// A solve refuses the task or the design, or its result would mean nothing (motors that
    /// cannot hold the load where the ends ask for it): `check` exits 1.
    Error,
    /// A solve runs, and the designer should know (a dead point or an open loop within the
    /// joint limits, a TCP outside the soft box at an end): `check` exits 0.
    Warning,
}

/// One check and its verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// What was checked.
    pub check: String,
    /// Whether it passed.
    pub ok: bool,
    /// How much its finding weighs, where it did not pass.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub severity: Option<Severity>,
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
    /// Each motor's catalogue part, where the task chooses them (`motors.parts`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<PartReport>,
    /// The parts the links carry (the task's `carried`) with their masses at the design
    /// inspected.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub carried: Vec<CarriedMassAt>,
    /// Every check, in order.
    pub verdicts: Vec<Verdict>,
    /// The linkage rows' readings (docs/model.md, section 17), at the design inspected where
    /// it is valid, else at the task's original design; absent when every row is constant.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub linkages: Vec<LinkageReport>,
    /// The errors found (`check: detail`): what a solve refuses or cannot make sense of.
    pub problems: Vec<String>,
    /// The warnings found: the verdicts' (`check: detail`), then the linkages'
    /// (`motor: warning`).
    pub warnings: Vec<String>,
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

impl Inspection {
    /// What `codesign check` and Python's `Task.check` report: `task` on `robot` (the task's
    /// payload and ends applied) at design `ratios` (None: the task's original), the hold
    /// judged at `hold_tolerance_nm`, N m (the task's `SolveSettings::constraint_tolerance`, as
    /// the solves judge it). Errs, naming the field, where the transmission does not fit the
    /// robot.
    pub fn of_task(
        task: &Task,
        robot: &Robot,
        ratios: Option<&[f64]>,
        hold_tolerance_nm: f64,
    ) -> Result<Inspection, String> {
        let dynamics = Dynamics::new(robot.clone());
        let transmission =
            Transmission::on_chain(&task.transmission, &dynamics).map_err(|e| e.to_string())?;
        let carried =
            CarriedModel::on_chain(&task.carried, robot.chain(), transmission.num_ratios())?;
        if transmission.dof() != robot.dof() {
            return Err(format!(
                "transmission.matrix is {0}x{0} but the robot has {1} moving joints",
                transmission.dof(),
                robot.dof()
            ));
        }
        let ratios = ratios.unwrap_or(&task.transmission.original);
        // The robot carrying the task's parts at the design inspected.
        let dynamics = dynamics.with_carried(&carried.mass_properties(ratios));
        let mut inspection = Inspection {
            ratios: ratios.to_vec(),
            bounds: transmission.bounds().to_vec(),
            order: (transmission.design_space().order().iter())
                .map(|c| c.to_string())
                .collect(),
            tcp_link: task.tcp.link.clone(),
            ends: Some(task.motion.ends),
            torque_limits_nm: task.motors.torque_limit_nm.values(transmission.dof()),
            speed_limits_rad_s: task.motors.speed_limit_rad_s.values(transmission.dof()),
            no_load_speeds_rad_s: (task.motors.no_load_speed_rad_s.as_ref())
                .map_or_else(Vec::new, |speeds| speeds.values(transmission.dof())),
            parts: part_reports(task),
            carried: carried.masses_at(&task.carried, ratios),
            ..Inspection::of_robot(robot)
        };
        // The checks that read the goal as a pose take a TCP goal's pose of the initial guess.
        let posed = targets::goal_posed(task, &dynamics);
        inspection.check_motion(&posed, robot);
        let parts = (&*posed, &dynamics, &transmission);
        inspection.check_design(parts, ratios, hold_tolerance_nm);
        if task.motion.goal.tcp().is_some() {
            inspection.guessed_goal_hold();
        }
        inspection.check_envelope();
        inspection.check_limit_modes(task, &transmission);
        inspection.check_memory(task, robot);
        inspection.check_box(&posed, &dynamics);
        inspection.check_targets(task, &dynamics);
        // The linkages at the design inspected where it is valid (a verdict names it otherwise).
        let design = match transmission.check_design(ratios) {
            Ok(()) => ratios,
            Err(_) => &task.transmission.original,
        };
        inspection.linkages = linkage_reports(&posed, (&dynamics, &transmission), design);
        inspection.conclude();
        Ok(inspection)
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
            parts: Vec::new(),
            carried: Vec::new(),
            verdicts: Vec::new(),
            linkages: Vec::new(),
            problems: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Lists the findings of the verdicts and the linkages as problems and warnings.
    fn conclude(&mut self) {
        let of = |severity: Severity| {
            (self.verdicts.iter())
                .filter(move |v| v.severity == Some(severity))
                .map(|v| format!("{}: {}", v.check, v.detail))
        };
        let linkages = (self.linkages.iter())
            .flat_map(|l| l.warnings.iter().map(|w| format!("{}: {w}", l.motor)));
        self.problems = of(Severity::Error).collect();
        self.warnings = of(Severity::Warning).chain(linkages).collect();
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
        text.push_str(&parts_text(&self.parts));
        text.push_str(&carried_text(&self.carried));
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
            let mark = match verdict.severity {
                None => "ok  ",
                Some(Severity::Warning) => "warn",
                Some(Severity::Error) => "FAIL",
            };
            let _ = writeln!(text, "{mark} {}: {}", verdict.check, shown(&verdict.detail));
        }
        text.push_str(&linkages_text(&self.linkages));
        text
    }
}

/// The lines of the chosen parts: `motor 1: Allied Motion HT02502-A00 (0.56 kg, continuous
/// 0.636 N m) of catalogue ...`, then their mass in all where every part gives it; empty
/// without parts.
fn parts_text(parts: &[PartReport]) -> String {
    let mut text = String::new();
    for (i, part) in parts.iter().enumerate() {
        let mass = part
            .mass_kg
            .map_or("mass not given".to_owned(), |m| format!("{} kg", number(m)));
        let continuous = part
            .continuous_torque_nm
            .map_or("not given".to_owned(), |t| format!("{:.3} N m", t));
        let _ = writeln!(
            text,
            "motor {}: {} ({mass}, continuous torque {continuous}) of catalogue {}",
            i + 1,
            shown(&part.name),
            shown(&part.catalogue)
        );
    }
    let masses: Option<Vec<f64>> = parts.iter().map(|p| p.mass_kg).collect();
    if let Some(masses) = masses.filter(|m| !m.is_empty()) {
        let total: f64 = masses.iter().sum();
        let _ = writeln!(text, "motor parts: {} kg in all", number(total));
    }
    text
}

/// The lines of the carried parts: `carried 1: pulley 'GT2 ...' on upper_arm, 0.107 kg at
/// this design`; empty without.
fn carried_text(parts: &[CarriedMassAt]) -> String {
    let mut text = String::new();
    for (i, part) in parts.iter().enumerate() {
        let _ = writeln!(
            text,
            "carried {}: {} '{}' on {}, {} kg at this design",
            i + 1,
            part.kind,
            shown(&part.name),
            shown(&part.link),
            rounded(part.mass_kg)
        );
    }
    text
}

/// `values` with four decimals, comma-separated; a value that rounds to zero is written 0,
/// never -0, and one of 1e15 or more as [`number`] writes it (`1e308`, not 309 digits).
fn four_places(values: &[f64]) -> String {
    let texts: Vec<String> = (values.iter())
        .map(|&v| match v.abs() {
            size if size < 5e-5 => format!("{:.4}", 0.0),
            size if size < 1e15 => format!("{v:.4}"),
            _ => number(v).to_string(),
        })
        .collect();
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
