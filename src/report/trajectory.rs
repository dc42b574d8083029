//! The result file and plots of one trajectory solve (`codesign solve`).

use super::plots::{Chart, Figure, Guide, Series};
use super::ReportError;
use crate::design::run::RecordedHash;
use crate::model::task::{LimitModes, Task};
use crate::problem::{Formulation, Space};
use crate::solve::{SolveSettings, TaskRecord, ToolInfo, Trajectory, TrajectoryResult};
use crate::transmission::JointLimits;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What defined a solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveInputs {
    /// The task file as given.
    pub task_file: String,
    /// The task hash of the task as read on its robot (`model::identity::task_hash`); unknown in
    /// files written before it was recorded.
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// The design r.
    pub ratios: Vec<f64>,
    /// Payload, kg.
    pub payload_kg: f64,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// The task with every override applied (horizon, payload, robot), and the solve settings.
    pub task: TaskRecord,
}

/// The JSON file `codesign solve --out` writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The inputs.
    pub inputs: SolveInputs,
    /// The result, flattened into the document.
    #[serde(flatten)]
    pub result: TrajectoryResult,
}

impl SolveDocument {
    /// The document of `result`, solved for `formulation` (its task, space and modes) from the
    /// task file `task_file` of task hash `task_hash` with `settings`.
    pub fn new(
        task_file: &str,
        task_hash: &str,
        formulation: &Formulation,
        settings: &SolveSettings,
        result: TrajectoryResult,
    ) -> SolveDocument {
        let task = formulation.task();
        SolveDocument {
            tool: ToolInfo::current(settings.linear_solver()),
            inputs: SolveInputs {
                task_file: task_file.to_owned(),
                task_hash: RecordedHash(Some(task_hash.to_owned())),
                space: formulation.space(),
                ratios: result.ratios.clone(),
                payload_kg: task.payload.mass_kg,
                limit_modes: *formulation.modes(),
                task: TaskRecord {
                    task: task.clone(),
                    solver: settings.clone(),
                },
            },
            result,
        }
    }
}

fn per_joint(time: &[f64], rows: &[Vec<f64>], label: &str) -> Vec<Series> {
    let joints = rows.first().map_or(0, Vec::len);
    (0..joints)
        .map(|i| {
            Series::line(
                format!("{label} {}", i + 1),
                time.iter().zip(rows).map(|(&t, row)| (t, row[i])).collect(),
            )
        })
        .collect()
}

/// The files of the plots of a solve, in the order [`write_plots`] writes them.
pub const PLOT_FILES: [&str; 4] = [
    "joint_positions.svg",
    "joint_torques.svg",
    "motor_torques.svg",
    "tcp_path.svg",
];

/// Writes the plots of a solve into `folder` ([`PLOT_FILES`]): joint positions, joint torques
/// and motor torques with their limits, and the TCP path in the world y-z plane with the
/// Cartesian box.
pub fn write_plots(
    folder: &Path,
    formulation: &Formulation,
    result: &TrajectoryResult,
) -> Result<(), ReportError> {
    crate::store::files::create_folder(folder)?;
    let task = formulation.task();
    let t = &result.trajectory;
    let title = plot_title(formulation, result);
    let charts = [
        joint_positions(formulation, t, &title),
        joint_torques(formulation, result, &title)?,
        motor_torques(task, t, &title),
        tcp_path(task, t, &title),
    ];
    for (name, chart) in PLOT_FILES.into_iter().zip(charts) {
        chart.write(&folder.join(name))?;
    }
    Ok(())
}

/// What every plot of a solve is of: the space, the design and the payload.
fn plot_title(formulation: &Formulation, result: &TrajectoryResult) -> String {
    format!(
        "{} space, r = ({}), payload {} kg",
        formulation.space(),
        result
            .ratios
            .iter()
            .map(|r| format!("{r:.3}"))
            .collect::<Vec<_>>()
            .join(", "),
        formulation.task().payload.mass_kg
    )
}

/// Joint positions over time, rad, with the robot's finite position limits.
fn joint_positions(formulation: &Formulation, t: &Trajectory, title: &str) -> Chart {
    let limits = formulation.dynamics().robot().position_limits();
    let position_guides = limits
        .iter()
        .flat_map(|&(lo, hi)| [lo, hi])
        .filter(|v| v.is_finite())
        .map(Guide::Horizontal);
    Chart {
        title: format!("Joint positions: {title}"),
        x_label: "time [s]".into(),
        y_label: "q [rad]".into(),
        series: per_joint(&t.time, &t.q, "joint"),
        guides: position_guides.collect(),
        log_y: false,
    }
}

/// Joint torques over the control intervals, N m, with the joint-space problem's torque box
/// (none for linear limits or the actuation-space problem).
fn joint_torques(
    formulation: &Formulation,
    result: &TrajectoryResult,
    title: &str,
) -> Result<Chart, ReportError> {
    let t = &result.trajectory;
    let guides = match formulation.space() {
        Space::Joint => {
            let coupling = formulation.transmission().coupling(&result.ratios)?;
            let limit = formulation.task().motors.torque_limit_nm;
            match coupling.torque_limits(formulation.modes().torque, limit) {
                JointLimits::Box { lower, upper } => lower
                    .into_iter()
                    .chain(upper)
                    .map(Guide::Horizontal)
                    .collect(),
                JointLimits::Linear { .. } => Vec::new(),
            }
        }
        Space::Actuation => Vec::new(),
    };
    Ok(Chart {
        title: format!("Joint torques: {title}"),
        x_label: "time [s]".into(),
        y_label: "tau [N m]".into(),
        series: per_joint(&t.time[..t.joint_torque.len()], &t.joint_torque, "joint"),
        guides,
        log_y: false,
    })
}

/// Motor torques over the control intervals, N m, with the motors' limit.
fn motor_torques(task: &Task, t: &Trajectory, title: &str) -> Chart {
    let limit = task.motors.torque_limit_nm;
    Chart {
        title: format!("Motor torques: {title}"),
        x_label: "time [s]".into(),
        y_label: "tau_u [N m]".into(),
        series: per_joint(&t.time[..t.joint_torque.len()], &t.motor_torque, "motor"),
        guides: vec![Guide::Horizontal(-limit), Guide::Horizontal(limit)],
        log_y: false,
    }
}

/// The TCP's path in the world y-z plane, m, with the task's Cartesian box.
fn tcp_path(task: &Task, t: &Trajectory, title: &str) -> Chart {
    let b = &task.cartesian_box;
    let mut box_guides = Vec::new();
    if let Some(y) = &b.y {
        box_guides.extend(y.range.map(Guide::Vertical));
    }
    if let Some(z) = &b.z {
        box_guides.extend(z.range.map(Guide::Horizontal));
    }
    Chart {
        title: format!("TCP path: {title}"),
        x_label: "world y [m]".into(),
        y_label: "world z [m]".into(),
        series: vec![Series::line(
            "TCP",
            t.tcp_y
                .iter()
                .copied()
                .zip(t.tcp_z.iter().copied())
                .collect(),
        )],
        guides: box_guides,
        log_y: false,
    }
}
