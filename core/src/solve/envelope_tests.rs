//! Tests of the torque-speed envelope (`motors.no_load_speed_rad_s`) through whole solves:
//! where it binds, dJ*/dr against differences of re-solved problems, the elastic kind's
//! relaxation of it, and its violation family.

use super::run::{solve_once, Start};
use super::tests::{assert_cost_gradient, assert_matches_differences, with_motor_terms};
use super::{least_envelope_margin, solve_design, solve_design_from, SolveSettings};
use crate::ipopt::Solution;
use crate::model::task::{LimitMode, LimitModes, PerMotor, Task};
use crate::model::Robot;
use crate::problem::tests::envelope_row;
use crate::problem::{penalty_weights, FamilyId, Formulation, Space};
use crate::testing;
use crate::transmission::Side;

/// The repository's task carrying `payload` kg, with motors of no-load speed `no_load` rad/s.
fn with_envelope(task: &Task, payload: f64, no_load: f64) -> Task {
    let mut task = task.clone();
    task.payload.mass_kg = payload;
    task.motors.no_load_speed_rad_s = Some(PerMotor::All(no_load));
    task
}

/// dJ*/dr with every motor term set (rotor inertia, friction, envelope) against central
/// differences of re-solved problems, at three feasible designs where the envelope binds over
/// a stretch of the motion at tens of rad/s (its multipliers weigh c dG v): actuation space,
/// and joint space with box and with exact torque limits.
#[test]
fn cost_gradient_with_the_envelope_matches_differences() {
    let cases = [
        (
            Space::Actuation,
            1.0,
            250.0,
            LimitMode::Paper,
            LimitMode::Exact,
            [7.0, 4.0, 2.0, 2.0],
        ),
        (
            Space::Joint,
            0.0,
            250.0,
            LimitMode::Interval,
            LimitMode::Exact,
            [6.5, 3.5, 1.5, 1.2],
        ),
        (
            Space::Joint,
            0.0,
            150.0,
            LimitMode::Exact,
            LimitMode::Paper,
            [8.0, 4.0, 2.0, 2.5],
        ),
    ];
    let settings = testing::settings();
    for (space, payload, no_load, torque, speed, ratios) in cases {
        let task = with_envelope(&with_motor_terms(&testing::task()), payload, no_load);
        let modes = LimitModes { torque, speed };
        let robot = Robot::load(&task).unwrap();
        let formulation = Formulation::new(&task, robot, space, modes).unwrap();
        let result = solve_design(&formulation, &ratios, &settings).unwrap();
        let least = least_envelope_margin(&formulation, &result.trajectory).unwrap();
        let speed = result.trajectory.motor_speed[least.node][least.motor];
        assert!(
            least.margin_nm.abs() < 1e-6 && speed.abs() > 1.0,
            "{space} {ratios:?}: the envelope does not bind ({least:?}, speed {speed})"
        );
        assert_cost_gradient(&task, space, modes, ratios);
    }
}

/// Where the envelope binds and the hard problem is feasible, the elastic problem finds the
/// same solution with no slack (its speed slacks relax the envelope too, and the penalty stays
/// exact); where no trajectory fits in it, the elastic problem is still solved, the design is
/// infeasible, and the result reports by how much the motors exceed it.
#[test]
fn the_elastic_problem_relaxes_the_envelope_exactly() {
    let settings = testing::settings();
    let task = with_envelope(&testing::task(), 0.5, 200.0);
    let robot = Robot::load(&task).unwrap();
    let hard = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
    let original = hard.transmission().original().to_vec();
    let [hard_result, elastic_result] =
        [hard.clone(), hard.elastic()].map(|f| solve_design(&f, &original, &settings).unwrap());
    assert!(hard_result.feasible && elastic_result.feasible);
    let least = least_envelope_margin(&hard, &hard_result.trajectory).unwrap();
    assert!(least.margin_nm.abs() < 1e-6, "{least:?}");
    let relative = (elastic_result.cost - hard_result.cost).abs() / hard_result.cost;
    assert!(
        relative < 1e-6,
        "{} vs {}",
        elastic_result.cost,
        hard_result.cost
    );
    let violation = hard_result.violations.get("motor_envelope").unwrap();
    assert!(violation <= 1e-6, "{violation:e}");
    let slow = with_envelope(&testing::task(), 0.5, 40.0);
    let robot = Robot::load(&slow).unwrap();
    let elastic = Formulation::new(&slow, robot, Space::Actuation, slow.limit_modes)
        .unwrap()
        .elastic();
    let result = solve_design(&elastic, &original, &settings).unwrap();
    let measures = result.elastic.as_ref().unwrap();
    assert!(result.status == "Solve_Succeeded" && !result.feasible);
    assert!(measures.speed_excess > 0.0, "{measures:?}");
    assert!(
        result
            .reason
            .as_ref()
            .unwrap()
            .contains("torque-speed envelope"),
        "{:?}",
        result.reason
    );
    assert!(result.violations.get("motor_envelope").unwrap() > 0.1);
    let without = testing::formulation(0.5, Space::Actuation);
    let ideal = solve_design(&without, &original, &settings).unwrap();
    assert_eq!(ideal.violations.get("motor_envelope"), None);
    assert!(ideal.cost < hard_result.cost);
}

/// The elastic kind's d(penalised objective)/dr where its speed slacks relax the envelope,
/// under a box speed mode (whose slacks are joint speeds, seen by the envelope rows through
/// G(r)) and under mode `exact`, against differences of re-solved problems. Each is one solve
/// of the elastic problem: the verdict's further starts on the hard problem, which this design
/// fails after 600 to 900 iterations each, have no part in the gradient (and made this test
/// take 46 s).
#[test]
fn elastic_objective_gradient_with_the_envelope_matches_differences() {
    let settings = SolveSettings {
        tol: 1e-10,
        ..testing::settings()
    };
    for (speed, no_load) in [(LimitMode::Interval, 60.0), (LimitMode::Exact, 40.0)] {
        let task = with_envelope(&testing::task(), 0.5, no_load);
        let ratios = [6.0, 3.0, 1.5, 1.5];
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            speed,
            ..task.limit_modes
        };
        let formulation = Formulation::new(&task, robot, Space::Actuation, modes)
            .unwrap()
            .elastic();
        let solve = |r: &[f64], warm: Option<&Solution>| {
            let start = warm.map_or(Start::Guess, Start::Warm);
            let (result, solution) = solve_once(&formulation, r, &settings, start).unwrap();
            assert!(solution.status.is_success(), "{r:?}: {}", result.status);
            (result, solution)
        };
        let (result, solution) = solve(&ratios, None);
        let measures = result.elastic.as_ref().unwrap();
        assert!(measures.speed_excess > 1e-3, "{speed:?}: {measures:?}");
        let gradient = measures.objective_gradient.clone().unwrap();
        let label = format!("{speed:?} elastic with the envelope");
        assert_matches_differences(&label, &gradient, &ratios, |r| {
            solve(r, Some(&solution)).0.elastic.unwrap().objective
        });
    }
}

/// The penalty rule of the elastic kind (docs/model.md, section 14) where the speed slacks
/// relax the envelope too: at hard solutions where the envelope binds, a speed slack's reduced
/// cost at zero, rho_w less |lambda_speed + c (lambda_P - lambda_M)|, stays positive, and so
/// does a torque deficit's, rho_tau less |lambda_dynamics|.
#[test]
fn the_penalty_rule_holds_where_the_envelope_binds() {
    let settings = testing::settings();
    let cases = [
        (
            Space::Actuation,
            0.5,
            200.0,
            LimitMode::Paper,
            [6.0, 3.0, 1.0, 1.0],
        ),
        (
            Space::Actuation,
            0.5,
            120.0,
            LimitMode::Paper,
            [6.0, 3.0, 1.0, 1.0],
        ),
        (
            Space::Actuation,
            1.0,
            250.0,
            LimitMode::Paper,
            [7.0, 4.0, 2.0, 2.0],
        ),
        (
            Space::Joint,
            0.0,
            250.0,
            LimitMode::Interval,
            [6.5, 3.5, 1.5, 1.2],
        ),
        (
            Space::Joint,
            0.0,
            150.0,
            LimitMode::Exact,
            [8.0, 4.0, 2.0, 2.5],
        ),
    ];
    for (space, payload, no_load, torque, ratios) in cases {
        let task = with_envelope(&testing::task(), payload, no_load);
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque,
            speed: LimitMode::Exact,
        };
        let f = Formulation::new(&task, robot, space, modes).unwrap();
        let (result, solution) = solve_design_from(&f, &ratios, &settings, None).unwrap();
        assert!(result.feasible, "{space} {ratios:?}: {}", result.status);
        let (layout, envelope, lambda) = (f.layout(), f.envelope().unwrap(), &solution.lambda);
        let (mut speed, mut dynamics, mut binds) = (0.0_f64, 0.0_f64, 0.0_f64);
        for (k, i) in (1..layout.steps).flat_map(|k| (0..4).map(move |i| (k, i))) {
            let [plus, minus] =
                Side::BOTH.map(|side| lambda[envelope_row(layout, k, i, side).unwrap()]);
            let row = lambda[layout.row(FamilyId::MotorSpeed, k, i).unwrap()];
            speed = speed.max((row + envelope.slope(i) * (plus - minus)).abs());
            dynamics = dynamics.max(lambda[layout.row(FamilyId::Dynamics, k, i).unwrap()].abs());
            binds = binds.max(plus.abs()).max(minus.abs());
        }
        let weights = penalty_weights(space);
        let label = format!("{space} {payload} kg, w_0 {no_load}, {ratios:?}");
        assert!(binds > 0.1, "{label}: the envelope does not bind");
        assert!(speed < weights.speed, "{label}: speed slack term {speed}");
        assert!(
            dynamics < weights.torque,
            "{label}: dynamics multiplier {dynamics}"
        );
    }
}
