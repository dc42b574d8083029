//! The LDLᵀ's analyses are kept for the process (`codesign_core::ldl::AnalysisCache::shared`): a second
//! solve of the same formulation analyses nothing and gives the same result, bit for bit, as the
//! first, whose analyses were new; MUMPS solves in the same process as before.
//!
//! One test in its own binary, so that the process-wide counts start at zero.

use codesign_core::ipopt::LinearSolver;
use codesign_core::ldl::{AnalysisCache, CacheCounts};
use codesign_core::model::task::{LimitMode, LimitModes, Task, TaskFile};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, SolveSettings, TrajectoryResult};
use serde_json::Value;

/// The solve settings of the built-in task's `solver` section, with `linear_solver`.
fn settings(linear_solver: LinearSolver) -> SolveSettings {
    let file = TaskFile::built_in().expect("the built-in task loads");
    let mut settings =
        SolveSettings::from_section(file.solver.as_ref()).expect("its solver section is valid");
    settings.linear_solver = Some(linear_solver);
    settings
}

/// The result as JSON without its wall times.
fn without_timing(result: &TrajectoryResult) -> Value {
    let mut json = serde_json::to_value(result).expect("a result serialises");
    json.as_object_mut()
        .expect("a result is an object")
        .remove("solve_seconds");
    json
}

#[test]
fn a_worker_analyses_each_structure_once_and_solves_as_if_it_had_not_kept_it() {
    let mut task = Task::built_in().expect("the built-in task loads");
    // A payload the original design holds at rest (up to 0.585 kg in actuation space).
    task.payload.mass_kg = 0.5;
    let ldl = settings(LinearSolver::Ldl);
    let formulation = |space, modes| {
        let robot = Robot::load(&task).expect("the robot loads");
        Formulation::new(&task, robot, space, modes).expect("formulation")
    };
    let actuation = formulation(Space::Actuation, task.limit_modes);
    let original = task.transmission.original.clone();
    let cache = AnalysisCache::shared();
    assert_eq!(cache.counts(), CacheCounts::default());

    // The default solve: the structure is analysed, then analysed again for its zero diagonals.
    let first = solve_design(&actuation, &original, &ldl).expect("solves");
    assert!(first.feasible, "{}", first.status);
    let once = cache.counts();
    assert!(once.analysed >= 1, "{once:?}");
    assert_eq!(once.reused, 0, "{once:?}");

    // Again, and another design of the same formulation: both analyses are reused.
    let second = solve_design(&actuation, &original, &ldl).expect("solves");
    let twice = cache.counts();
    assert_eq!(twice.analysed, once.analysed, "{twice:?}");
    assert_eq!(twice.reused, once.analysed, "{twice:?}");
    assert_eq!(without_timing(&second), without_timing(&first));
    let other = solve_design(&actuation, &[9.0, 5.62, 3.0, 1.8], &ldl).expect("solves");
    assert!(other.feasible, "{}", other.status);
    assert_eq!(cache.counts().analysed, once.analysed);

    // MUMPS is untouched by the cache and still solves the default problem.
    let mumps = solve_design(&actuation, &original, &settings(LinearSolver::Mumps))
        .expect("solves with MUMPS");
    assert!(mumps.feasible, "{}", mumps.status);
    assert!(
        (mumps.cost - first.cost).abs() < 1e-6 * first.cost,
        "{} {}",
        mumps.cost,
        first.cost
    );
    assert_eq!(cache.counts().analysed, once.analysed);

    // The joint space's KKT matrix has a structure of its own (torque mode `interval`: mode
    // `paper` gives joint 4 no torque to hold the load with).
    let modes = LimitModes {
        torque: LimitMode::Interval,
        ..task.limit_modes
    };
    let joint = formulation(Space::Joint, modes);
    let joint = solve_design(&joint, &original, &ldl).expect("solves");
    assert!(joint.feasible, "{}", joint.status);
    assert!(cache.counts().analysed > once.analysed);
}
