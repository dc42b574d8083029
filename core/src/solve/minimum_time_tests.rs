//! dT*/dr of the pure minimum-time problem (docs/model.md, section 6): the envelope theorem's
//! dJ*/dr with J = T, against central differences of re-solved problems, each re-solve started
//! from the solution at the design itself so that every difference follows one local optimum.
//!
//! The re-solves start with a small barrier parameter (`mu_init` 1e-9): from IPOPT's default 0.1
//! the barrier outweighs J = T (about 0.5 s), and a re-solve from the solution itself takes as
//! many iterations as a cold one (about 100) and may end on another local optimum (measured at
//! r = (7, 4, 2, 2): 0.53029 s, re-solved 0.53076 s; its neighbours 1e-4 away down to 0.52774
//! s); from 1e-9 each takes 7 to 11 iterations and stays on the design's optimum.

use super::tests::assert_matches_differences;
use super::{solve_design_from, SolveSettings};
use crate::model::task::{LimitMode, LimitModes, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;

/// Checks dT*/dr of `task`'s pure minimum-time problem in `space` with `modes` at `ratios` (a
/// feasible design) against re-solved central differences, to 1e-4 relative to its largest
/// entry: both sides are divided by that entry before the shared check.
fn assert_time_gradient(task: &Task, space: Space, modes: LimitModes, ratios: &[f64]) {
    let settings = SolveSettings {
        tol: 1e-11,
        ..testing::settings()
    };
    let pure = task.minimum_time();
    let robot = Robot::load(&pure).unwrap();
    let formulation = Formulation::new(&pure, robot, space, modes).unwrap();
    let (result, solution) = solve_design_from(&formulation, ratios, &settings, None).unwrap();
    assert!(result.feasible, "{space} {ratios:?}: {}", result.status);
    assert_eq!(result.horizon_s, Some(result.cost), "J* = T*");
    let gradient = result.cost_gradient.clone().unwrap();
    let mut warm = settings.clone();
    warm.options
        .insert("mu_init".into(), serde_json::json!(1e-9));
    let scale = gradient.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0, "{space} {ratios:?}: dT*/dr = 0");
    let scaled: Vec<f64> = gradient.iter().map(|g| g / scale).collect();
    let label = format!("T* in {space} {:?}/{:?}", modes.torque, modes.speed);
    assert_matches_differences(&label, &scaled, ratios, |r| {
        let (result, _) = solve_design_from(&formulation, r, &warm, Some(&solution)).unwrap();
        assert!(result.feasible, "{label} {r:?}: {}", result.status);
        result.cost / scale
    });
}

/// The built-in arm at 0 kg, at three interior designs in each space (the
/// actuation space under the task's modes, the joint space under `interval` torques and `exact`
/// speeds, whose bounds have no kink at 0).
#[test]
fn the_minimum_times_gradient_matches_resolved_differences_on_the_arm() {
    let mut task = testing::task();
    task.payload.mass_kg = 0.0;
    let joint = LimitModes {
        torque: LimitMode::Interval,
        speed: LimitMode::Exact,
    };
    let designs = [
        [7.0, 4.0, 2.0, 2.0],
        [6.0, 3.0, 1.5, 1.5],
        [8.0, 5.0, 2.5, 2.0],
    ];
    for (space, modes) in [(Space::Actuation, task.limit_modes), (Space::Joint, joint)] {
        for ratios in designs {
            assert_time_gradient(&task, space, modes, &ratios);
        }
    }
}

/// The planar example's ball screw at its elbow (`robots/examples/planar_2dof/ball_screw.json`,
/// a linkage: G depends on the pose) at a design inside its box, actuation space.
#[test]
fn the_minimum_times_gradient_matches_resolved_differences_on_a_ball_screw() {
    let path = testing::repository().join("robots/examples/planar_2dof/ball_screw.json");
    let task = Task::load(&path).unwrap();
    let modes = task.limit_modes;
    assert_time_gradient(&task, Space::Actuation, modes, &[40.0, 15.0]);
}

/// The built-in arm at 0 kg with a TCP via point within a window, [0.1, 0.2] s (its time a
/// variable of the problem, as T is): the TCP point of the straight joint path a quarter of the
/// way, 3 cm higher. dT*/dr keeps its form (no row that depends on r reads a via time), and
/// matches re-solved differences in the actuation space.
#[test]
fn the_minimum_times_gradient_matches_resolved_differences_with_a_via_window() {
    use crate::model::task::{TcpVia, Via, ViaTime};
    let mut task = testing::task();
    task.payload.mass_kg = 0.0;
    let (start, goal) = (&task.motion.start, task.motion.goal.joints().unwrap());
    let pose: Vec<f64> = (start.iter().zip(goal))
        .map(|(s, g)| 0.75 * s + 0.25 * g)
        .collect();
    let dynamics = crate::dynamics::Dynamics::new(Robot::load(&task).unwrap());
    let point = dynamics.tcp_position(&mut dynamics.workspace(), &pose);
    task.motion.via = vec![Via::Tcp(TcpVia {
        time: ViaTime::Within([0.1, 0.2]),
        tcp: (point + nalgebra::Vector3::new(0.0, 0.0, 0.03)).into(),
        tol_m: 0.01,
    })];
    let modes = task.limit_modes;
    assert_time_gradient(&task, Space::Actuation, modes, &[7.0, 4.0, 2.0, 2.0]);
}

/// Issue 52's first test of done: on the built-in arm (actuation space, original design, pure
/// minimum time) at 0 and 1 kg, T* shortened by the fixed-horizon rule (`free_horizon` =
/// `descend`, shaped by the task's weights and box) is no longer than the shortest duration a
/// bisection to 1 ms of the fixed-horizon rule finds feasible (`codesign solve --space actuation
/// --payload P --duration T` on the repository's task: 0.5408 s at 0 kg, 0.7131 s at 1 kg; the
/// standard guess alone gives 0.5541 s and 0.7381 s), and at 0.97 T* the fixed-horizon rule
/// finds no feasible trajectory.
#[test]
fn the_shortened_minimum_time_is_no_longer_than_the_fixed_horizon_bisection() {
    use crate::model::task::Horizon;
    let settings = SolveSettings {
        free_horizon: super::FreeHorizonSearch::Descend,
        ..SolveSettings::default()
    };
    for (payload_kg, bisected_s) in [(0.0, 0.5408), (1.0, 0.7131)] {
        let mut task = Task::built_in().unwrap();
        task.payload.mass_kg = payload_kg;
        let ratios = task.transmission.original.clone();
        let pure = task.minimum_time();
        let robot = Robot::load(&pure).unwrap();
        let free = Formulation::new(&pure, robot.clone(), Space::Actuation, task.limit_modes)
            .unwrap()
            .shaped_by(&task);
        let (result, _) = solve_design_from(&free, &ratios, &settings, None).unwrap();
        let t_star = result.horizon_s.unwrap();
        assert!(result.feasible && result.cost == t_star, "{payload_kg} kg");
        assert!(t_star <= bisected_s, "{payload_kg} kg: T* = {t_star} s");
        let mut shorter = task.clone();
        shorter.motion.horizon = Horizon::Fixed(0.97 * t_star);
        let fixed = Formulation::new(&shorter, robot, Space::Actuation, task.limit_modes).unwrap();
        let (verdict, _) = solve_design_from(&fixed, &ratios, &settings, None).unwrap();
        assert!(
            !verdict.feasible,
            "{payload_kg} kg: feasible at 0.97 T* = {}",
            0.97 * t_star
        );
    }
}
