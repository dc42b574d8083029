//! A free horizon's cost against a fixed one's (issue 52): on the built-in arm (original design,
//! 0 and 1 kg, both spaces), the pure minimum-time problem solved from the standard guess
//! (`solver.free_horizon` = `local`) against the repository task solved at the T* it found, and
//! the same pure problem shortened by the fixed-horizon rule (`descend`). IPOPT iterations
//! (deterministic) and the median wall time of 5 solves each.
//!
//! `cargo bench --bench free_horizon`

use codesign::stats::median;
use codesign_core::model::task::{Horizon, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, FreeHorizonSearch, SolveSettings, TrajectoryResult};
use std::time::Instant;

/// Solves `formulation` at the original design 5 times: the last result and the median wall
/// time, ms.
fn timed(formulation: &Formulation, settings: &SolveSettings) -> (TrajectoryResult, f64) {
    let ratios = formulation.task().transmission.original.clone();
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        let start = Instant::now();
        let result = solve_design(formulation, &ratios, settings).expect("solves");
        times.push(start.elapsed().as_secs_f64() * 1e3);
        last = Some(result);
    }
    (last.expect("five solves"), median(&times))
}

fn main() {
    println!("| space | payload | free, local: T*, iterations, ms | task at T*: iterations, ms | ratio of iterations | free, descend: T*, iterations, ms |");
    println!("|---|---|---|---|---|---|");
    for space in [Space::Actuation, Space::Joint] {
        for payload_kg in [0.0, 1.0] {
            let mut task = Task::built_in().expect("the built-in task");
            task.payload.mass_kg = payload_kg;
            let pure = task.minimum_time();
            let robot = Robot::load(&pure).expect("the robot loads");
            let free = Formulation::new(&pure, robot.clone(), space, task.limit_modes)
                .expect("formulation")
                .shaped_by(&task);
            let local = SolveSettings::default();
            let (found, free_ms) = timed(&free, &local);
            let t_star = found.horizon_s.expect("a free horizon");
            task.motion.horizon = Horizon::Fixed(t_star);
            let fixed =
                Formulation::new(&task, robot, space, task.limit_modes).expect("formulation");
            let (at_t_star, fixed_ms) = timed(&fixed, &local);
            let descend = SolveSettings {
                free_horizon: FreeHorizonSearch::Descend,
                ..SolveSettings::default()
            };
            let (shortened, descend_ms) = timed(&free, &descend);
            println!(
                "| {space} | {payload_kg} kg | {t_star:.4} s, {}, {free_ms:.0} | {}, {fixed_ms:.0} | {:.2} | {:.4} s, {}, {descend_ms:.0} |",
                found.iterations,
                at_t_star.iterations,
                found.iterations as f64 / at_t_star.iterations as f64,
                shortened.horizon_s.expect("a free horizon"),
                shortened.iterations,
            );
        }
    }
}
