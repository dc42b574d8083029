//! Median wall time of trajectory solves with each linear solver inside IPOPT, split into the
//! problem's callbacks and IPOPT itself (with its linear algebra).
//!
//! `cargo bench --bench solve`: the default problem (no payload, original design) in both spaces,
//! 30 solves after 3 warm-up solves; and an infeasible design (3 kg, actuation space, original
//! ratios), 5 solves; then, in one run with the default linear solver, the time to classify that
//! design: IPOPT's infeasibility detection on the hard problem against the elastic problem
//! (docs/model.md, section 14), 7 solves each.

use codesign::ipopt::LinearSolver;
use codesign::model::task::{Task, TaskFile};
use codesign::model::Robot;
use codesign::problem::{Formulation, ProblemKind, Space};
use codesign::solve::{solve_design, SolveSeconds, SolveSettings};
use codesign::stats::median;

/// Solves the problem of `kind` `runs` times (after `warm_up` unmeasured solves), prints the
/// medians and returns the median total, s.
fn measure(
    task: &Task,
    (space, kind): (Space, ProblemKind),
    solver: LinearSolver,
    warm_up: usize,
    runs: usize,
) -> f64 {
    let section = TaskFile::built_in()
        .expect("the built-in task loads")
        .solver;
    let mut settings = SolveSettings::from_section(section.as_ref()).expect("valid settings");
    settings.linear_solver = Some(solver);
    let robot = Robot::load(task).expect("the robot loads");
    let hard = Formulation::new(task, robot, space, task.limit_modes).expect("formulation");
    let formulation = match kind {
        ProblemKind::Hard => hard,
        ProblemKind::Elastic => hard.elastic(),
    };
    let original = task.transmission.original.clone();
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
        "solve {kind:?} {solver} {space} space, {} kg, r = {original:?}: {} ({} iterations, J = {:.6}); median of {runs}: total {:.2} ms, callbacks {:.2} ms ({:.0}%), ipopt {:.2} ms",
        task.payload.mass_kg,
        results[0].status,
        results[0].iterations,
        results[0].cost,
        total * 1e3,
        callbacks * 1e3,
        100.0 * callbacks / total,
        ipopt * 1e3
    );
    total
}

fn main() {
    let task = Task::built_in().expect("the built-in task loads");
    for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
        for space in [Space::Actuation, Space::Joint] {
            measure(&task, (space, ProblemKind::Hard), solver, 3, 30);
        }
    }
    let mut heavy = task.clone();
    heavy.payload.mass_kg = 3.0;
    for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
        measure(&heavy, (Space::Actuation, ProblemKind::Hard), solver, 1, 5);
    }
    let solver = LinearSolver::Ldl;
    let hard = measure(&heavy, (Space::Actuation, ProblemKind::Hard), solver, 1, 7);
    let elastic = measure(
        &heavy,
        (Space::Actuation, ProblemKind::Elastic),
        solver,
        1,
        7,
    );
    println!(
        "classifying the infeasible design: the elastic solve takes {:.2} of the hard solve's time ({:.1}x faster)",
        elastic / hard,
        hard / elastic
    );
}
