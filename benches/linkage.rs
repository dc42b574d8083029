//! Median wall time of trajectory solves whose transmission changes with the pose, beside the
//! same robot with constant rows (issue 34: at most 1.5 times as long).
//!
//! `cargo bench --bench linkage`: the planar example (`robots/examples/planar_2dof/ball_screw.json`)
//! with its elbow driven by its ball screw, by a crank and rod, and by the screw's constant
//! approximation (its ratio at the middle of the motion, q = 0), in both spaces, 30 solves after
//! 3 warm-up solves each. The problems differ, so their iteration counts differ: the medians are
//! given per solve and per iteration, with the ratios to the constant rows.
//!
//! Then one problem written both ways: the SCARA example (`robots/examples/scara_3dof`) with its
//! quill's ball screw as its constant row 2 pi / lead and as a linear actuator along the quill,
//! whose ratio is that constant. Both take the same iterations to the same optimum, so their ratio
//! is the cost of evaluating a linkage row itself.

use codesign::stats::median;
use codesign_core::model::task::{MatrixRow, Task, TaskFile};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, SolveSettings};
use std::path::Path;

/// The crank and rod of the tests on the planar example's elbow.
const CRANK: &str = r#"{"crank_rod": {"crank": {"link": "upper_arm", "point": [0.1, 0, 0],
    "axis": [0, -1, 0], "radius_m": 0.06, "ratio": 10}, "rod_m": 0.2,
    "to": {"link": "forearm", "point": [0, 0, 0.05]}}}"#;

/// The screw's ratio at q = 0: 2 pi / lead (-0.015 / 0.18), lead 12 mm.
const SCREW_AT_MIDDLE: f64 = -43.633_231;

/// The task file whose solver section every solve takes.
const SETTINGS_FROM: &str = "robots/examples/planar_2dof/ball_screw.json";

/// The SCARA's quill screw as a linear actuator along the quill, its lead r3 in mm.
const QUILL_SCREW: &str = r#"{"linear": {"from": {"link": "outer_arm", "point": [0.175, 0, 0.05]},
    "to": {"link": "quill", "point": [0, 0, 0]}, "lead_m": "0.001*r3"}}"#;

/// The SCARA with its quill on a constant row and on the same screw as a linear actuator, in
/// both spaces.
fn one_problem_both_ways() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/examples/scara_3dof/task.json");
    let constant = Task::load(&path).expect("the SCARA example loads");
    let mut screw = constant.clone();
    screw.transmission.matrix[2] = serde_json::from_str(QUILL_SCREW).expect("the row parses");
    screw.transmission.original[2] =
        1000.0 * std::f64::consts::TAU / constant.transmission.original[2];
    screw.transmission.bounds[2] = [2.5, 40.0];
    for space in [Space::Actuation, Space::Joint] {
        let base = measure("SCARA, quill on its constant row", &constant, space, 3, 30);
        let posed = measure("SCARA, quill on a linear actuator", &screw, space, 3, 30);
        println!(
            "  the same problem through a linkage row, {space} space: {:.2}x per solve, {:.2}x per iteration",
            posed.0 / base.0,
            posed.1 / base.1
        );
    }
}

/// Median total and per-iteration seconds of `runs` solves of `task` in `space` (after
/// `warm_up`), printed under `label`.
fn measure(label: &str, task: &Task, space: Space, warm_up: usize, runs: usize) -> (f64, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SETTINGS_FROM);
    let section = TaskFile::load(&path).expect("the example loads").solver;
    let settings = SolveSettings::from_section(section.as_ref()).expect("valid settings");
    let robot = Robot::load(task).expect("the robot loads");
    let f = Formulation::new(task, robot, space, task.limit_modes).expect("formulation");
    let original = task.transmission.original.clone();
    for _ in 0..warm_up {
        solve_design(&f, &original, &settings).expect("solves");
    }
    let results: Vec<_> = (0..runs)
        .map(|_| solve_design(&f, &original, &settings).expect("solves"))
        .collect();
    let total = median(
        &results
            .iter()
            .map(|r| r.solve_seconds.total)
            .collect::<Vec<_>>(),
    );
    let callbacks = median(
        &results
            .iter()
            .map(|r| r.solve_seconds.callbacks)
            .collect::<Vec<_>>(),
    );
    let iterations = results[0].iterations.max(1);
    let per_iteration = median(
        &results
            .iter()
            .map(|r| r.solve_seconds.total / r.iterations.max(1) as f64)
            .collect::<Vec<_>>(),
    );
    println!(
        "{label}, {space} space: {} in {iterations} iterations, J = {:.6}; median of {runs}: \
         total {:.2} ms, callbacks {:.2} ms, {:.3} ms per iteration",
        results[0].status,
        results[0].cost,
        total * 1e3,
        callbacks * 1e3,
        per_iteration * 1e3
    );
    (total, per_iteration)
}

fn main() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/examples/planar_2dof/ball_screw.json");
    let screw = Task::load(&path).expect("the ball-screw example loads");
    let mut crank = screw.clone();
    crank.transmission.matrix[1] = serde_json::from_str(CRANK).expect("the crank row parses");
    let mut constant = screw.clone();
    let row = format!("[0, {SCREW_AT_MIDDLE}]");
    constant.transmission.matrix[1] = serde_json::from_str::<MatrixRow>(&row).expect("row");
    for space in [Space::Actuation, Space::Joint] {
        let base = measure(
            "constant rows (the screw at q = 0)",
            &constant,
            space,
            3,
            30,
        );
        for (label, task) in [("ball screw", &screw), ("crank and rod", &crank)] {
            let posed = measure(label, task, space, 3, 30);
            println!(
                "  {label} against constant rows, {space} space: {:.2}x per solve, {:.2}x per iteration",
                posed.0 / base.0,
                posed.1 / base.1
            );
        }
    }
    one_problem_both_ways();
}
