//! One design scored over a task's several motions: J and dJ*/dr against the single-motion
//! solves (weighted sum, worst), an infeasible motion named, objectives of one motion refused.

use super::*;
use codesign_core::model::task::{MotionEntry, MotionsScore, Task};
use codesign_core::problem::Space;
use codesign_core::testing;

/// An entry of `name` with `weight`, changing nothing else.
fn entry(name: &str, weight: f64) -> MotionEntry {
    MotionEntry {
        name: name.to_owned(),
        weight,
        payload_kg: None,
        start: None,
        goal: None,
        horizon: None,
        steps: None,
        ends: None,
        via: None,
        upright: None,
    }
}

/// The repository's held task on 20 intervals at 0 kg with two motions: its own (`pick`, w 1)
/// and a shorter one carrying 0.25 kg (`place`, w 2), scored by `score`.
fn two_motions(score: MotionsScore) -> Task {
    let mut task = testing::held_task();
    task.payload.mass_kg = 0.0;
    task.motion.steps = 20;
    let place = MotionEntry {
        goal: Some(vec![-2.5, -1.2, -1.2, 0.3].into()),
        payload_kg: Some(0.25),
        ..entry("place", 2.0)
    };
    task.motions = vec![entry("pick", 1.0), place];
    task.motions_score = score;
    task.validate().unwrap();
    task
}

/// The fitness of `task` for the cost objective in actuation space with the flat penalty.
fn cost_fitness(task: &Task) -> Fitness {
    let penalty = "flat".parse().unwrap();
    let settings = testing::settings();
    let modes = task.limit_modes;
    Fitness::new(
        task,
        &settings,
        Space::Actuation,
        modes,
        &Objective::Cost,
        penalty,
    )
    .unwrap()
}

/// Whether `a` and `b` agree to 1e-9, relative to the larger of 1 and |b|.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

/// The done-when of issue 52, item 4: at a fixed design, J of two motions is the weighted sum
/// of the single-motion solves and dJ*/dr the weighted sum of theirs; under `worst`, J is the
/// larger weighted J_i* and dJ*/dr the active motion's weighted gradient.
#[test]
fn two_motions_score_the_weighted_sum_or_the_worst_of_their_solves() {
    let ratios = [7.0, 5.0, 2.0, 2.0];
    let task = two_motions(MotionsScore::Sum);
    let singles: Vec<(f64, Merit)> = (task.motion_tasks().iter())
        .map(|motion| {
            let descent = cost_fitness(&motion.task).descend_from(&ratios, &[]);
            (
                motion.weight,
                descent.merit.expect("each motion is feasible"),
            )
        })
        .collect();
    let weighted: Vec<f64> = singles.iter().map(|(w, m)| w * m.value).collect();
    for score in [MotionsScore::Sum, MotionsScore::Worst] {
        let fitness = cost_fitness(&two_motions(score));
        let descent = fitness.descend_from(&ratios, &[]);
        let merit = descent.merit.clone().expect("a merit");
        let (expected, gradient): (f64, Vec<f64>) = match score {
            MotionsScore::Sum => (
                weighted.iter().sum(),
                (0..4)
                    .map(|j| singles.iter().map(|(w, m)| w * m.gradient[j]).sum())
                    .collect(),
            ),
            MotionsScore::Worst => {
                let a = if weighted[1] > weighted[0] { 1 } else { 0 };
                let (w, m) = &singles[a];
                (weighted[a], m.gradient.iter().map(|g| w * g).collect())
            }
        };
        assert!(close(merit.value, expected), "{score:?}: {merit:?}");
        for (found, expected) in merit.gradient.iter().zip(&gradient) {
            assert!(
                close(*found, *expected),
                "{score:?}: {merit:?} {gradient:?}"
            );
        }
        assert_eq!(merit.feasible_cost, Some(descent.evaluation.cost));
        assert_eq!(merit.starts.len(), 2);
        assert_eq!(fitness.implausible_merit(&descent.evaluation, &merit), None);
        // The evaluation CMA-ES makes agrees, and the merit's starts start a nearby design.
        let evaluated = fitness.evaluate(&ratios);
        assert!(
            evaluated.feasible && close(evaluated.cost, expected),
            "{evaluated:?}"
        );
        let near = fitness.descend_from(&[7.1, 5.0, 2.0, 2.0], &merit.starts);
        assert!(near.merit.is_some(), "{near:?}");
    }
    assert!(weighted[0] != weighted[1]);
}

/// A design infeasible for one motion is infeasible, by that motion, named; the capacity and
/// range objectives refuse a task with several motions.
#[test]
fn a_motion_too_fast_makes_the_design_infeasible_and_capacity_is_refused() {
    let mut task = two_motions(MotionsScore::Sum);
    task.motions[1].horizon = Some(codesign_core::model::task::Horizon::Fixed(0.05));
    task.motions[1].steps = Some(10);
    let fitness = cost_fitness(&task);
    let evaluation = fitness.evaluate(&task.transmission.original);
    assert!(
        !evaluation.feasible && evaluation.cost == 1e6,
        "{evaluation:?}"
    );
    let reason = evaluation.reason.unwrap();
    assert!(reason.starts_with("motion place: "), "{reason}");
    let penalty = "flat".parse().unwrap();
    let settings = testing::settings();
    let capacity = Objective::Capacity(Default::default());
    let modes = task.limit_modes;
    let error = Fitness::new(&task, &settings, Space::Joint, modes, &capacity, penalty)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("the capacity objective is of one motion, and the task lists 2"),
        "{error}"
    );
}

/// With the graded penalty a feasible design scores the same sum (the elastic problem's optimum
/// is J* where it is feasible) and its merit is the weighted sum of the motions' elastic merits.
#[test]
fn the_graded_penalty_scores_feasible_motions_as_the_flat_one() {
    let ratios = [7.0, 5.0, 2.0, 2.0];
    let task = two_motions(MotionsScore::Sum);
    let flat = cost_fitness(&task).evaluate(&ratios);
    let graded = Fitness::new(
        &task,
        &testing::settings(),
        Space::Actuation,
        task.limit_modes,
        &Objective::Cost,
        "graded".parse().unwrap(),
    )
    .unwrap();
    let descent = graded.descend_from(&ratios, &[]);
    assert!(descent.evaluation.feasible, "{descent:?}");
    let merit = descent.merit.expect("an elastic merit");
    assert!((descent.evaluation.cost - flat.cost).abs() <= 1e-6 * flat.cost);
    assert!(
        (merit.value - flat.cost).abs() <= 1e-6 * flat.cost,
        "{merit:?}"
    );
    assert_eq!(merit.feasible_cost, Some(descent.evaluation.cost));
}

/// The fitness of `objective` for `task` in actuation space with `penalty` (`flat`, `graded`).
fn fitness_of(task: &Task, objective: &Objective, penalty: &str) -> Fitness {
    let settings = testing::settings();
    let (modes, penalty) = (task.limit_modes, penalty.parse().unwrap());
    Fitness::new(task, &settings, Space::Actuation, modes, objective, penalty).unwrap()
}

/// Issue 52, item 4: a payload range is the motions of its payloads, each of weight 1, and
/// their mean: its J is the mean of the single-payload solves to the last bit (summed in order,
/// then divided, as the range always summed), flat and graded, and its merit's dJ*/dr the mean
/// of theirs (the elastic ones' under the graded penalty).
#[test]
fn a_payload_range_scores_the_mean_of_its_payloads_solves() {
    let ratios = [7.0, 5.0, 2.0, 2.0];
    let mut task = testing::held_task();
    task.motion.steps = 20;
    let payloads = [0.0, 0.25];
    let range = Objective::Range(PayloadRange {
        payloads_kg: payloads.to_vec(),
    });
    for penalty in ["flat", "graded"] {
        let singles: Vec<Descent> = (payloads.iter())
            .map(|&kg| {
                let mut one = task.clone();
                one.payload.mass_kg = kg;
                fitness_of(&one, &Objective::Cost, penalty).descend_from(&ratios, &[])
            })
            .collect();
        assert!(singles.iter().all(|d| d.evaluation.feasible), "{singles:?}");
        let costs: Vec<f64> = singles.iter().map(|d| d.evaluation.cost).collect();
        let fitness = fitness_of(&task, &range, penalty);
        let evaluation = fitness.evaluate(&ratios);
        assert!(evaluation.feasible, "{penalty}: {evaluation:?}");
        assert_eq!(
            evaluation.cost,
            (costs[0] + costs[1]) / 2.0,
            "{penalty}: {costs:?}"
        );
        let motions = fitness.motions().expect("a range is scored as motions");
        let labels: Vec<String> = motions.labelled().into_iter().map(|(l, _)| l).collect();
        assert_eq!(labels, ["at 0 kg", "at 0.25 kg"]);
        let descent = fitness.descend_from(&ratios, &[]);
        let merit = descent.merit.expect("a range's merit");
        for j in 0..ratios.len() {
            let mean = (singles.iter())
                .map(|d| d.merit.as_ref().expect("a merit").gradient[j])
                .sum::<f64>()
                / 2.0;
            assert!(
                close(merit.gradient[j], mean),
                "{penalty}: r{j}: {mean} {merit:?}"
            );
        }
        assert_eq!(merit.starts.len(), 2);
    }
}
