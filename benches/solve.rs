//! Median wall time of trajectory solves with each linear solver inside IPOPT, split into the
//! problem's callbacks and IPOPT itself (with its linear algebra).
//!
//! `cargo bench --bench solve`: the default problem (no payload, original design) in both spaces,
//! 30 solves after 3 warm-up solves; and an infeasible design (3 kg, actuation space, original
//! ratios), 5 solves; then, in one run with the default linear solver, the time to classify that
//! design: IPOPT's infeasibility detection on the hard problem against the elastic problem
//! (docs/model.md, section 14), 7 solves each. Side by side in the same run, when CasADi is
//! importable (from `$PAPER_STACK_PYTHON`, else `python3`; see benches/paper_stack/README.md),
//! the paper's stack solves the default problem in actuation space 30 times after 3 warm-up
//! solves (`benches/paper_stack/bench.py --quick`), and the ratio of the medians is printed.

use codesign::stats::median;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::{Task, TaskFile};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, ProblemKind, Space};
use codesign_core::solve::{solve_design, SolveSeconds, SolveSettings};
use std::path::Path;
use std::process::Command;

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

/// The paper stack's median time of the default solve, s, or None without CasADi.
fn paper_stack_default() -> Option<f64> {
    let python = std::env::var("PAPER_STACK_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_casadi = Command::new(&python)
        .args(["-c", "import casadi"])
        .output()
        .is_ok_and(|output| output.status.success());
    if !has_casadi {
        println!(
            "the paper's stack is not importable with {python}: `pip install casadi` (or set \
             PAPER_STACK_PYTHON, see benches/paper_stack/README.md); the crate's side only"
        );
        return None;
    }
    let rows = std::env::temp_dir().join(format!("codesign-solve-{}.json", std::process::id()));
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/paper_stack/bench.py");
    let output = Command::new(&python)
        .arg(script)
        .args(["--quick", "--runs", "30", "--warm-up", "3", "--json"])
        .arg(&rows)
        .output()
        .expect("the paper stack's bench starts");
    print!("paper stack: {}", String::from_utf8_lossy(&output.stdout));
    let text = std::fs::read_to_string(&rows).ok()?;
    std::fs::remove_file(&rows).ok();
    let rows: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(rows[0]["median_solve_ms"].as_f64()? / 1e3)
}

fn main() {
    let task = Task::built_in().expect("the built-in task loads");
    let ours = measure(
        &task,
        (Space::Actuation, ProblemKind::Hard),
        LinearSolver::Ldl,
        3,
        30,
    );
    if let Some(paper) = paper_stack_default() {
        println!(
            "default solve (actuation space, 0 kg, original design): codesign {:.2} ms, the \
             paper's stack {:.2} ms: {:.1}x faster",
            1e3 * ours,
            1e3 * paper,
            paper / ours
        );
    }
    for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
        for space in [Space::Actuation, Space::Joint] {
            if (solver, space) != (LinearSolver::Ldl, Space::Actuation) {
                measure(&task, (space, ProblemKind::Hard), solver, 3, 30);
            }
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
