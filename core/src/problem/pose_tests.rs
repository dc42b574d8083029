//! Tests of the trajectory NLP where G depends on the pose (docs/model.md, section 17): its
//! derivatives against finite differences and IPOPT's checker, for a ball screw and a crank and
//! rod, in both spaces and both kinds, for a screw whose stroke is held, for the ankle
//! example's two crank-rods over two joints, and for the SCARA example's quill (a prismatic
//! joint) driven by a constant row and by a slanted screw; each linkage also with motors of rotor
//! inertia and friction, whose speed term dG/dt v brings in the fourth derivatives, and a
//! torque-speed envelope, and with lossy transmissions, whose loss L(G^-T RNEA, G v) takes G(q)
//! three times.

use super::tests::{
    assert_checker_finds_nothing, assert_checker_finds_nothing_at_step, assert_derivatives_match,
    assert_design_partials_match,
};
use super::*;
use crate::model::task::{LimitMode, LimitModes, PerMotor, Task};
use crate::model::Robot;
use crate::testing::{
    ankle_task, posed_task, scara_task, CRANK_ROW, SCREW_ROW, SLANTED_QUILL_ROW, STROKED_SCREW_ROW,
};

/// The formulations of a linkage `row` on the planar example's elbow: both spaces, 5 steps,
/// modes `exact`, with 0.5 kg in the gripper, in the hard and the elastic kind.
fn posed_formulations(row: &str) -> Vec<Formulation> {
    let mut task = posed_task(row);
    task.payload.mass_kg = 0.5;
    exact_formulations(task, |_| {})
}

/// Gives the task's motors a rotor inertia (kg m^2), a viscous friction (N m s/rad) and a
/// no-load speed (rad/s: a torque-speed envelope) of a small servo motor, a little different
/// per motor.
fn with_motor_dynamics(task: &mut Task) {
    let count = task.transmission.matrix.len();
    let each =
        |base: f64| PerMotor::Each((0..count).map(|i| base * (1.0 + 0.3 * i as f64)).collect());
    task.motors.rotor_inertia_kgm2 = Some(each(2e-5));
    task.motors.viscous_friction_nm_s_per_rad = Some(each(1e-4));
    task.motors.no_load_speed_rad_s = Some(each(400.0));
}

/// Gives the task's transmissions an efficiency a little different per motor (0.9, 0.85, ...).
fn with_efficiency(task: &mut Task) {
    let count = task.transmission.matrix.len();
    let each = (0..count).map(|i| 0.9 - 0.05 * i as f64).collect();
    task.motors.efficiency = Some(PerMotor::Each(each));
}

/// The formulations of `task` with what `give` adds to its motors: 5 steps, modes `exact`, both
/// spaces, both kinds.
fn exact_formulations(mut task: Task, give: fn(&mut Task)) -> Vec<Formulation> {
    give(&mut task);
    task.motion.steps = 5;
    let mut list = Vec::new();
    for space in [Space::Actuation, Space::Joint] {
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

/// Every linkage example with what `give` adds to its motors, and the design each is evaluated
/// at, the SCARA's slanted quill screw at a lead of `quill_lead_mm`.
fn linkages_with(give: fn(&mut Task), quill_lead_mm: f64) -> Vec<(Formulation, Vec<f64>)> {
    let mut all = Vec::new();
    for row in [SCREW_ROW, CRANK_ROW] {
        let mut task = posed_task(row);
        task.payload.mass_kg = 0.5;
        all.extend(
            exact_formulations(task, give)
                .into_iter()
                .map(|f| (f, vec![50.0, 12.0])),
        );
    }
    all.extend(
        exact_formulations(ankle_task(), give)
            .into_iter()
            .map(|f| (f, vec![55.0, 65.0, 12.0])),
    );
    let scara = scara_task(Some(SLANTED_QUILL_ROW));
    all.extend(
        exact_formulations(scara, give)
            .into_iter()
            .map(|f| (f, vec![60.0, 30.0, quill_lead_mm])),
    );
    all
}

#[test]
fn motor_dynamics_through_linkages_match_finite_differences() {
    for (f, design) in linkages_with(with_motor_dynamics, 10.0) {
        assert_derivatives_match(&f, &design);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_motor_dynamics_through_linkages() {
    for (f, design) in linkages_with(with_motor_dynamics, 10.0) {
        assert_checker_finds_nothing(&f, &design);
    }
}

/// Lossy transmissions alone, and with every motor term beside them.
#[test]
fn losses_through_linkages_match_finite_differences() {
    let everything = |task: &mut Task| {
        with_motor_dynamics(task);
        with_efficiency(task);
    };
    for give in [with_efficiency, everything] {
        for (f, design) in linkages_with(give, 10.0) {
            assert_derivatives_match(&f, &design);
        }
    }
}

/// With IPOPT's default step (1e-8) and the SCARA's quill screw at its coarsest lead: the loss
/// turns with the quill's speed within omega / G = 15 rad/s / 628 rad/m = 0.024 m/s at a lead
/// of 10 mm, and the checker's forward differences at the initial guess's v = 0 (where the
/// turn is steepest) then err by 1e-2 at a step of 1e-7 and 1e-3 at 1e-8 (the central
/// differences above match there). At 40 mm the turn is 4 times wider.
#[test]
fn ipopt_derivative_checker_finds_nothing_with_losses_through_linkages() {
    for (f, design) in linkages_with(with_efficiency, 40.0) {
        assert_checker_finds_nothing_at_step(&f, &design, 1e-8);
    }
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

/// Every linkage example's design terms, lossless, with motor dynamics and with losses.
#[test]
fn design_partials_through_linkages_match_finite_differences() {
    let none = |_: &mut Task| {};
    for give in [none, with_motor_dynamics, with_efficiency] {
        for (f, design) in linkages_with(give, 10.0) {
            assert_design_partials_match(&f, &design);
        }
    }
}
