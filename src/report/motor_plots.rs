//! The plots of a solve that follow the motors (`codesign solve --plot`, beside
//! `trajectory.rs`'s): each motor's torque against its speed within its own limits, one figure
//! per motor, and the ratios of the linkage rows, G(q) over time.

use super::plots::{Chart, Guide, Line, Series};
use codesign_core::problem::Formulation;
use codesign_core::solve::Trajectory;
use codesign_core::text::number;

/// The file of motor `motor`'s torque-speed figure (0-based: `motor_1_torque_speed.svg` for the
/// first row of G).
pub fn motor_plot_file(motor: usize) -> String {
    format!("motor_{}_torque_speed.svg", motor + 1)
}

/// The file of the linkage rows' ratios over time, written where the transmission changes with
/// the pose.
pub const LINKAGE_RATIOS_FILE: &str = "linkage_ratios.svg";

/// One torque-speed figure per motor ([`motor_plot_file`]) and, where the transmission has
/// linkage rows, their ratios over time ([`LINKAGE_RATIOS_FILE`]), each with its file's name,
/// for the trajectory `t` solved for `formulation`, its joints and motors named `names`, every
/// title ending in `title`.
pub(super) fn motor_charts(
    formulation: &Formulation,
    t: &Trajectory,
    names: (&[String], &[String]),
    title: &str,
) -> Vec<(String, Chart)> {
    let (joints, motors) = names;
    let task = formulation.task();
    let torque_limits = formulation.motor_torque_limits();
    let speed_limits = task.motors.speed_limit_rad_s.values(motors.len());
    let envelope = formulation.envelope();
    let mut charts = Vec::new();
    for (motor, name) in motors.iter().enumerate() {
        let limits = MotorLimits {
            torque_nm: torque_limits[motor],
            speed_rad_s: speed_limits[motor],
            no_load_rad_s: envelope.map(|e| e.no_load_speed(motor)),
        };
        let chart = motor_torque_speed(motor, name, &limits, t, title);
        charts.push((motor_plot_file(motor), chart));
    }
    if let Some(chart) = linkage_ratios(formulation, t, (joints, motors), title) {
        charts.push((LINKAGE_RATIOS_FILE.to_owned(), chart));
    }
    charts
}

/// One motor's limits: its torque limit tau_max (N m), its speed limit (rad/s) and, where the
/// task gives its torque-speed envelope |tau_u| <= tau_max (1 - |w| / w_0), its no-load speed
/// w_0 (rad/s).
struct MotorLimits {
    torque_nm: f64,
    speed_rad_s: f64,
    no_load_rad_s: Option<f64>,
}

/// Motor `motor`'s (named `name`) operating points (speed w_k, torque tau_u,k) at the nodes
/// k < N, from start to goal, within its torque limits -+tau_max, its speed limits -+w_max
/// and, where given, its torque-speed envelope drawn as a diamond.
fn motor_torque_speed(
    motor: usize,
    name: &str,
    limits: &MotorLimits,
    t: &Trajectory,
    title: &str,
) -> Chart {
    let points = t.motor_torque.iter().zip(&t.motor_speed);
    let points = points.map(|(torque, speed)| (speed[motor], torque[motor]));
    let (tau, w) = (limits.torque_nm, limits.speed_rad_s);
    let torque_label = format!("torque limit -+{} N m", number(tau));
    let speed_label = format!("speed limit -+{} rad/s", number(w));
    let mut guides = vec![
        Guide::plain(Line::Horizontal(-tau), &torque_label),
        Guide::plain(Line::Horizontal(tau), torque_label),
        Guide::plain(Line::Vertical(-w), &speed_label),
        Guide::plain(Line::Vertical(w), speed_label),
    ];
    if let Some(w0) = limits.no_load_rad_s {
        let corners = [(w0, 0.0), (0.0, tau), (-w0, 0.0), (0.0, -tau)];
        let label = format!("torque-speed envelope (no-load speed {} rad/s)", number(w0));
        guides.extend((0..4).map(|i| Guide {
            line: Line::Segment(corners[i], corners[(i + 1) % 4]),
            owners: vec![0],
            label: label.clone(),
        }));
    }
    Chart {
        title: format!("Motor torque against motor speed, {name}: {title}"),
        x_label: "w [rad/s]".into(),
        y_label: "tau_u [N m]".into(),
        series: vec![Series::path(name, points.collect())],
        guides,
        log_y: false,
    }
}

/// The entries G_ij(q) of the linkage rows over the nodes, one curve per motor i and joint j
/// its linkage moves (where it is not zero at every node), named by `names` (joints, motors);
/// None for a transmission without linkage rows or a trajectory that does not record G(q).
fn linkage_ratios(
    formulation: &Formulation,
    t: &Trajectory,
    (joints, motors): (&[String], &[String]),
    title: &str,
) -> Option<Chart> {
    let rows = formulation.transmission().linkages();
    if rows.is_empty() || t.ratio.len() != t.time.len() {
        return None;
    }
    let mut series = Vec::new();
    for row in rows {
        for joint in row.joints() {
            let values: Vec<f64> = t.ratio.iter().map(|g| g[row.motor][joint]).collect();
            if values.iter().all(|&g| g == 0.0) {
                continue;
            }
            let name = format!("G[{}, {}]", motors[row.motor], joints[joint]);
            series.push(Series::line(
                name,
                t.time.iter().copied().zip(values).collect(),
            ));
        }
    }
    Some(Chart {
        title: format!("Ratios of the linkage rows, G(q) over time: {title}"),
        x_label: "time [s]".into(),
        y_label: "G_ij = dq_u,i / dq_j [rad/rad; rad/m at a prismatic joint]".into(),
        series,
        guides: Vec::new(),
        log_y: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use codesign_core::problem::Space;
    use codesign_core::testing;

    /// A trajectory of 5 nodes of two motors, motor 2's speed -30 rad/s at node 2.
    fn trajectory() -> Trajectory {
        let rows = |n: usize| (0..n).map(|k| vec![0.1 * k as f64; 2]).collect::<Vec<_>>();
        let mut t = Trajectory {
            time: (0..5).map(|k| 0.25 * k as f64).collect(),
            motor_torque: rows(4),
            motor_speed: rows(5),
            ..Trajectory::default()
        };
        t.motor_speed[2][1] = -30.0;
        t
    }

    #[test]
    fn each_motor_is_drawn_within_its_own_limits_and_envelope() {
        let t = trajectory();
        let limits = MotorLimits {
            torque_nm: 1.7,
            speed_rad_s: 40.0,
            no_load_rad_s: None,
        };
        let chart = motor_torque_speed(1, "elbow", &limits, &t, "test");
        // Motor torque over interval k against motor speed at node k, k < N, start to goal.
        assert_eq!(chart.series.len(), 1);
        assert_eq!(chart.series[0].points.len(), 4);
        assert_eq!(chart.series[0].points[2], (-30.0, 0.2));
        assert!(chart.series[0].ends);
        let lines: Vec<Line> = chart.guides.iter().map(|g| g.line).collect();
        assert_eq!(
            lines,
            [
                Line::Horizontal(-1.7),
                Line::Horizontal(1.7),
                Line::Vertical(-40.0),
                Line::Vertical(40.0)
            ]
        );
        let svg = crate::report::plots::Figure::to_svg(&chart).unwrap();
        for text in ["elbow", "torque limit -+1.7 N m", "speed limit -+40 rad/s"] {
            assert!(svg.contains(&format!(">\n{text}\n</text>")), "{text}");
        }
        // With an envelope: its diamond through (-+w_0, 0) and (0, -+tau_max), in the motor's
        // colour.
        let enveloped = MotorLimits {
            no_load_rad_s: Some(50.0),
            ..limits
        };
        let chart = motor_torque_speed(1, "elbow", &enveloped, &t, "test");
        assert_eq!(chart.guides.len(), 8);
        assert_eq!(chart.guides[4].line, Line::Segment((50.0, 0.0), (0.0, 1.7)));
        assert_eq!(chart.guides[4].owners, [0]);
        assert_eq!(
            chart.guides[7].label,
            "torque-speed envelope (no-load speed 50 rad/s)"
        );
    }

    #[test]
    fn only_a_transmission_with_linkage_rows_has_its_ratios_drawn() {
        let formulation = testing::formulation(0.0, Space::Actuation);
        let names = ["a".to_owned(), "b".to_owned()];
        let mut t = trajectory();
        assert!(linkage_ratios(&formulation, &t, (&names, &names), "test").is_none());
        t.ratio = vec![vec![vec![1.0, 0.0], vec![0.0, 2.0]]; 5];
        assert!(linkage_ratios(&formulation, &t, (&names, &names), "test").is_none());
    }
}
