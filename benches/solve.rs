//! Median wall time of trajectory solves with each linear solver inside IPOPT, split into the
//! problem's callbacks and IPOPT itself (with its linear algebra).
//!
//! `cargo bench --bench solve`: the default problem (no payload, original design) in both spaces,
//! 30 solves after 3 warm-up solves; and an infeasible design (3 kg, actuation space, original
//! ratios), 5 solves.

use codesign::ipopt::LinearSolver;
use codesign::model::task::Task;
use codesign::model::Robot;
use codesign::problem::{Formulation, Space};
use codesign::solver::{solve_design, SolveSeconds, SolveSettings};
use codesign::stats::median;

/// Solves `runs` times (after `warm_up` unmeasured solves) and prints the medians.
fn measure(task: &Task, space: Space, solver: LinearSolver, warm_up: usize, runs: usize) {
    let mut task = task.clone();
    task.solver.linear_solver = Some(solver);
    let robot = Robot::load(&task).expect("the robot loads");
    let formulation = Formulation::new(&task, robot, space, task.limit_modes).expect("formulation");
    let original = task.transmission.original.clone();
    let settings = SolveSettings::default();
    for _ in 0..warm_up {
        solve_design(&formulation, &original, &settings).expect("solves");
    }
    let results: Vec<_> = (0..runs)
        .map(|_| solve_design(&formulation, &original, &settings).expect("solves"))
        .collect();
    let seconds = |part: fn(&SolveSeconds) -> f64| {
        median(
            &results
                .iter()
                .map(|r| part(&r.solve_seconds))
                .collect::<Vec<_>>(),
        )
    };
    let (total, callbacks, ipopt) = (
        seconds(|s| s.total),
        seconds(|s| s.callbacks),
        seconds(|s| s.ipopt),
    );
    println!(
        "solve {solver} {space} space, {} kg, r = {original:?}: {} ({} iterations, J = {:.6}); median of {runs}: total {:.2} ms, callbacks {:.2} ms ({:.0}%), ipopt {:.2} ms",
        task.payload.mass_kg,
        results[0].status,
        results[0].iterations,
        results[0].cost,
        total * 1e3,
        callbacks * 1e3,
        100.0 * callbacks / total,
        ipopt * 1e3
    );
}

fn main() {
    let task = Task::built_in().expect("the built-in task loads");
    for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
        for space in [Space::Actuation, Space::Joint] {
            measure(&task, space, solver, 3, 30);
        }
    }
    let mut heavy = task.clone();
    heavy.payload.mass_kg = 3.0;
    for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
        measure(&heavy, Space::Actuation, solver, 1, 5);
    }
}
