//! How the hard and the elastic trajectory problems classify designs at the edge of feasibility
//! (docs/model.md, section 14), and how long each takes.
//!
//! `cargo bench --bench classify`: at 3 kg in actuation space, two sets of designs, each solved
//! cold once as the hard problem and once as the elastic one with the default linear solver:
//! - `near the best`: 30 designs within 7% of the best 3 kg designs found (seeded);
//! - `spread`: the first 30 Halton designs of the design space (`spread_designs`).
//!
//! Per set it prints how many designs each problem calls feasible and how many only one of them
//! does (both solves are local: IPOPT's verdict of infeasibility and a local minimum of the
//! elastic problem with positive slack can each miss a feasible trajectory the other finds),
//! whether and by how much the two J differ where both are feasible (the non-convex problem has
//! several local optima, and the two solves take different paths), and the median solve times
//! and iterations on the designs both call infeasible, with the median per-design time ratio.

use codesign::design::gradient::spread_designs;
use codesign::stats::median;
use codesign_core::model::task::{Task, TaskFile};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, SolveSettings, TrajectoryResult};

/// Best designs of the 3 kg actuation-space runs (results/quick, results/runs).
const CENTRES: [[f64; 4]; 3] = [
    [7.84, 4.45, 1.51, 2.56],
    [9.0, 4.5, 1.88, 2.8],
    [8.5, 4.4, 1.9, 2.9],
];

/// A small linear congruential stream in [0, 1): the same designs on every machine.
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` designs within 7% of [`CENTRES`], projected onto the design space.
fn near_the_best(formulation: &Formulation, n: usize) -> Vec<Vec<f64>> {
    let set = formulation.transmission().design_space();
    let mut stream = Stream(12);
    (0..n)
        .map(|k| {
            let centre = CENTRES[k % CENTRES.len()];
            let moved: Vec<f64> = centre
                .iter()
                .map(|r| r * (0.93 + 0.14 * stream.next()))
                .collect();
            set.project(&moved)
        })
        .collect()
}

/// Solves every design as the hard and the elastic problem and prints the comparison.
fn compare(label: &str, hard: &Formulation, designs: &[Vec<f64>]) {
    let elastic = hard.elastic();
    let section = TaskFile::built_in()
        .expect("the built-in task loads")
        .solver;
    let settings = SolveSettings::from_section(section.as_ref()).expect("valid settings");
    let solve = |f: &Formulation, r: &[f64]| -> TrajectoryResult {
        solve_design(f, r, &settings).expect("a design of the design space solves")
    };
    let pairs: Vec<(TrajectoryResult, TrajectoryResult)> = designs
        .iter()
        .map(|r| (solve(hard, r), solve(&elastic, r)))
        .collect();
    let count = |keep: &dyn Fn(&(TrajectoryResult, TrajectoryResult)) -> bool| {
        pairs.iter().filter(|p| keep(p)).count()
    };
    let both = count(&|(h, e)| h.feasible && e.feasible);
    let agree =
        count(&|(h, e)| h.feasible && e.feasible && (h.cost - e.cost).abs() <= 1e-6 * h.cost.abs());
    println!(
        "{label}: {} designs; feasible by the hard solve {}, by the elastic {}; by both {both} \
         (same J to 1e-6 on {agree}), only hard {}, only elastic {}",
        pairs.len(),
        count(&|(h, _)| h.feasible),
        count(&|(_, e)| e.feasible),
        count(&|(h, e)| h.feasible && !e.feasible),
        count(&|(h, e)| !h.feasible && e.feasible),
    );
    let differences: Vec<f64> = pairs
        .iter()
        .filter(|(h, e)| h.feasible && e.feasible)
        .map(|(h, e)| (e.cost - h.cost) / h.cost.abs())
        .collect();
    if !differences.is_empty() {
        println!(
            "  where both are feasible: the elastic J is lower on {} of {}; (elastic - hard) / hard: \
             median {:+.3}, from {:+.3} to {:+.3}",
            differences.iter().filter(|&&d| d < 0.0).count(),
            differences.len(),
            median(&differences),
            differences.iter().copied().fold(f64::INFINITY, f64::min),
            differences.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
    }
    let infeasible: Vec<_> = pairs
        .iter()
        .filter(|(h, e)| !h.feasible && !e.feasible)
        .collect();
    if infeasible.is_empty() {
        return;
    }
    let of = |part: &dyn Fn(&(TrajectoryResult, TrajectoryResult)) -> f64| {
        median(&infeasible.iter().map(|p| part(p)).collect::<Vec<_>>())
    };
    println!(
        "  on the {} designs both call infeasible, medians: hard {:.1} ms ({} iterations), \
         elastic {:.1} ms ({} iterations); per design the elastic solve is {:.2}x faster",
        infeasible.len(),
        1e3 * of(&|(h, _)| h.solve_seconds.total),
        of(&|(h, _)| h.iterations as f64),
        1e3 * of(&|(_, e)| e.solve_seconds.total),
        of(&|(_, e)| e.iterations as f64),
        of(&|(h, e)| h.solve_seconds.total / e.solve_seconds.total),
    );
}

fn main() {
    let mut task = Task::built_in().expect("the built-in task loads");
    task.payload.mass_kg = 3.0;
    let robot = Robot::load(&task).expect("the robot loads");
    let hard =
        Formulation::new(&task, robot, Space::Actuation, task.limit_modes).expect("formulation");
    compare("near the best", &hard, &near_the_best(&hard, 30));
    let spread = spread_designs(hard.transmission(), 1..31);
    compare("spread", &hard, &spread);
}
