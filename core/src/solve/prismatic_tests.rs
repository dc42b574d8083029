//! Solves of the SCARA example (`robots/examples/scara_3dof`), whose quill is a prismatic joint:
//! a ball screw along the quill is the constant ratio 2 pi / lead (the same optimum, its motor
//! position offset by the screw's length at q = 0); a slanted screw's motor positions against its
//! geometry computed here; the power balance at every node; dJ*/dr against differences.

use super::linkage_tests::{assert_cost_gradient_at, assert_power_balances};
use super::{solve_design, SolveSettings, TrajectoryResult};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing::{scara_task, QUILL_SCREW_ROW, SLANTED_QUILL_ROW};
use std::f64::consts::TAU;

/// The SCARA example's formulation in `space` with `quill` as the quill's row, 1 kg in the
/// gripper.
fn formulation(quill: Option<&str>, space: Space) -> Formulation {
    let mut task = scara_task(quill);
    task.payload.mass_kg = 1.0;
    let robot = Robot::load(&task).unwrap();
    Formulation::new(&task, robot, space, task.limit_modes).unwrap()
}

/// A feasible solve of `f` at `ratios`, tolerance 1e-10.
fn solved(f: &Formulation, ratios: &[f64]) -> TrajectoryResult {
    let settings = SolveSettings {
        tol: 1e-10,
        ..crate::testing::settings()
    };
    let result = solve_design(f, ratios, &settings).unwrap();
    assert!(result.feasible, "{ratios:?}: {}", result.status);
    assert_power_balances(&result);
    result
}

#[test]
fn a_screw_along_the_quill_is_its_constant_ratio() {
    let lead = 0.010;
    for space in [Space::Actuation, Space::Joint] {
        let constant = solved(&formulation(None, space), &[60.0, 30.0, TAU / lead]);
        let screw = solved(
            &formulation(Some(QUILL_SCREW_ROW), space),
            &[60.0, 30.0, 10.0],
        );
        let scale = constant.cost.abs();
        assert!(
            (constant.cost - screw.cost).abs() <= 1e-7 * scale,
            "{space}: J {} with the constant row, {} with the screw",
            constant.cost,
            screw.cost
        );
        let (a, b) = (&constant.trajectory, &screw.trajectory);
        for (k, (qa, qb)) in a.q.iter().zip(&b.q).enumerate() {
            for (x, y) in qa.iter().zip(qb) {
                assert!(
                    (x - y).abs() <= 1e-6,
                    "{space} node {k}: {qa:?} against {qb:?}"
                );
            }
            // The screw's length is 0.05 m plus the quill's stroke.
            let turned = TAU * (0.05 + qb[2]) / lead;
            let position = b.motor_position[k][2];
            assert!(
                (position - turned).abs() <= 1e-12 * turned,
                "{position} against {turned}"
            );
            let ratio = b.ratio[k][2][2];
            assert!((ratio - TAU / lead).abs() <= 1e-9 * ratio, "{ratio}");
        }
    }
}

#[test]
fn a_slanted_screw_drives_the_quill_as_its_geometry_says() {
    for space in [Space::Actuation, Space::Joint] {
        let result = solved(
            &formulation(Some(SLANTED_QUILL_ROW), space),
            &[60.0, 30.0, 8.0],
        );
        let t = &result.trajectory;
        for (k, q) in t.q.iter().enumerate() {
            // On the outer arm, the quill's frame is at (0.175, 0, -q) and the screw's other
            // end at (0.1, 0, 0.05): 75 mm across, 0.05 + q along the quill.
            let along = 0.05 + q[2];
            let length = (0.075_f64 * 0.075 + along * along).sqrt();
            let turned = TAU * length / 0.008;
            let position = t.motor_position[k][2];
            assert!(
                (position - turned).abs() <= 1e-12 * turned,
                "{position} against {turned}"
            );
            let ratio = TAU / 0.008 * along / length;
            let read = t.ratio[k][2][2];
            assert!(
                (read - ratio).abs() <= 1e-9 * ratio,
                "node {k}: {read} against {ratio}"
            );
        }
    }
}

/// dJ*/dr with respect to the arms' ratios and the slanted screw's lead, in both spaces.
#[test]
fn a_quills_cost_gradient_matches_differences() {
    for space in [Space::Actuation, Space::Joint] {
        let f = formulation(Some(SLANTED_QUILL_ROW), space);
        assert_cost_gradient_at(&f, &[50.0, 25.0, 12.0], &format!("{space} quill"));
    }
}
