//! Tests of the trajectory NLP where G depends on the pose (docs/model.md, section 17): its
//! derivatives against finite differences and IPOPT's checker, for a ball screw and a crank and
//! rod, in both spaces and both kinds, for a screw whose stroke is held, for the ankle
//! example's two crank-rods over two joints, and for the SCARA example's quill (a prismatic
//! joint) driven by a constant row and by a slanted screw.

use super::tests::{assert_checker_finds_nothing, assert_derivatives_match};
use super::*;
use crate::model::task::{LimitMode, LimitModes};
use crate::model::Robot;
use crate::testing::{
    ankle_task, posed_task, scara_task, CRANK_ROW, SCREW_ROW, SLANTED_QUILL_ROW, STROKED_SCREW_ROW,
};

/// The formulations of a linkage `row` on the planar example's elbow: both spaces, 5 steps,
/// modes `exact`, with 0.5 kg in the gripper, in the hard and the elastic kind.
fn posed_formulations(row: &str) -> Vec<Formulation> {
    let mut list = Vec::new();
    for space in [Space::Actuation, Space::Joint] {
        let mut task = posed_task(row);
        task.motion.steps = 5;
        task.payload.mass_kg = 0.5;
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque: LimitMode::Exact,
            speed: LimitMode::Exact,
        };
        let f = Formulation::new(&task, robot, space, modes).unwrap();
        list.push(f.elastic());
        list.push(f);
    }
    list
}

/// The ankle example's formulations (two crank-rods, each over both joints): 5 steps, both spaces,
/// both kinds.
fn ankle_formulations() -> Vec<Formulation> {
    let mut list = Vec::new();
    for space in [Space::Actuation, Space::Joint] {
        let mut task = ankle_task();
        task.motion.steps = 5;
        let robot = Robot::load(&task).unwrap();
        let f = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
        list.push(f.elastic());
        list.push(f);
    }
    list
}

/// The SCARA example's formulations with `quill` as the quill's row (its own constant row
/// without): 5 steps, 1 kg in the gripper, both spaces, both kinds.
fn scara_formulations(quill: Option<&str>) -> Vec<Formulation> {
    let mut list = Vec::new();
    for space in [Space::Actuation, Space::Joint] {
        let mut task = scara_task(quill);
        task.motion.steps = 5;
        task.payload.mass_kg = 1.0;
        let robot = Robot::load(&task).unwrap();
        let f = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
        list.push(f.elastic());
        list.push(f);
    }
    list
}

#[test]
fn a_quills_derivatives_match_finite_differences() {
    for f in scara_formulations(None) {
        assert_derivatives_match(&f, &[60.0, 30.0, 628.3]);
    }
    for f in scara_formulations(Some(SLANTED_QUILL_ROW)) {
        assert_derivatives_match(&f, &[60.0, 30.0, 10.0]);
    }
}

#[test]
fn an_ankles_derivatives_match_finite_differences() {
    for f in ankle_formulations() {
        assert_derivatives_match(&f, &[55.0, 65.0, 12.0]);
    }
}

#[test]
fn a_screws_derivatives_match_finite_differences() {
    for f in posed_formulations(SCREW_ROW) {
        assert_derivatives_match(&f, &[50.0, 12.0]);
    }
}

#[test]
fn a_stroked_screws_derivatives_match_finite_differences() {
    for f in posed_formulations(STROKED_SCREW_ROW) {
        assert_derivatives_match(&f, &[50.0, 12.0]);
    }
}

#[test]
fn a_crank_rods_derivatives_match_finite_differences() {
    for f in posed_formulations(CRANK_ROW) {
        assert_derivatives_match(&f, &[50.0, 12.0]);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_linkages() {
    for row in [SCREW_ROW, STROKED_SCREW_ROW, CRANK_ROW] {
        for f in posed_formulations(row) {
            assert_checker_finds_nothing(&f, &[50.0, 12.0]);
        }
    }
    for f in ankle_formulations() {
        assert_checker_finds_nothing(&f, &[60.0, 60.0, 15.0]);
    }
    for f in scara_formulations(None) {
        assert_checker_finds_nothing(&f, &[60.0, 30.0, 628.3]);
    }
    for f in scara_formulations(Some(SLANTED_QUILL_ROW)) {
        assert_checker_finds_nothing(&f, &[60.0, 30.0, 10.0]);
    }
}
