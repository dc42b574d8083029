//! What an outer method found, in one type for CMA-ES and the gradient method, with the
//! progress records each keeps.

use super::verdicts::VerdictTally;
use codesign_core::ipopt::Solution;
use codesign_core::solve::StartPoint;
use serde::{Deserialize, Serialize};

/// The result of a co-design run, whichever method made it.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignOutcome {
    /// The best design seen; empty when no evaluation found a design feasible (an infeasible
    /// design is never reported as the best).
    pub best_ratios: Vec<f64>,
    /// Its fitness: the optimal cost J, or minus the capacity; None with no best design (a
    /// penalty is no cost of a design).
    pub best_cost: Option<f64>,
    /// The fitness of every evaluation, in order.
    pub costs: Vec<f64>,
    /// The wall time of every inner solve that ran, s, in order (replayed ones included).
    pub seconds: Vec<f64>,
    /// The evaluations by kind of verdict, with the iterations and time of each kind (replayed
    /// ones included, as the log holds them).
    pub verdicts: VerdictTally,
    /// Why the method stopped, in words.
    pub stop_reason: String,
    /// What only the method that ran keeps.
    pub method: MethodOutcome,
}

/// The part of an outcome that one method alone keeps.
#[derive(Clone, Debug, PartialEq)]
pub enum MethodOutcome {
    /// CMA-ES's.
    Cmaes {
        /// Per-generation statistics.
        generations: Vec<GenerationSummary>,
        /// The design whose solution the best design's solve started from (with warm starts:
        /// the anchor of the generation that found it; see `WarmStart`).
        best_anchor: Option<Vec<f64>>,
        /// Evaluations replayed from a resumed run's log instead of solved.
        replayed: usize,
    },
    /// The gradient method's.
    Gradient {
        /// Accepted iterates of every descent.
        iterates: Vec<GradientIterate>,
        /// The inner solution behind `best_cost` (the method's warm-started solves can reach a
        /// lower local optimum than a cold solve of the same design).
        best_solution: Option<Box<Solution>>,
        /// The starts the best design's solve began at (none: the standard guess): where this
        /// process solves it again to confirm a worker's answer.
        best_from: Vec<StartPoint>,
    },
}

/// Where the solve of an outcome's best design starts, to find the solution behind its cost.
pub enum BestStart<'a> {
    /// From this point, where the gradient method's solve of it began (the solution of the
    /// design it was a trial from): solved again from there, it gives the same solution. (From
    /// the best design's own solution a minimum-time solve may move to another local optimum,
    /// docs/model.md, section 6.)
    Point(&'a StartPoint),
    /// From the solution of this anchor (CMA-ES with warm starts).
    Anchor(&'a [f64]),
    /// From the standard initial guess.
    Cold,
}

impl DesignOutcome {
    /// Where the solve of the best design starts.
    pub fn best_start(&self) -> BestStart<'_> {
        match &self.method {
            MethodOutcome::Cmaes {
                best_anchor: Some(anchor),
                ..
            } => BestStart::Anchor(anchor),
            MethodOutcome::Gradient { best_from, .. } if best_from.len() == 1 => {
                BestStart::Point(&best_from[0])
            }
            _ => BestStart::Cold,
        }
    }
}

/// The cost statistics of one CMA-ES generation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GenerationSummary {
    /// Generation (0 = the initial population).
    pub generation: usize,
    /// Best cost in the generation.
    pub best: f64,
    /// Median cost in the generation.
    pub median: f64,
    /// Designs with a feasible trajectory.
    pub feasible: usize,
    /// Designs evaluated.
    pub evaluated: usize,
}

/// One accepted iterate of the gradient method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GradientIterate {
    /// Which start it belongs to.
    pub start: usize,
    /// The design.
    pub ratios: Vec<f64>,
    /// Its merit: the optimal cost J*, or with the graded penalty the elastic problem's optimal
    /// penalised objective (J* where the design is feasible).
    pub cost: f64,
    /// The merit's gradient with respect to the ratios.
    pub gradient: Vec<f64>,
}
