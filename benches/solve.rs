//! Median wall time of the default trajectory solve (actuation space, no payload, original
//! design), split into the problem's callbacks and IPOPT itself.
//!
//! `cargo bench --bench solve` (30 solves after 3 warm-up solves).

use codesign::model::task::Task;
use codesign::model::Robot;
use codesign::problem::{Formulation, Space};
use codesign::solver::{solve_design, SolveSettings};
use std::path::Path;

fn median(mut samples: Vec<f64>) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

fn main() {
    let task =
        Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json"))
            .expect("the default task loads");
    for space in [Space::Actuation, Space::Joint] {
        let robot = Robot::load(&task).expect("the robot loads");
        let formulation =
            Formulation::new(&task, robot, space, task.limit_modes).expect("formulation");
        let original = task.transmission.original.clone();
        let settings = SolveSettings::default();
        for _ in 0..3 {
            solve_design(&formulation, &original, &settings).expect("solves");
        }
        let runs: Vec<_> = (0..30)
            .map(|_| solve_design(&formulation, &original, &settings).expect("solves"))
            .collect();
        let total = median(runs.iter().map(|r| r.solve_seconds.total).collect());
        let callbacks = median(runs.iter().map(|r| r.solve_seconds.callbacks).collect());
        let ipopt = median(runs.iter().map(|r| r.solve_seconds.ipopt).collect());
        println!(
            "solve {space} space, 0 kg, r = {original:?}: {} ({} iterations, J = {:.6}); median of 30: total {:.2} ms, callbacks {:.2} ms ({:.0}%), ipopt {:.2} ms",
            runs[0].status,
            runs[0].iterations,
            runs[0].cost,
            total * 1e3,
            callbacks * 1e3,
            100.0 * callbacks / total,
            ipopt * 1e3
        );
    }
}
