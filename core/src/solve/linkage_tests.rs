//! Solves where G depends on the pose (docs/model.md, section 17), on the planar example with a
//! ball screw or a crank and rod at its elbow: the trajectory read back (motor positions, ratios
//! and speeds) against the screw's geometry computed here independently, the power balance through G(q) at every node, dJ*/dr
//! against differences of re-solved problems, and a linkage that cannot close named.

use super::tests::assert_matches_differences;
use super::{solve_design, solve_design_from, SolveSettings, TrajectoryResult};
use crate::model::task::{LimitMode, LimitModes, PerMotor, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing::{self, ankle_task, posed_task, CRANK_ROW, SCREW_ROW, STROKED_SCREW_ROW};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::TAU;

/// The formulation of linkage `row` on the planar example's elbow in `space`, modes `exact`.
fn formulation(row: &str, space: Space) -> Formulation {
    exact_formulation(&posed_task(row), space)
}

/// The formulation of `task` in `space`, modes `exact`.
fn exact_formulation(task: &Task, space: Space) -> Formulation {
    let robot = Robot::load(task).unwrap();
    let modes = LimitModes {
        torque: LimitMode::Exact,
        speed: LimitMode::Exact,
    };
    Formulation::new(task, robot, space, modes).unwrap()
}

/// The ratio d(motor angle)/dq of the screw of [`SCREW_ROW`] at elbow angle q (rad) with lead
/// `lead` (m), from the planar example's geometry: the anchors 0.15 m behind the elbow on the
/// upper arm and 0.10 m across it on the forearm (about -y) are (0.15 - 0.1 sin q, 0, 0.1 cos q)
/// apart, so L^2 = 0.0325 - 0.03 sin q and dL/dq = -0.015 cos q / L.
fn screw_ratio(q: f64, lead: f64) -> f64 {
    let length = (0.0325 - 0.03 * q.sin()).sqrt();
    TAU / lead * (-0.015 * q.cos() / length)
}

/// sum_i tau_u,i qd_u,i = sum_j tau_j qd_j at every node k < N of `result`, to 1e-8 of the
/// larger power: the motor torques, motor speeds and joint torques read back share G(q_k).
pub(super) fn assert_power_balances(result: &TrajectoryResult) {
    let t = &result.trajectory;
    for k in 0..t.motor_torque.len() {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let motors = dot(&t.motor_torque[k], &t.motor_speed[k]);
        let joints = dot(&t.joint_torque[k], &t.v[k]);
        let scale = motors.abs().max(joints.abs()).max(1e-300);
        assert!(
            (motors - joints).abs() <= 1e-8 * scale,
            "node {k}: motors {motors} W, joints {joints} W"
        );
    }
}

#[test]
fn a_screw_drives_the_elbow_as_its_geometry_says_and_balances_power() {
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(SCREW_ROW, space);
        let result = solve_design(&f, &[50.0, 12.0], &testing::settings()).unwrap();
        assert!(
            result.feasible,
            "{space}: {} {:?}",
            result.status, result.reason
        );
        assert_power_balances(&result);
        let t = &result.trajectory;
        for (k, (q, v)) in t.q.iter().zip(&t.v).enumerate() {
            let length = (0.0325 - 0.03 * q[1].sin()).sqrt();
            let angle = TAU * length / 0.012;
            let position = t.motor_position[k][1];
            assert!(
                (position - angle).abs() <= 1e-12 * angle,
                "{position} against {angle}"
            );
            assert_eq!(t.motor_position[k][0], 50.0 * q[0]);
            assert_eq!(t.ratio[k][0], [50.0, 0.0]);
            let ratio = screw_ratio(q[1], 0.012);
            assert!((t.ratio[k][1][1] - ratio).abs() <= 1e-9 * ratio.abs());
            let speeds = &t.motor_speed[k];
            let screw = screw_ratio(q[1], 0.012) * v[1];
            assert!((speeds[0] - 50.0 * v[0]).abs() <= 1e-12 * (1.0 + speeds[0].abs()));
            assert!(
                (speeds[1] - screw).abs() <= 1e-9 * (1.0 + screw.abs()),
                "{space} node {k}: {} rad/s against {screw} from the geometry",
                speeds[1]
            );
        }
        let peak = result.max_motor_speed;
        assert!(peak <= 250.0 * (1.0 + 1e-6), "{space}: {peak} rad/s");
    }
}

#[test]
fn a_crank_rod_solve_balances_power() {
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(CRANK_ROW, space);
        let result = solve_design(&f, &[50.0, 12.0], &testing::settings()).unwrap();
        assert!(
            result.feasible,
            "{space}: {} {:?}",
            result.status, result.reason
        );
        assert_power_balances(&result);
    }
}

/// Solves `f` at `ratios` (tol 1e-11), asserts a feasible result whose dJ*/dr matches central
/// differences of problems re-solved from its optimum (a non-convex problem has other local
/// optima nearby, which a cold start may reach), and returns the result.
pub(super) fn assert_cost_gradient_at(
    f: &Formulation,
    ratios: &[f64],
    label: &str,
) -> TrajectoryResult {
    let settings = SolveSettings {
        tol: 1e-11,
        ..testing::settings()
    };
    let (result, solution) = solve_design_from(f, ratios, &settings, None).unwrap();
    assert!(
        result.feasible,
        "{label} {ratios:?}: {} {:?}",
        result.status, result.reason
    );
    let gradient = result.cost_gradient.clone().unwrap();
    assert_matches_differences(label, &gradient, ratios, |r| {
        let (near, _) = solve_design_from(f, r, &settings, Some(&solution)).unwrap();
        near.cost
    });
    result
}

/// dJ*/dr with respect to the first motor's ratio and the screw's lead, against central
/// differences of problems re-solved from the optimum, at three interior designs in both spaces.
#[test]
fn a_screws_cost_gradient_matches_differences() {
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(SCREW_ROW, space);
        // Not [25, 20]: its optimum passes the screw's dead point at pi/2 between two nodes.
        for design in [[40.0, 14.0], [70.0, 9.0], [30.0, 16.0]] {
            assert_cost_gradient_at(&f, &design, &format!("{space} screw"));
        }
    }
}

/// A screw's stroke held at every node: the free motion swings the elbow past the goal to a
/// screw of 0.055 m; with the stroke [0.08, 0.25] m it keeps within, binding, and dJ*/dr still
/// matches differences of re-solved problems (the lead, a design parameter, scales the length
/// the row holds).
#[test]
fn a_screws_stroke_is_held_and_its_cost_gradient_matches_differences() {
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(STROKED_SCREW_ROW, space);
        let label = format!("{space} stroked screw");
        let result = assert_cost_gradient_at(&f, &[60.0, 10.0], &label);
        let lengths = result
            .trajectory
            .motor_position
            .iter()
            .map(|p| p[1] * 0.010 / TAU);
        let shortest = lengths.fold(f64::INFINITY, f64::min);
        assert!(
            (shortest - 0.08).abs() < 1e-6,
            "{space}: the stroke binds at 0.08 m, not {shortest}"
        );
    }
}

/// The ankle example (two crank-rods over the pitch and the roll): solved in both spaces with the
/// power balanced at every node, and dJ*/dr in actuation space against differences of re-solved
/// problems at three interior designs (crank radius, rod attachment, crank reduction).
#[test]
fn an_ankles_cost_gradient_matches_differences() {
    let settings = SolveSettings {
        tol: 1e-11,
        ..testing::settings()
    };
    let task = ankle_task();
    for space in [Space::Actuation, Space::Joint] {
        let f =
            Formulation::new(&task, Robot::load(&task).unwrap(), space, task.limit_modes).unwrap();
        let result = solve_design(&f, &task.transmission.original, &settings).unwrap();
        assert!(result.feasible, "{space}: {}", result.status);
        assert_power_balances(&result);
    }
    let f = Formulation::new(
        &task,
        Robot::load(&task).unwrap(),
        Space::Actuation,
        task.limit_modes,
    )
    .unwrap();
    for ratios in [[60.0, 60.0, 15.0], [45.0, 75.0, 8.0], [70.0, 50.0, 25.0]] {
        assert_cost_gradient_at(&f, &ratios, "ankle");
    }
}

/// The four-bar example (`four_bar.json`: crank radius and reduction as design parameters): dJ*/dr
/// in actuation space against differences of re-solved problems at three interior designs.
#[test]
fn a_four_bars_cost_gradient_matches_differences() {
    let path = crate::testing::repository().join("robots/examples/planar_2dof/four_bar.json");
    let task = crate::model::task::Task::load(&path).unwrap();
    let robot = Robot::load(&task).unwrap();
    let f = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
    // Not [40, 70, 15]: its optimum passes the crank's dead point between two nodes.
    for ratios in [[50.0, 60.0, 10.0], [60.0, 75.0, 12.0], [70.0, 85.0, 30.0]] {
        assert_power_balances(&assert_cost_gradient_at(&f, &ratios, "four-bar"));
    }
}

/// A rod too short to reach the crank pin at the motion's start: the design is refused,
/// naming the motor, its row and what its loop lacks.
#[test]
fn a_rod_that_cannot_close_is_named() {
    let short = CRANK_ROW.replace("\"rod_m\": 0.2", "\"rod_m\": 0.05");
    let f = formulation(&short, Space::Actuation);
    let error = f.problem(&[50.0, 12.0]).unwrap_err().to_string();
    assert!(
        error.starts_with("at the start, the linkage of motor 2 (transmission.matrix[1]): its rod"),
        "{error}"
    );
}

/// The planar example with its elbow on the ball screw and motors of rotor inertia, friction
/// and a torque-speed envelope (no-load speed 400 rad/s), in `space`, with transmissions of
/// efficiency `efficiency` (None: lossless).
fn screw_with_motor_dynamics(space: Space, efficiency: Option<[f64; 2]>) -> Formulation {
    let mut task = posed_task(SCREW_ROW);
    task.motors.rotor_inertia_kgm2 = Some(PerMotor::Each(vec![2e-5, 3e-5]));
    task.motors.viscous_friction_nm_s_per_rad = Some(PerMotor::Each(vec![1e-4, 2e-4]));
    task.motors.no_load_speed_rad_s = Some(PerMotor::Each(vec![400.0, 400.0]));
    task.motors.efficiency = efficiency.map(|each| PerMotor::Each(each.to_vec()));
    exact_formulation(&task, space)
}

/// With rotor inertia and losses, the joint torques read back are what the links take: the
/// inverse dynamics of the trajectory, the motors' G(q)^T (J_m (G a + dG/dt v) + B_m G v) and
/// the losses' G(q)^T L taken off the controls' torques at every node (to the solver's
/// tolerance).
#[test]
fn a_screw_with_rotor_inertia_and_losses_reads_back_the_links_torques() {
    for space in [Space::Actuation, Space::Joint] {
        let f = screw_with_motor_dynamics(space, Some([0.9, 0.8]));
        let settings = SolveSettings {
            tol: 1e-10,
            ..testing::settings()
        };
        let result = solve_design(&f, &[50.0, 12.0], &settings).unwrap();
        assert!(result.feasible, "{space}: {}", result.status);
        let t = &result.trajectory;
        let dynamics = f.dynamics();
        let mut data = dynamics.workspace();
        let mut tau = vec![0.0; 2];
        for k in 0..t.joint_torque.len() {
            dynamics.rnea(&mut data, &t.q[k], &t.v[k], &t.a[k], &mut tau);
            for (read, rnea) in t.joint_torque[k].iter().zip(&tau) {
                assert!(
                    (read - rnea).abs() <= 1e-7 * (1.0 + rnea.abs()),
                    "{space} node {k}: {read} N m read back, {rnea} N m by RNEA"
                );
            }
        }
    }
}

/// dJ*/dr with rotor inertia, friction and the envelope through the screw, against differences.
#[test]
fn a_screws_cost_gradient_with_motor_dynamics_matches_differences() {
    for space in [Space::Actuation, Space::Joint] {
        let f = screw_with_motor_dynamics(space, None);
        assert_cost_gradient_at(&f, &[40.0, 14.0], &format!("{space} screw with motors"));
    }
}

/// dJ*/dr with lossy transmissions (the belt's and the screw's), against differences at two
/// designs, and each motor's loss read back as the efficiency gives it where it drives its load
/// fast. (At some designs, such as (40, 14) and (70, 9) in the actuation space, a solve warm
/// started from the cold solve's optimum at the same design finds another optimum 0.007 to
/// 0.02 lower in J nearby: the differences of re-solved problems then measure that jump, while
/// cold re-solves at (40 +- 1e-4, 14) give dJ*/dr1 to 5 digits.)
#[test]
fn a_screws_cost_gradient_with_losses_matches_differences() {
    let efficiency = [0.9, 0.8];
    for space in [Space::Actuation, Space::Joint] {
        let mut task = posed_task(SCREW_ROW);
        task.motors.efficiency = Some(PerMotor::Each(efficiency.to_vec()));
        let f = exact_formulation(&task, space);
        let label = format!("{space} lossy screw");
        assert_cost_gradient_at(&f, &[25.0, 20.0], &label);
        let result = assert_cost_gradient_at(&f, &[40.0, 12.0], &label);
        let t = &result.trajectory;
        let mut driving = 0;
        for k in 0..t.transmission_loss.len() {
            // t = G(q_k)^-T tau, the torques the transmissions pass.
            let g = DMatrix::from_fn(2, 2, |i, j| t.ratio[k][i][j]);
            let tau = DVector::from_column_slice(&t.joint_torque[k]);
            let transmitted = g.transpose().lu().solve(&tau).unwrap();
            for i in 0..2 {
                let (w, passed) = (t.motor_speed[k][i], transmitted[i]);
                if w * passed > 0.0 && w.abs() > 40.0 && passed.abs() > 0.05 {
                    let expected = (1.0 / efficiency[i] - 1.0) * passed;
                    let loss = t.transmission_loss[k][i];
                    assert!(
                        (loss - expected).abs() < 0.01 * expected.abs(),
                        "{loss} {expected}"
                    );
                    driving += 1;
                }
            }
        }
        assert!(driving > 0, "{space}: no motor drives its load fast");
    }
}

/// The planar example's ball screw with its forearm anchor on the forearm's axis, [0.1, 0, 0]:
/// its ratio falls to zero at an elbow of 0, which the 10-step optimum crosses between two
/// nodes (G's elbow entry from 6.1 to -17.3). Its result was feasible; it is infeasible now,
/// saying where the linkage passes its dead point.
#[test]
fn a_screw_that_passes_its_dead_point_between_two_nodes_is_infeasible() {
    let path = testing::repository().join("robots/examples/planar_2dof/ball_screw.json");
    let mut task = Task::load(&path).unwrap();
    task.motion.steps = 10;
    task.transmission.matrix[1] = serde_json::from_str(
        r#"{"linear": {"from": {"link": "upper_arm", "point": [0.15, 0, 0]},
            "to": {"link": "forearm", "point": [0.1, 0, 0]}, "lead_m": "0.001*r2"}}"#,
    )
    .unwrap();
    let f = exact_formulation(&task, Space::Actuation);
    let result = solve_design(&f, &[50.0, 12.0], &testing::settings()).unwrap();
    assert!(!result.feasible, "{:?}", result.dead_points);
    let crossing = &result.dead_points[0];
    assert_eq!(crossing.motors, [1]);
    let elbow = |k: usize| result.trajectory.q[k][1];
    assert!(elbow(crossing.node) * elbow(crossing.node + 1) < 0.0);
    let reason = result.reason.clone().unwrap_or_default();
    assert!(
        reason.contains("the linkage of motor 2 passes a dead point there"),
        "{reason}"
    );
    assert_eq!(result.unjudged(), None);
}
