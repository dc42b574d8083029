//! The experiment `codesign reproduce` runs on a task: the payloads at which the original design
//! is solved, those that are co-designed, those co-designed with the graded penalty, the payload
//! range of one design, and how much CMA-ES runs. A task file may give it as its optional
//! `experiment` section; a field left out takes the paper's value ([`Experiment::paper`]), so a
//! task without the section runs the paper's experiment (docs/model.md, section 13).
//!
//! Like the `solver` section, the experiment is no part of the problem a run solves: it says
//! which runs to make, so it stays out of the task hash and of the task that result files record.
//! The section is read and checked by `Experiment::from_section` in `read_experiment.rs`.

use crate::text::numbers;

/// Most CMA-ES seeds per case: 20 times the paper's 5.
pub const MAX_SEEDS: u64 = 100;

/// How much CMA-ES runs in an experiment: seeds per case, population and generations of the
/// runs on the cost, and population and generations of the co-design on the payload capacity
/// (one seed; each of its evaluations is about 10 solves).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Seeds per co-designed case (0..seeds).
    pub seeds: u64,
    /// Population of the runs on the cost.
    pub population: usize,
    /// Generations of the runs on the cost.
    pub generations: usize,
    /// Population of the capacity co-design.
    pub capacity_population: usize,
    /// Generations of the capacity co-design.
    pub capacity_generations: usize,
}

impl Budget {
    /// The paper's budget: 5 seeds of population 100 over 30 generations (and, beyond the
    /// paper, 20 designs over 10 generations for the capacity).
    pub const PAPER: Budget = Budget {
        seeds: 5,
        population: 100,
        generations: 30,
        capacity_population: 20,
        capacity_generations: 10,
    };

    /// The reduced budget of `reproduce --quick`, which ends in minutes.
    pub const QUICK: Budget = Budget {
        seeds: 2,
        population: 16,
        generations: 8,
        capacity_population: 6,
        capacity_generations: 2,
    };
}

/// The experiment of a task: every payload in kg, each list in the order its rows and runs
/// follow.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Payloads at which the original design is solved, in both spaces ("before").
    pub original_payloads_kg: Vec<f64>,
    /// Payloads co-designed in both spaces: CMA-ES per seed ("after") and the gradient method.
    pub codesign_payloads_kg: Vec<f64>,
    /// Payloads co-designed with the graded penalty in both spaces (CMA-ES per seed and the
    /// gradient method); empty: none.
    pub graded_payloads_kg: Vec<f64>,
    /// The payloads of one design for a range (CMA-ES on the mean cost, actuation space, graded
    /// penalty, seed 0); empty: none.
    pub range_payloads_kg: Vec<f64>,
    /// The budget of a full run.
    pub budget: Budget,
    /// The budget of `reproduce --quick`.
    pub quick_budget: Budget,
}

impl Default for Experiment {
    /// [`Experiment::paper`].
    fn default() -> Experiment {
        Experiment::paper()
    }
}

impl Experiment {
    /// The paper's experiment: the original design at 0, 1 and 3 kg, co-design at 1 and 3 kg,
    /// the graded penalty at 3 kg, one design for 1 to 3 kg, on [`Budget::PAPER`] (and
    /// [`Budget::QUICK`] for `--quick`).
    pub fn paper() -> Experiment {
        Experiment {
            original_payloads_kg: vec![0.0, 1.0, 3.0],
            codesign_payloads_kg: vec![1.0, 3.0],
            graded_payloads_kg: vec![3.0],
            range_payloads_kg: vec![1.0, 2.0, 3.0],
            budget: Budget::PAPER,
            quick_budget: Budget::QUICK,
        }
    }

    /// Whether this is the paper's experiment.
    pub fn is_paper(&self) -> bool {
        *self == Experiment::paper()
    }

    /// The payloads of the experiment in words, for the table's notes, e.g. `original design at
    /// 0, 1, 3 kg; co-design at 1, 3 kg; ...`.
    pub fn describe(&self) -> String {
        let kg = |payloads: &[f64]| format!("{} kg", numbers(payloads));
        let mut parts = vec![
            format!("original design at {}", kg(&self.original_payloads_kg)),
            format!("co-design at {}", kg(&self.codesign_payloads_kg)),
        ];
        if !self.graded_payloads_kg.is_empty() {
            parts.push(format!(
                "graded penalty at {}",
                kg(&self.graded_payloads_kg)
            ));
        }
        if !self.range_payloads_kg.is_empty() {
            parts.push(format!("one design for {}", kg(&self.range_payloads_kg)));
        }
        parts.join("; ")
    }
}
