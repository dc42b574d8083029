//! Tests of the free horizon T (docs/model.md, section 6): the derivatives in T of the
//! integration rows and of the cost against central differences and IPOPT's checker, in both
//! spaces and kinds, for a constant transmission and a linkage.

use super::tests::{assert_checker_finds_nothing, assert_derivatives_match};
use super::*;
use crate::model::task::{Horizon, LimitMode, LimitModes, Task};
use crate::model::Robot;
use crate::testing::{self, posed_task, SCREW_ROW};

/// `task` on 5 steps with T free in [0.4, 1.2] s and w_T = 2 per s beside its other weights, in
/// both spaces (the joint space under the modes `exact`), hard and elastic.
fn free_horizon_formulations(mut task: Task) -> Vec<Formulation> {
    task.motion.steps = 5;
    task.motion.horizon = Horizon::Free {
        min_s: 0.4,
        max_s: 1.2,
    };
    task.weights.time = 2.0;
    let exact = LimitModes {
        torque: LimitMode::Exact,
        speed: LimitMode::Exact,
    };
    let mut list = Vec::new();
    for (space, modes) in [(Space::Actuation, task.limit_modes), (Space::Joint, exact)] {
        let robot = Robot::load(&task).unwrap();
        let hard = Formulation::new(&task, robot, space, modes).unwrap();
        list.push(hard.elastic());
        list.push(hard);
    }
    list
}

/// The built-in task at 1 kg and the planar example with a ball screw at its elbow.
fn cases() -> Vec<(Formulation, Vec<f64>)> {
    let mut task = testing::task();
    task.payload.mass_kg = 1.0;
    let built_in = free_horizon_formulations(task).into_iter();
    let mut screw = posed_task(SCREW_ROW);
    screw.payload.mass_kg = 0.5;
    let screw = free_horizon_formulations(screw).into_iter();
    (built_in.map(|f| (f, vec![7.0, 4.0, 2.0, 1.5])))
        .chain(screw.map(|f| (f, vec![50.0, 12.0])))
        .collect()
}

#[test]
fn the_free_horizons_derivatives_match_finite_differences() {
    for (f, design) in cases() {
        assert_eq!(f.layout().horizon(), Some(f.layout().slacks().start - 1));
        assert_derivatives_match(&f, &design);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_a_free_horizon() {
    for (f, design) in cases() {
        assert_checker_finds_nothing(&f, &design);
    }
}

#[test]
fn a_free_horizon_is_a_bounded_variable_that_starts_at_its_longest() {
    let f = free_horizon_formulations(testing::task()).remove(1);
    let problem = f.problem(&[6.0, 3.0, 1.0, 1.0]).unwrap();
    let column = f.layout().horizon().unwrap();
    let (mut lower, mut upper) = (vec![0.0; f.layout().num_variables()], vec![0.0; 0]);
    upper.resize(lower.len(), 0.0);
    crate::ipopt::Nlp::variable_bounds(&problem, &mut lower, &mut upper);
    assert_eq!((lower[column], upper[column]), (0.4, 1.2));
    let mut x = vec![0.0; lower.len()];
    crate::ipopt::Nlp::initial_point(&problem, &mut x);
    assert_eq!(x[column], 1.2);
    assert_eq!(f.step_at(&x, 0), 1.2 / 5.0);
}

#[test]
fn the_copper_losses_refuse_a_free_horizon() {
    let f = free_horizon_formulations(testing::task()).remove(1);
    let error = f.minimising_copper_loss().unwrap_err().to_string();
    assert!(error.contains("free horizon"), "{error}");
}
