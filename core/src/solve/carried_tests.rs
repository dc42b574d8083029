//! Parts carried by links (the task's `carried`) through whole solves, on the planar example
//! with a pulley whose teeth follow r2 and a motor on its upper arm
//! (`robots/examples/planar_2dof/carried_pulley.json`): dJ*/dr against differences of
//! re-solved problems with the pulley's mass growing with the ratio, IPOPT's derivative
//! checker, and a massless pulley that reproduces the task without parts bit for bit.

use super::linkage_tests::assert_cost_gradient_at;
use super::{solve_design, TrajectoryResult};
use crate::model::task::{PerMotor, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;

/// The formulation of `task` in `space` with its own limit modes.
fn formulation(task: &Task, space: Space) -> Formulation {
    let robot = Robot::load(task).unwrap();
    Formulation::new(task, robot, space, task.limit_modes).unwrap()
}

/// The example whose pulley is massless (density 0) and carries no motor.
fn massless_pulley() -> Task {
    let mut task = testing::carried_task();
    task.carried.retain(|part| part.pulley.is_some());
    task.carried[0].pulley.as_mut().unwrap().density_kg_m3 = Some(0.0);
    task
}

/// With the pulley's mass growing with r2, dJ*/dr matches central differences of re-solved
/// problems at three interior designs in both spaces, and with lossy transmissions at one;
/// the pulley moves dJ*/dr2 away from the massless pulley's.
#[test]
fn the_cost_gradient_with_a_growing_pulley_matches_differences() {
    let task = testing::carried_task();
    let massless = massless_pulley();
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(&task, space);
        for design in [[50.0, 12.0], [35.0, 18.0], [70.0, 9.0]] {
            let label = format!("{space} pulley");
            let result = assert_cost_gradient_at(&f, &design, &label);
            let bare = solve_design(
                &formulation(&massless, space),
                &design,
                &testing::settings(),
            );
            let (with, without) = (
                result.cost_gradient.unwrap()[1],
                bare.unwrap().cost_gradient,
            );
            let without = without.unwrap()[1];
            assert!(
                (with - without).abs() > 1e-3 * with.abs().max(without.abs()),
                "{label} {design:?}: the pulley leaves dJ*/dr2 at {with}"
            );
        }
        let mut lossy = task.clone();
        lossy.motors.efficiency = Some(PerMotor::Each(vec![0.9, 0.8]));
        let f = formulation(&lossy, space);
        assert_cost_gradient_at(&f, &[40.0, 14.0], &format!("{space} lossy pulley"));
    }
}

/// A massless pulley (density 0) reproduces the task without parts to the bit: J, the
/// iterations, dJ*/dr, the trajectory and every other figure (the times, the carried part's
/// line and the actuator mass aside), at two designs in both spaces.
#[test]
fn a_massless_pulley_reproduces_the_task_without_parts_bit_for_bit() {
    let plain =
        Task::load(&testing::repository().join("robots/examples/planar_2dof/task.json")).unwrap();
    let massless = massless_pulley();
    assert!(plain.carried.is_empty());
    let solve = |task: &Task, space: Space, design: &[f64]| -> TrajectoryResult {
        solve_design(&formulation(task, space), design, &testing::settings()).unwrap()
    };
    for space in [Space::Actuation, Space::Joint] {
        for design in [[50.0, 12.0], [30.0, 20.0]] {
            let expected = solve(&plain, space, &design);
            let mut found = solve(&massless, space, &design);
            assert_eq!(found.carried.len(), 1);
            assert_eq!(found.carried[0].mass_kg, 0.0);
            assert_eq!(found.actuator_mass_kg, Some(0.0));
            assert_eq!(
                found.cost.to_bits(),
                expected.cost.to_bits(),
                "{space} {design:?}"
            );
            found.solve_seconds = expected.solve_seconds;
            found.carried.clear();
            found.actuator_mass_kg = None;
            assert_eq!(found, expected, "{space} {design:?}");
        }
    }
}

/// The results record each carried part's mass at the design: the pulley's
/// rho pi w R^2 with R = 2 r2 z_d p / (2 pi), the motor's catalogue mass, and their sum as the
/// actuator mass (the task chooses no motor parts).
#[test]
fn results_record_the_carried_masses_at_the_design() {
    let task = testing::carried_task();
    let result = solve_design(
        &formulation(&task, Space::Actuation),
        &[50.0, 20.0],
        &testing::settings(),
    )
    .unwrap();
    // `teeth_of` 2*r2: 2 x 20 x 12 teeth of 2 mm pitch.
    let radius = 2.0 * 20.0 * 12.0 * 2e-3 / (2.0 * std::f64::consts::PI);
    let pulley = 2700.0 * std::f64::consts::PI * 6e-3 * radius * radius;
    assert_eq!(result.carried.len(), 2);
    assert_eq!(
        (
            result.carried[0].kind.as_str(),
            result.carried[1].kind.as_str()
        ),
        ("pulley", "motor")
    );
    assert!((result.carried[0].mass_kg - pulley).abs() < 1e-12 * pulley);
    assert_eq!(result.carried[1].mass_kg, 0.38);
    let total = result.actuator_mass_kg.unwrap();
    assert!((total - pulley - 0.38).abs() < 1e-12);
}
