//! Tests of the transmissions' losses (`motors.efficiency`) through whole solves: dJ*/dr
//! against differences of re-solved problems, what a result reports of them, and the lossless
//! limit.

use super::tests::{assert_cost_gradient, with_motor_terms};
use super::{solve_design, TrajectoryResult};
use crate::model::task::{LimitMode, LimitModes, PerMotor, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;

/// `task` carrying `payload` kg through transmissions of efficiency `efficiency` (None:
/// lossless).
fn with_efficiency(task: &Task, payload: f64, efficiency: Option<PerMotor>) -> Task {
    let mut task = task.clone();
    task.payload.mass_kg = payload;
    task.motors.efficiency = efficiency;
    task
}

/// Solves `task` at `ratios` in the actuation space (torque mode `paper`, speed `exact`).
fn solve(task: &Task, ratios: &[f64]) -> TrajectoryResult {
    let modes = LimitModes {
        torque: LimitMode::Paper,
        speed: LimitMode::Exact,
    };
    let robot = Robot::load(task).unwrap();
    let formulation = Formulation::new(task, robot, Space::Actuation, modes).unwrap();
    solve_design(&formulation, ratios, &testing::settings()).unwrap()
}

/// dJ*/dr with lossy transmissions (one efficiency per motor) and every other motor term
/// against central differences of re-solved problems, at three feasible designs: actuation
/// space, and joint space with box and with exact torque limits.
#[test]
fn cost_gradient_with_transmission_losses_matches_differences() {
    let cases = [
        (
            Space::Actuation,
            1.0,
            LimitMode::Paper,
            LimitMode::Exact,
            [7.0, 4.0, 2.0, 2.3],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Interval,
            LimitMode::Exact,
            [6.5, 3.5, 1.5, 1.2],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Exact,
            LimitMode::Paper,
            [8.0, 4.0, 2.0, 2.5],
        ),
    ];
    let efficiency = PerMotor::Each(vec![0.9, 0.85, 0.95, 0.8]);
    for (space, payload, torque, speed, ratios) in cases {
        let task = with_motor_terms(&testing::task());
        let task = with_efficiency(&task, payload, Some(efficiency.clone()));
        assert_cost_gradient(&task, space, LimitModes { torque, speed }, ratios);
    }
}

/// A result with losses records each motor's loss torque per interval, takes them off the
/// joint torques (the dynamics residual stays at the solver's level), and reports the energy
/// lost, int L w dt, per motor and in total. Without the key it records none, and an efficiency
/// of 1 costs what no key does.
#[test]
fn a_result_reports_what_the_transmissions_lose() {
    let ratios = [6.0, 3.0, 1.0, 1.0];
    let lossless = solve(&with_efficiency(&testing::task(), 1.0, None), &ratios);
    let lossy = solve(
        &with_efficiency(&testing::task(), 1.0, Some(PerMotor::All(0.9))),
        &ratios,
    );
    assert!(lossless.feasible && lossy.feasible, "{:?}", lossy.reason);
    assert!(
        lossy.violations.get("dynamics").unwrap() < 1e-6,
        "{:?}",
        lossy.violations
    );
    let t = &lossy.trajectory;
    assert_eq!(t.transmission_loss.len(), t.motor_torque.len());
    let figures = lossy.figures.as_ref().unwrap();
    for (i, motor) in figures.motors.iter().enumerate() {
        let by_hand: f64 = (0..t.motor_torque.len())
            .map(|k| {
                let h = t.time[k + 1] - t.time[k];
                let mean_speed = (t.motor_speed[k][i] + t.motor_speed[k + 1][i]) / 2.0;
                h * t.transmission_loss[k][i] * mean_speed
            })
            .sum();
        let reported = motor.transmission_loss_j.unwrap();
        assert!((reported - by_hand).abs() <= 1e-12 * by_hand.abs().max(1.0));
    }
    assert!(figures.transmission_loss_j.unwrap() > 0.0);
    assert!(lossless.trajectory.transmission_loss.is_empty());
    assert_eq!(lossless.figures.unwrap().transmission_loss_j, None);
    let ideal = solve(
        &with_efficiency(&testing::task(), 1.0, Some(PerMotor::All(1.0))),
        &ratios,
    );
    assert!((ideal.cost - lossless.cost).abs() <= 1e-6 * lossless.cost);
}

/// Under the energy objective's criterion the optimal cost is the motors' copper losses, J, as
/// the physical figures compute them from the trajectory, plus the soft box's penalty; and its
/// dJ*/dr matches central differences of re-solved problems (the copper losses do not depend
/// on r in the actuation space, so the dynamics rows carry it all).
#[test]
fn the_energy_criterion_minimises_the_copper_losses() {
    let (k_t, r) = crate::problem::tests::electrical();
    let mut task = with_efficiency(&testing::task(), 1.0, None);
    task.motors.torque_constant_nm_per_a = Some(PerMotor::Each(k_t));
    task.motors.resistance_ohm = Some(PerMotor::Each(r));
    let modes = LimitModes {
        torque: LimitMode::Paper,
        speed: LimitMode::Exact,
    };
    let robot = Robot::load(&task).unwrap();
    let formulation = Formulation::new(&task, robot, Space::Actuation, modes)
        .unwrap()
        .minimising_copper_loss()
        .unwrap();
    let settings = super::SolveSettings {
        tol: 1e-11,
        ..testing::settings()
    };
    let ratios = [8.0, 5.0, 2.5, 2.5];
    let result = solve_design(&formulation, &ratios, &settings).unwrap();
    assert!(result.feasible, "{:?}", result.reason);
    let figures = result.figures.as_ref().unwrap();
    let copper = figures.electrical.as_ref().unwrap().copper_loss_j;
    let terms = result.cost_terms.as_ref().unwrap();
    assert!(
        (terms.control - copper).abs() <= 1e-9 * copper,
        "{terms:?} vs {copper}"
    );
    assert_eq!((terms.position, terms.velocity), (0.0, 0.0));
    let sum = terms.control + terms.cartesian_box;
    // IPOPT moves x onto the bounds it reached after its last objective, by about 1e-8 N m.
    assert!(
        (result.cost - sum).abs() <= 1e-7 * result.cost,
        "{} vs {sum}",
        result.cost
    );
    let gradient = result.cost_gradient.clone().unwrap();
    super::tests::assert_matches_differences("energy", &gradient, &ratios, |r| {
        solve_design(&formulation, r, &settings).unwrap().cost
    });
}
