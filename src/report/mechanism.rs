//! The linkages of a transmission as `codesign check` shows them: each one's ratio dq_u/dq at the
//! start and the goal and over the joint range, its length or crank angle, its motor's static
//! torque at the start and the goal through G(q), and where it reaches
//! a dead point, leaves its stroke or cannot close (docs/model.md, section 17).

use codesign_core::dynamics::{Dynamics, Workspace};
use codesign_core::model::matrix_row::MatrixRow;
use codesign_core::model::task::Task;
use codesign_core::text::rounded as number;
use codesign_core::transmission::linkage::{Linkage, ResolveError, Variables};
use codesign_core::transmission::Transmission;
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt::Write as _;

/// Poses sampled over the joint range of a linkage, at most: a grid over the joints it spans.
const RANGE_SAMPLES: f64 = 4096.0;

/// A row's ratio below this share of its largest over the range is reported as near a dead
/// point.
const NEAR_ZERO_SHARE: f64 = 0.02;

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

/// One linkage over a grid of poses within its joints' limits.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RangeReading {
    /// Poses sampled.
    pub samples: usize,
    /// Poses where the loop did not close.
    pub open: usize,
    /// Over the poses where it closed; None if it closed at none.
    pub closed: Option<ClosedRange>,
}

/// A linkage's readings over the poses where it closed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClosedRange {
    /// The smallest and largest ratio per spanned joint.
    pub ratio_min: Vec<f64>,
    /// See `ratio_min`.
    pub ratio_max: Vec<f64>,
    /// The smallest and largest length (m) or crank angle (rad).
    pub measure_range: [f64; 2],
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

/// The linkage rows of a task's transmission, resolved on its robot and read; empty when every
/// row is constant; read at `design` (one value per design parameter, within the design space).
pub fn linkage_reports(
    task: &Task,
    dynamics: &Dynamics,
    design: &[f64],
) -> Result<Vec<LinkageReport>, ResolveError> {
    let mut reports = Vec::new();
    let original = &task.transmission.original;
    let transmission = Transmission::on_chain(&task.transmission, dynamics).ok();
    for (row, written) in task.transmission.matrix.iter().enumerate() {
        let MatrixRow::Linkage(spec) = written else {
            continue;
        };
        let linkage = Linkage::resolve(spec, row, dynamics, original)?;
        let motor = task
            .motors
            .names
            .as_ref()
            .and_then(|names| names.get(row).cloned())
            .unwrap_or_else(|| format!("motor {}", row + 1));
        let mut report = read(
            (task, dynamics, design),
            &linkage,
            (row, motor, spec.kind()),
        );
        if let Some(transmission) = &transmission {
            for (reading, q) in report
                .poses
                .iter_mut()
                .zip([&task.motion.start, &task.motion.goal])
            {
                reading.static_torque_nm = static_torque(transmission, (dynamics, design), q, row);
            }
        }
        reports.push(report);
    }
    Ok(reports)
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
    (row, motor, kind): (usize, String, &'static str),
) -> LinkageReport {
    let variables = Variables {
        joints: linkage.joints(),
        parameters: Vec::new(),
    };
    let names = dynamics.robot().joint_names();
    let mut data = dynamics.workspace();
    let poses = [("start", &task.motion.start), ("goal", &task.motion.goal)]
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
        .to_vec();
    let range = over_range((task, dynamics, design), &mut data, linkage, &variables);
    let joints: Vec<String> = variables.joints.clone().map(|j| names[j].clone()).collect();
    let mut warnings = warnings(linkage, &range, &joints);
    let crossings = linkage.sweep(dynamics, design, &task.motion.start);
    warnings.extend(crossings.iter().map(|crossing| crossing.text(names)));
    LinkageReport {
        row,
        motor,
        kind,
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

/// The readings over a grid within the spanned joints' limits (a continuous joint: one turn),
/// the other joints at the start (they do not move the linkage).
fn over_range(
    (task, dynamics, design): (&Task, &Dynamics, &[f64]),
    data: &mut Workspace,
    linkage: &Linkage,
    variables: &Variables,
) -> RangeReading {
    let joints = variables.joints.clone();
    let limits = dynamics.robot().position_limits();
    let per_joint = (RANGE_SAMPLES.powf(1.0 / joints.len().max(1) as f64).floor() as usize).max(3);
    let mut q = task.motion.start.clone();
    let span = joints.len();
    let samples = per_joint.pow(span as u32);
    let mut open = 0;
    let mut range = ClosedRange {
        ratio_min: vec![f64::INFINITY; span],
        ratio_max: vec![f64::NEG_INFINITY; span],
        measure_range: [f64::INFINITY, f64::NEG_INFINITY],
    };
    for sample in 0..samples {
        let mut rest = sample;
        for joint in joints.clone() {
            let (low, high) = limits[joint];
            let (low, high) = if low.is_finite() && high.is_finite() {
                (low, high)
            } else {
                (-PI, PI)
            };
            q[joint] = low + (high - low) * (rest % per_joint) as f64 / (per_joint - 1) as f64;
            rest /= per_joint;
        }
        match reading(dynamics, data, linkage, &q, design, variables) {
            Ok((ratio, measure)) => {
                for (k, value) in ratio.iter().enumerate() {
                    range.ratio_min[k] = range.ratio_min[k].min(*value);
                    range.ratio_max[k] = range.ratio_max[k].max(*value);
                }
                range.measure_range[0] = range.measure_range[0].min(measure);
                range.measure_range[1] = range.measure_range[1].max(measure);
            }
            Err(_) => open += 1,
        }
    }
    RangeReading {
        samples,
        open,
        closed: (open < samples).then_some(range),
    }
}

/// The warnings a designer needs: loops open, ratios through zero, strokes left.
fn warnings(linkage: &Linkage, range: &RangeReading, joints: &[String]) -> Vec<String> {
    let mut warnings = Vec::new();
    if range.open > 0 {
        warnings.push(format!(
            "the loop does not close at {} of {} poses within the joint limits",
            range.open, range.samples
        ));
    }
    let Some(closed) = &range.closed else {
        return warnings;
    };
    for (k, joint) in joints.iter().enumerate() {
        let (low, high) = (closed.ratio_min[k], closed.ratio_max[k]);
        let largest = low.abs().max(high.abs());
        if low < 0.0 && high > 0.0 {
            warnings.push(format!(
                "its ratio to joint {joint} changes sign within the joint limits ({} to {}): the motor passes a dead point",
                number(low),
                number(high)
            ));
        } else if low.abs().min(high.abs()) < NEAR_ZERO_SHARE * largest {
            warnings.push(format!(
                "its ratio to joint {joint} falls to {} within the joint limits, near a dead point (largest {})",
                number(if low.abs() < high.abs() { low } else { high }),
                number(largest)
            ));
        }
    }
    if let Some([min, max]) = linkage.stroke() {
        let [shortest, longest] = closed.measure_range;
        if shortest < min || longest > max {
            warnings.push(format!(
                "its length runs from {} to {} m within the joint limits, beyond its stroke [{}, {}] m",
                number(shortest),
                number(longest),
                number(min),
                number(max)
            ));
        }
    }
    warnings
}

/// The reports as text, one block per linkage.
pub fn linkages_text(reports: &[LinkageReport]) -> String {
    let mut text = String::new();
    for report in reports {
        let _ = writeln!(
            text,
            "{} (row {}): {} linkage over joint(s) {}",
            report.motor,
            report.row,
            report.kind,
            report.joints.join(", ")
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
