//! The linkages of a transmission as `codesign check` shows them: each one's ratio dq_u/dq at the
//! start and the goal and over the joint range, its length or crank angle, its motor's static
//! torque at the start and the goal through G(q), and where it reaches
//! a dead point, leaves its stroke or cannot close (docs/model.md, section 17).

mod range;

use codesign_core::dynamics::{Dynamics, Workspace};
use codesign_core::model::task::Task;
use codesign_core::transmission::linkage::{Linkage, Variables};
use codesign_core::transmission::Transmission;

use codesign_core::text::{rounded as number, shown};
use range::over_range;
pub use range::{ClosedRange, DeadPoint, RangeReading};
use serde::Serialize;
use std::fmt::Write as _;

/// One linkage at one pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PoseReading {
    /// `start` or `goal`.
    pub pose: String,
    /// dq_u/dq for each joint the linkage spans (motor rad per joint rad), or None where the
    /// loop does not close.
    pub ratio: Option<Vec<f64>>,
    /// Its length (m) or crank angle (rad).
    pub measure: Option<f64>,
    /// The motor's torque holding the robot (with the task's payload) at rest there at the
    /// design read, G(q)^-T g(q), N m; None where G(q) has no inverse there.
    pub static_torque_nm: Option<f64>,
    /// Why it has no reading, if so.
    pub error: Option<String>,
}

/// What `check` shows of one linkage row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LinkageReport {
    /// Its row of G (0-based) and its motor's name.
    pub row: usize,
    /// The motor's name (`motors.names`, or `motor <row + 1>`).
    pub motor: String,
    /// `linear` or `crank_rod`.
    pub kind: &'static str,
    /// The joints it spans.
    pub joints: Vec<String>,
    /// What `measure` is.
    pub measure: &'static str,
    /// At the start and the goal.
    pub poses: Vec<PoseReading>,
    /// Over the joint range.
    pub range: RangeReading,
    /// Dead points, strokes left, loops open.
    pub warnings: Vec<String>,
}

/// The linkage rows of `transmission` (the task's, on the chain of `dynamics`), read at
/// `design` (one value per design parameter, within the design space); empty when every row is
/// constant.
pub fn linkage_reports(
    task: &Task,
    (dynamics, transmission): (&Dynamics, &Transmission),
    design: &[f64],
) -> Vec<LinkageReport> {
    let mut reports = Vec::new();
    for row in transmission.linkages() {
        let motor = (task.motors.names.as_ref())
            .and_then(|names| names.get(row.motor).cloned())
            .unwrap_or_else(|| format!("motor {}", row.motor + 1));
        let mut report = read((task, dynamics, design), &row.linkage, (row.motor, motor));
        for (reading, (_, q)) in (report.poses.iter_mut()).zip(ends(task)) {
            reading.static_torque_nm =
                static_torque(transmission, (dynamics, design), q, row.motor);
        }
        reports.push(report);
    }
    reports
}

/// The task's start and goal poses by name, rad: the goal where it is joint angles (`check`
/// gives a TCP goal's pose of the initial guess in its place).
fn ends(task: &Task) -> Vec<(&'static str, &[f64])> {
    let goal = task.motion.goal.joints().map(|q| ("goal", q));
    [Some(("start", &task.motion.start[..])), goal]
        .into_iter()
        .flatten()
        .collect()
}

/// Motor `row`'s torque holding the robot at rest at pose q through G(q) at `design`, N m; None
/// where the design or G(q) does not allow it.
fn static_torque(
    transmission: &Transmission,
    (dynamics, design): (&Dynamics, &[f64]),
    q: &[f64],
    row: usize,
) -> Option<f64> {
    let coupling = transmission
        .coupling_at(design, (dynamics, q), "the pose")
        .ok()?;
    let mut gravity = vec![0.0; dynamics.dof()];
    dynamics.gravity_torques(&mut dynamics.workspace(), q, &mut gravity);
    coupling.motor_torques(&gravity).get(row).copied()
}

/// Reads one linkage at the ends and over the range.
fn read(
    (task, dynamics, design): (&Task, &Dynamics, &[f64]),
    linkage: &Linkage,
    (row, motor): (usize, String),
) -> LinkageReport {
    let variables = Variables {
        joints: linkage.joints(),
        parameters: Vec::new(),
    };
    let names = dynamics.robot().joint_names();
    let mut data = dynamics.workspace();
    let poses = (ends(task).into_iter())
        .map(|(pose, q)| {
            let reading = reading(dynamics, &mut data, linkage, q, design, &variables);
            match reading {
                Ok((ratio, measure)) => PoseReading {
                    pose: pose.into(),
                    ratio: Some(ratio),
                    measure: Some(measure),
                    static_torque_nm: None,
                    error: None,
                },
                Err(error) => PoseReading {
                    pose: pose.into(),
                    ratio: None,
                    measure: None,
                    static_torque_nm: None,
                    error: Some(error),
                },
            }
        })
        .collect();
    let range = over_range(
        (dynamics, &mut data),
        (&task.motion.start, design),
        linkage,
        &variables,
    );
    let joints: Vec<String> = variables.joints.clone().map(|j| names[j].clone()).collect();
    let warnings = range::warnings(linkage, &range, dynamics.robot());
    LinkageReport {
        row,
        motor,
        kind: linkage.kind(),
        joints,
        measure: linkage.measure_name(),
        poses,
        range,
        warnings,
    }
}

/// The ratio per spanned joint and the measure at `q`, or why the loop does not close.
fn reading(
    dynamics: &Dynamics,
    data: &mut Workspace,
    linkage: &Linkage,
    q: &[f64],
    r: &[f64],
    variables: &Variables,
) -> Result<(Vec<f64>, f64), String> {
    let shape = variables.shape(1);
    let angle = linkage
        .angle(dynamics, data, (q, r), variables, &shape)
        .map_err(|e| e.to_string())?;
    let measure = linkage
        .measure(dynamics, data, (q, r), variables, &shape)
        .map_err(|e| e.to_string())?;
    let ratio = (0..variables.joints.len())
        .map(|v| angle.derivative(&[v]))
        .collect();
    Ok((ratio, measure.value()))
}

/// The reports as text, one block per linkage.
pub fn linkages_text(reports: &[LinkageReport]) -> String {
    let mut text = String::new();
    for report in reports {
        let _ = writeln!(
            text,
            "{} (row {}): {} linkage over joint(s) {}",
            shown(&report.motor),
            report.row,
            report.kind,
            shown(&report.joints.join(", "))
        );
        for pose in &report.poses {
            let _ = match (&pose.ratio, pose.measure, &pose.error) {
                (Some(ratio), Some(measure), _) => writeln!(
                    text,
                    "  at the {}: ratio dq_u/dq {}; {} {}{}",
                    pose.pose,
                    ratio
                        .iter()
                        .map(|v| number(*v).to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    report.measure,
                    number(measure),
                    pose.static_torque_nm
                        .map(|t| format!("; static torque {} N m", number(t)))
                        .unwrap_or_default()
                ),
                (_, _, error) => writeln!(
                    text,
                    "  at the {}: {}",
                    pose.pose,
                    error.as_deref().unwrap_or("no reading")
                ),
            };
        }
        let samples = report.range.samples;
        let _ = match &report.range.closed {
            Some(range) => {
                let ratios: Vec<String> = (0..range.ratio_min.len())
                    .map(|k| {
                        format!(
                            "{} to {}",
                            number(range.ratio_min[k]),
                            number(range.ratio_max[k])
                        )
                    })
                    .collect();
                writeln!(
                    text,
                    "  over the joint range ({samples} poses): ratio {}; {} {} to {}",
                    ratios.join(", "),
                    report.measure,
                    number(range.measure_range[0]),
                    number(range.measure_range[1])
                )
            }
            None => writeln!(
                text,
                "  over the joint range ({samples} poses): the loop closes at none"
            ),
        };
        for warning in &report.warnings {
            let _ = writeln!(text, "  warning: {warning}");
        }
    }
    text
}
