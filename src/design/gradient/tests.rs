//! Tests of the gradient method.

use super::*;
use crate::design::evaluate::InProcess;
use crate::design::penalty::Penalty;
use crate::design::score::{Fitness, Objective};
use codesign_core::ipopt::Solution;
use codesign_core::model::task::Task;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, solve_design_from};
use codesign_core::testing;

/// `task` carrying `payload_kg`.
fn at(mut task: Task, payload_kg: f64) -> Task {
    task.payload.mass_kg = payload_kg;
    task
}

/// The gradient method on `task` (actuation space) under `penalty`, on `threads` threads of
/// this process.
fn run(
    task: &Task,
    settings: &GradientSettings,
    penalty: Penalty,
    threads: usize,
) -> Result<DesignOutcome, GradientError> {
    let (space, modes) = (Space::Actuation, task.limit_modes);
    let solve = testing::settings();
    let fitness = Fitness::new(task, &solve, space, modes, &Objective::Cost, penalty).unwrap();
    let evaluator = InProcess::new(fitness, threads);
    let transmission = Transmission::from_spec(&task.transmission).unwrap();
    optimize_gradient(&transmission, &evaluator, settings)
}

/// The hard problem the fitness of [`run`] solves.
fn formulation(task: &Task) -> Formulation {
    let robot = codesign_core::model::Robot::load(task).unwrap();
    let tolerance = testing::settings().constraint_tolerance();
    Formulation::new(task, robot, Space::Actuation, task.limit_modes)
        .unwrap()
        .with_hold_tolerance(tolerance)
}

fn transmission() -> Transmission {
    Transmission::from_spec(&testing::task().transmission).unwrap()
}

/// The gradient method's own part of an outcome: its iterates and best solution.
fn gradient_part(outcome: &DesignOutcome) -> (&[GradientIterate], Option<&Solution>) {
    match &outcome.method {
        MethodOutcome::Gradient {
            iterates,
            best_solution,
            ..
        } => (iterates, best_solution.as_deref()),
        MethodOutcome::Cmaes { .. } => panic!("a CMA-ES outcome"),
    }
}

/// The candidate starts and the fallbacks solved on 1, 2 or 3 threads, and the descents side by
/// side on as many, give the same record: the same solves in the same order, the same
/// descents, the same best design.
#[test]
fn the_outcome_does_not_depend_on_the_threads() {
    // 1 kg held at rest at the ends: the designs whose motors cannot hold it are
    // infeasible at once, so that fallbacks are solved, in batches.
    let task = at(testing::held_task(), 1.0);
    let settings = GradientSettings {
        spread: 3,
        fallbacks: 8,
        descents: 3,
        // Two quasi-Newton iterations of each descent, with their line searches.
        max_iterations: 2,
        ..GradientSettings::default()
    };
    let on = |threads: usize| run(&task, &settings, Penalty::PAPER, threads).unwrap();
    let one = on(1);
    // Five of the first eight candidates cannot hold the load: four fallbacks are solved
    // (on 3 threads, in batches whose last two attempts are dropped).
    assert!(
        one.stop_reason.starts_with("8 candidate starts solved"),
        "{one:?}"
    );
    // Each descent's iterates, its start and up to two accepted steps, one descent after the
    // other, from the best candidate to the worst.
    let iterates = gradient_part(&one).0;
    assert!(iterates.len() > 3, "{iterates:?}");
    let firsts: Vec<&GradientIterate> = (iterates.iter().enumerate())
        .filter(|(i, it)| *i == 0 || iterates[i - 1].start != it.start)
        .map(|(_, it)| it)
        .collect();
    assert_eq!(firsts.len(), settings.descents, "{iterates:?}");
    assert!(
        firsts.windows(2).all(|w| w[0].cost <= w[1].cost),
        "{firsts:?}"
    );
    for threads in [2, 3] {
        let other = on(threads);
        assert_eq!(other.costs, one.costs, "{threads} threads");
        assert_eq!(other.stop_reason, one.stop_reason, "{threads} threads");
        assert_eq!(other.best_ratios, one.best_ratios, "{threads} threads");
        assert_eq!(other.best_cost, one.best_cost, "{threads} threads");
        assert_eq!(gradient_part(&other).0, gradient_part(&one).0);
    }
}

#[test]
fn descends_from_the_original_design_to_a_stationary_point() {
    // 0.5 kg: a payload the original design holds at rest (up to 0.585 kg).
    let task = at(testing::task(), 0.5);
    // The original design alone.
    let settings = GradientSettings {
        spread: 0,
        fallbacks: 0,
        descents: 1,
        ..GradientSettings::default()
    };
    let outcome = run(&task, &settings, Penalty::PAPER, 1).unwrap();
    let formulation = formulation(&task);
    let (iterates, _) = gradient_part(&outcome);
    let first = &iterates[0];
    let last = iterates.last().unwrap();
    assert!(
        last.cost < 0.5 * first.cost,
        "{} -> {}",
        first.cost,
        last.cost
    );
    assert_eq!(outcome.best_cost, Some(last.cost));
    assert!(formulation
        .transmission()
        .check_design(&outcome.best_ratios)
        .is_ok());
    // Costs fall monotonically along the accepted iterates.
    assert!(iterates.windows(2).all(|w| w[1].cost <= w[0].cost));
    // At the end the projected gradient step is short: a stationary point of the design box.
    let set = formulation.transmission().design_space();
    let moved: Vec<f64> = last
        .ratios
        .iter()
        .zip(&last.gradient)
        .map(|(x, g)| x - g / last.cost)
        .collect();
    let step = set
        .project(&moved)
        .iter()
        .zip(&last.ratios)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        step < 1e-2,
        "projected relative gradient step {step} at {:?}",
        last.ratios
    );
    assert_eq!(
        outcome.costs.len(),
        outcome.seconds.len(),
        "every solve ran"
    );
}

/// At 1.5 kg in actuation space the original design and the first Halton designs are
/// infeasible; the graded penalty descends from the best of them to a feasible design (one
/// that holds the load at rest too: at 3 kg, where the designs the elastic merit leads to
/// cannot hold it, the descent ends without one).
#[test]
fn graded_descent_reaches_feasibility_from_an_infeasible_start() {
    let task = at(testing::held_task(), 1.5);
    let formulation = formulation(&task);
    let descent = GradientSettings {
        spread: 3,
        fallbacks: 0,
        descents: 1,
        ..GradientSettings::default()
    };
    let flat = run(&task, &descent, Penalty::PAPER, 2);
    let none = matches!(flat, Err(GradientError::NoFeasibleStart { solved: 4 }));
    assert!(none, "no start is feasible: {flat:?}");
    let graded: Penalty = "graded".parse().unwrap();
    let settings = testing::settings();
    let outcome = run(&task, &descent, graded, 2).unwrap();
    let (iterates, best_solution) = gradient_part(&outcome);
    let first = &iterates[0];
    let start = solve_design(&formulation, &first.ratios, &settings).unwrap();
    assert!(!start.feasible, "the descent starts infeasible");
    // The merit falls along the accepted iterates, to a feasible design whose elastic solve
    // warm-started from the descent's solution gives the reported cost.
    assert!(iterates.windows(2).all(|w| w[1].cost <= w[0].cost));
    let best = solve_design_from(
        &formulation.elastic(),
        &outcome.best_ratios,
        &settings,
        best_solution,
    );
    let (best, _) = best.unwrap();
    assert!(best.feasible, "{}", best.status);
    assert!(
        outcome
            .best_cost
            .is_some_and(|cost| (best.cost - cost).abs() <= 1e-6 * best.cost),
        "{} against {:?}",
        best.cost,
        outcome.best_cost
    );
    // Every solve's fitness is recorded: the penalty band for infeasible ones.
    assert_eq!(outcome.costs.len(), outcome.seconds.len());
    assert!(outcome.costs.iter().any(|&c| (1e6..2e6).contains(&c)));
}

#[test]
fn default_starts_lie_in_the_design_space() {
    let t = transmission();
    let starts = default_starts(&t, 12);
    assert_eq!(starts.len(), 13);
    for start in starts {
        assert!(t.check_design(&start).is_ok(), "{start:?}");
    }
}
