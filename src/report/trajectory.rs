//! The plots of one trajectory solve (`codesign solve --plot`); its document is
//! `solve_document.rs`.

use super::motor_plots::{motor_charts, motor_plot_file, LINKAGE_RATIOS_FILE};
use super::plots::{Chart, Figure, Guide, Line, Series};
use super::world::{path_plane, plot_title};
use super::ReportError;
use codesign_core::model::chain::JointKind;
use codesign_core::model::task::Task;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{Trajectory, TrajectoryResult};
use codesign_core::transmission::JointLimits;
use std::path::Path;

/// One series per column of `rows` (one row per time of `time`), named by `labels`.
fn per_column(time: &[f64], rows: &[Vec<f64>], labels: &[String]) -> Vec<Series> {
    labels
        .iter()
        .enumerate()
        .map(|(i, label)| {
            Series::line(
                label.clone(),
                time.iter().zip(rows).map(|(&t, row)| (t, row[i])).collect(),
            )
        })
        .collect()
}

/// The moving joints' URDF names: the result's, or the robot's for a result written before
/// they were recorded.
pub(super) fn joint_labels(formulation: &Formulation, result: &TrajectoryResult) -> Vec<String> {
    let robot = formulation.dynamics().robot();
    if result.joints.len() == robot.dof() {
        result.joints.clone()
    } else {
        robot.joint_names().to_vec()
    }
}

/// The label of a chart of joint quantities `symbol`, in `turning` units, and in `sliding` units
/// for the prismatic joints, named: "q [rad]", or "q [rad; m: quill]".
fn joint_axis_label(
    formulation: &Formulation,
    symbol: &str,
    turning: &str,
    sliding: &str,
) -> String {
    let robot = formulation.dynamics().robot();
    let prismatic: Vec<&str> = (0..robot.dof())
        .filter(|&j| robot.joint_kind(j) == JointKind::Prismatic)
        .map(|j| robot.joint_names()[j].as_str())
        .collect();
    match prismatic.is_empty() {
        true => format!("{symbol} [{turning}]"),
        false => format!("{symbol} [{turning}; {sliding}: {}]", prismatic.join(", ")),
    }
}

/// The names of `motors` motors (row i of G drives motor i): the task's `motors.names`, else
/// `motor 1` to `motor m`.
pub(super) fn motor_labels(task: &Task, motors: usize) -> Vec<String> {
    match &task.motors.names {
        Some(names) if names.len() == motors => names.clone(),
        _ => (1..=motors).map(|i| format!("motor {i}")).collect(),
    }
}

/// Each of `limits`' finite values, a (lower, upper) pair per curve, as a horizontal line in
/// the curve's colour, labelled `<name> limit` by the curves' `names`.
fn limit_guides(limits: impl IntoIterator<Item = (f64, f64)>, names: &[String]) -> Vec<Guide> {
    let lines = limits
        .into_iter()
        .enumerate()
        .flat_map(|(i, (lo, hi))| [(i, Line::Horizontal(lo)), (i, Line::Horizontal(hi))]);
    Guide::owned(lines, "limit", names)
}

/// The files of the plots of a solve, in the order [`write_plots`] writes them.
pub const PLOT_FILES: [&str; 4] = [
    "joint_positions.svg",
    "joint_torques.svg",
    "motor_torques.svg",
    "tcp_path.svg",
];

/// Every file [`write_plots`] may write for a transmission of `motors` motors:
/// [`PLOT_FILES`], each motor's torque-speed figure, the linkage rows' ratios, and the arm's
/// poses and animation (`poses`).
pub fn every_plot_file(motors: usize) -> Vec<String> {
    let mut files: Vec<String> = PLOT_FILES.map(String::from).to_vec();
    files.extend((0..motors).map(motor_plot_file));
    files.extend(
        [
            LINKAGE_RATIOS_FILE,
            super::poses::POSES_FILE,
            super::poses::MOTION_FILE,
        ]
        .map(String::from),
    );
    files
}

/// Writes the plots of a solve into `folder` ([`PLOT_FILES`]): joint positions and joint
/// torques (named as in the URDF) and motor torques (named as in the task) with each curve's
/// limits in its colour, and the TCP path from its start to its goal in the world plane it moves
/// most in ([`path_plane`]) with the Cartesian box; each motor's operating points in the
/// torque-speed plane within its own limits and envelope, and the linkage rows' ratios over time
/// (`motor_plots`); and the arm in poses along the motion and animated (`poses`). An
/// infeasible design's titles say so, and why ([`plot_title`]).
pub fn write_plots(
    folder: &Path,
    formulation: &Formulation,
    result: &TrajectoryResult,
) -> Result<(), ReportError> {
    crate::store::files::create_folder(folder)?;
    for (name, chart) in charts(formulation, result)? {
        chart.write(&folder.join(name))?;
    }
    super::poses::write_poses(folder, formulation, result)
}

/// The charts [`write_plots`] draws, each with its file's name, in the order it writes them:
/// [`PLOT_FILES`], then each motor's torque-speed figure and the linkage rows' ratios.
pub fn charts(
    formulation: &Formulation,
    result: &TrajectoryResult,
) -> Result<Vec<(String, Chart)>, ReportError> {
    let task = formulation.task();
    let t = &result.trajectory;
    let title = plot_title(formulation, result);
    let joints = joint_labels(formulation, result);
    let motors = motor_labels(task, t.motor_torque.first().map_or(0, Vec::len));
    let charts = [
        joint_positions(formulation, t, &joints, &title),
        joint_torques(formulation, result, &joints, &title)?,
        motor_torques(formulation.motor_torque_limits(), t, &motors, &title),
        tcp_path(task, t, &title),
    ];
    let mut named: Vec<(String, Chart)> = PLOT_FILES
        .map(String::from)
        .into_iter()
        .zip(charts)
        .collect();
    named.extend(motor_charts(formulation, t, (&joints, &motors), &title));
    Ok(named)
}

/// Joint positions over time, rad, with the robot's finite position limits.
fn joint_positions(
    formulation: &Formulation,
    t: &Trajectory,
    joints: &[String],
    title: &str,
) -> Chart {
    let limits = formulation.dynamics().robot().position_limits();
    Chart {
        title: format!("Joint positions: {title}"),
        x_label: "time [s]".into(),
        y_label: joint_axis_label(formulation, "q", "rad", "m"),
        series: per_column(&t.time, &t.q, joints),
        guides: limit_guides(limits.iter().copied(), joints),
        log_y: false,
    }
}

/// Joint torques over the control intervals, N m (N at a prismatic joint), with the joint-space
/// problem's torque box (none for linear limits, a G that changes with the pose, or the
/// actuation-space problem).
fn joint_torques(
    formulation: &Formulation,
    result: &TrajectoryResult,
    joints: &[String],
    title: &str,
) -> Result<Chart, ReportError> {
    let t = &result.trajectory;
    let constant = !formulation.transmission().is_pose_dependent();
    let guides = match formulation.space() {
        Space::Joint if constant => {
            let coupling = formulation.transmission().coupling(&result.ratios)?;
            let limits = formulation.motor_torque_limits();
            match coupling.torque_limits(formulation.modes().torque, limits) {
                JointLimits::Box { lower, upper } => {
                    limit_guides(lower.into_iter().zip(upper), joints)
                }
                JointLimits::Linear { .. } => Vec::new(),
            }
        }
        Space::Joint | Space::Actuation => Vec::new(),
    };
    Ok(Chart {
        title: format!("Joint torques: {title}"),
        x_label: "time [s]".into(),
        y_label: joint_axis_label(formulation, "tau", "N m", "N"),
        series: per_column(&t.time[..t.joint_torque.len()], &t.joint_torque, joints),
        guides,
        log_y: false,
    })
}

/// Motor torques over the control intervals, N m, of the motors named `motors`, with their
/// limits (`limits`, one per motor): lines at -+ each limit, one for motors that share it.
fn motor_torques(limits: &[f64], t: &Trajectory, motors: &[String], title: &str) -> Chart {
    Chart {
        title: format!("Motor torques: {title}"),
        x_label: "time [s]".into(),
        y_label: "tau_u [N m]".into(),
        series: per_column(&t.time[..t.joint_torque.len()], &t.motor_torque, motors),
        guides: limit_guides(limits.iter().map(|&l| (-l, l)), motors),
        log_y: false,
    }
}

/// The TCP's path from its start to its goal in the world plane it moves most in
/// ([`path_plane`]), m, with the task's Cartesian box on those axes.
fn tcp_path(task: &Task, t: &Trajectory, title: &str) -> Chart {
    let (across, up) = path_plane(t);
    let mut edges = Vec::new();
    if let Some(interval) = across.interval(task) {
        edges.extend(interval.range.map(Line::Vertical));
    }
    if let Some(interval) = up.interval(task) {
        edges.extend(interval.range.map(Line::Horizontal));
    }
    let box_guides = edges.into_iter().map(|l| Guide::plain(l, "Cartesian box"));
    Chart {
        title: format!("TCP path: {title}"),
        x_label: format!("world {} [m]", across.name()),
        y_label: format!("world {} [m]", up.name()),
        series: vec![Series::path(
            "TCP",
            across
                .of(t)
                .iter()
                .copied()
                .zip(up.of(t).iter().copied())
                .collect(),
        )],
        guides: box_guides.collect(),
        log_y: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use codesign_core::testing;

    /// A trajectory of `nodes` nodes whose TCP runs through `tcp(s)`, s from 0 to 1, with
    /// `joints` joints and motors.
    fn trajectory(nodes: usize, joints: usize, tcp: impl Fn(f64) -> [f64; 3]) -> Trajectory {
        let s = |k: usize| k as f64 / (nodes - 1) as f64;
        let rows = |n: usize| (0..n).map(|k| vec![s(k); joints]).collect::<Vec<_>>();
        Trajectory {
            time: (0..nodes).map(s).collect(),
            q: rows(nodes),
            v: rows(nodes),
            a: rows(nodes - 1),
            joint_torque: rows(nodes - 1),
            motor_torque: rows(nodes - 1),
            motor_speed: rows(nodes),
            tcp_x: (0..nodes).map(|k| tcp(s(k))[0]).collect(),
            tcp_y: (0..nodes).map(|k| tcp(s(k))[1]).collect(),
            tcp_z: (0..nodes).map(|k| tcp(s(k))[2]).collect(),
            ..Trajectory::default()
        }
    }

    #[test]
    fn the_path_is_drawn_in_the_plane_it_moves_most_in() {
        use crate::report::world::WorldAxis::{X, Y, Z};
        let arc = |s: f64| (std::f64::consts::PI * s).sin_cos();
        // The built-in arm's kind of path: an arc in y-z, x still to a few micrometres.
        let yz = trajectory(21, 4, |s| [4e-6 * s, -arc(s).1, 0.3 * arc(s).0]);
        assert_eq!(path_plane(&yz), (Y, Z));
        // A planar arm swinging in x-z, and one turning in x-y.
        let xz = trajectory(21, 2, |s| [arc(s).1, 0.0, 0.5 * arc(s).0 - 0.2]);
        assert_eq!(path_plane(&xz), (X, Z));
        let xy = trajectory(21, 2, |s| [arc(s).1, 0.4 * arc(s).0, 0.1 + 1e-3 * s]);
        assert_eq!(path_plane(&xy), (X, Y));
        // A file written before tcp_x was recorded, and a path that stands still.
        let mut old = xz.clone();
        old.tcp_x.clear();
        assert_eq!(path_plane(&old), (Y, Z));
        assert_eq!(path_plane(&trajectory(3, 1, |_| [1.0, 2.0, 3.0])), (Y, Z));
    }

    #[test]
    fn the_path_plot_names_its_axes_and_draws_the_box_on_them() {
        let mut task = testing::task();
        let xz = trajectory(11, 2, |s| [s, 0.0, 0.2 * s]);
        let chart = tcp_path(&task, &xz, "planar");
        assert_eq!(
            (chart.x_label.as_str(), chart.y_label.as_str()),
            ("world x [m]", "world z [m]")
        );
        // The task's box bounds y and z: only z shows in the x-z plane, in grey.
        let lines = |chart: &Chart| chart.guides.iter().map(|g| g.line).collect::<Vec<_>>();
        assert_eq!(
            lines(&chart),
            [Line::Horizontal(-0.9), Line::Horizontal(0.6)]
        );
        assert!(chart
            .guides
            .iter()
            .all(|g| g.owners.is_empty() && g.label == "Cartesian box"));
        task.cartesian_box.x = task.cartesian_box.y.clone();
        let chart = tcp_path(&task, &xz, "planar");
        assert_eq!(
            lines(&chart)[..2],
            [Line::Vertical(-1.0), Line::Vertical(0.4)]
        );
        assert_eq!(chart.series[0].points[10], (1.0, 0.2));
        // From its start to its goal, marked.
        assert!(chart.series[0].ends);
        let svg = chart.to_svg().unwrap();
        assert!(svg.contains(">\nstart\n</text>") && svg.contains(">\ngoal\n</text>"));
    }

    #[test]
    fn joints_and_motors_are_named_in_the_plots() {
        let formulation = testing::formulation(0.0, Space::Actuation);
        let t = trajectory(5, 4, |s| [0.0, s, s]);
        let joints = formulation.dynamics().robot().joint_names().to_vec();
        assert_eq!(joints[0], "joint_arm_1");
        let svg = joint_positions(&formulation, &t, &joints, "test")
            .to_svg()
            .unwrap();
        for name in &joints {
            assert!(svg.contains(name.as_str()), "{name} missing");
        }
        assert!(!svg.contains("joint 1"));
        // Each joint's limits in its colour, named after it (the built-in arm's first joint
        // has its own, the others share theirs).
        assert!(svg.contains(">\njoint_arm_1 limit\n</text>"));
        let shared = ">\nlimit of joint_arm_2, joint_arm_3,\n</text>";
        assert!(svg.contains(shared) && svg.contains(">\njoint_arm_4\n</text>"));
        let task = formulation.task();
        let motors = motor_labels(task, 4);
        assert_eq!(motors, ["motor 1", "motor 2", "motor 3", "motor 4"]);
        let svg = motor_torques(formulation.motor_torque_limits(), &t, &motors, "test")
            .to_svg()
            .unwrap();
        for i in 1..=4 {
            assert!(
                svg.contains(&format!(">\nmotor {i}\n</text>")),
                "motor {i} missing"
            );
        }
        // One limit the four share, its legend text wrapped: its second row and motor 4's.
        assert!(svg.contains(">\nlimit of motor 1, motor 2, motor 3,\n</text>"));
        assert_eq!(svg.matches(">\nmotor 4\n</text>").count(), 2);
        // Named as the task names them.
        let mut named = task.clone();
        let names = ["shoulder", "elbow", "wrist 1", "wrist 2"].map(String::from);
        named.motors.names = Some(names.to_vec());
        assert_eq!(motor_labels(&named, 4), names);
        assert_eq!(motor_labels(&named, 3), ["motor 1", "motor 2", "motor 3"]);
        let limits = [1.7, 0.9, 0.9, 0.9];
        let chart = motor_torques(&limits, &t, &names, "test");
        let labels: Vec<&str> = chart.guides.iter().map(|g| g.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "shoulder limit",
                "shoulder limit",
                "limit of elbow, wrist 1, wrist 2",
                "limit of elbow, wrist 1, wrist 2"
            ]
        );
        assert_eq!(chart.guides[0].line, Line::Horizontal(-1.7));
        assert_eq!(chart.guides[0].owners, [0]);
    }
}
