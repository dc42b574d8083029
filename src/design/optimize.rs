//! The co-design loop: CMA-ES over the gear ratios, designs evaluated by worker processes, every
//! evaluation logged, and finished ones replayed on resume.

use super::cmaes::{Cmaes, CmaesSettings};
use super::evaluate::Evaluation;
use super::log::{EvaluationLog, Finished};
use super::workers::Pool;
use serde::{Deserialize, Serialize};

/// The cost statistics of one generation.
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

/// What a co-design run found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimizeOutcome {
    /// The best design seen.
    pub best_ratios: Vec<f64>,
    /// Its cost (the penalty if no feasible design was seen).
    pub best_cost: f64,
    /// Per-generation statistics.
    pub generations: Vec<GenerationSummary>,
    /// Every evaluation, in (generation, index) order.
    pub evaluations: Vec<Evaluation>,
    /// Evaluations replayed from the log instead of solved.
    pub replayed: usize,
    /// Why CMA-ES stopped.
    pub stop_reason: String,
}

/// Something that hears about progress (a progress bar); the no-op is `()`.
pub trait Progress {
    /// One more evaluation finished; `best` is the best cost so far.
    fn evaluated(&mut self, best: f64);
}

impl Progress for () {
    fn evaluated(&mut self, _best: f64) {}
}

fn median(costs: &[f64]) -> f64 {
    let mut sorted = costs.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => f64::NAN,
        len if len % 2 == 1 => sorted[len / 2],
        len => 0.5 * (sorted[len / 2 - 1] + sorted[len / 2]),
    }
}

/// Runs CMA-ES with `settings` in the box `bounds`, evaluating with `pool`, logging to `log`, and
/// replaying `finished` evaluations (from a resumed log) whose design matches exactly.
pub fn optimize(
    settings: CmaesSettings,
    bounds: &[[f64; 2]],
    pool: &mut Pool,
    log: &mut EvaluationLog,
    finished: &Finished,
    progress: &mut dyn Progress,
) -> Result<OptimizeOutcome, String> {
    let lower = bounds.iter().map(|b| b[0]).collect();
    let upper = bounds.iter().map(|b| b[1]).collect();
    let mut cmaes = Cmaes::new(settings, lower, upper)?;
    let mut outcome = OptimizeOutcome {
        best_ratios: Vec::new(),
        best_cost: f64::INFINITY,
        generations: Vec::new(),
        evaluations: Vec::new(),
        replayed: 0,
        stop_reason: String::new(),
    };
    let initial = cmaes.initial_population();
    let mut evaluations =
        evaluate_generation(0, &initial, pool, log, finished, &mut outcome, progress)?;
    cmaes.tell_initial(&record(0, evaluations, &mut outcome))?;
    while let Some(designs) = cmaes.ask() {
        let generation = cmaes.generation() + 1;
        evaluations = evaluate_generation(
            generation,
            &designs,
            pool,
            log,
            finished,
            &mut outcome,
            progress,
        )?;
        cmaes.tell(&record(generation, evaluations, &mut outcome))?;
    }
    outcome.stop_reason = cmaes
        .stop_reason()
        .map_or_else(|| "stopped".to_owned(), |reason| reason.to_string());
    let (best, cost) = cmaes.best().ok_or("CMA-ES has no best design")?;
    outcome.best_ratios = best.to_vec();
    outcome.best_cost = cost;
    Ok(outcome)
}

/// Adds a generation's evaluations to the outcome and returns their costs.
fn record(
    generation: usize,
    evaluations: Vec<Evaluation>,
    outcome: &mut OptimizeOutcome,
) -> Vec<f64> {
    let costs: Vec<f64> = evaluations.iter().map(|e| e.cost).collect();
    outcome.generations.push(GenerationSummary {
        generation,
        best: costs.iter().copied().fold(f64::INFINITY, f64::min),
        median: median(&costs),
        feasible: evaluations.iter().filter(|e| e.feasible).count(),
        evaluated: evaluations.len(),
    });
    outcome.evaluations.extend(evaluations);
    costs
}

fn evaluate_generation(
    generation: usize,
    designs: &[Vec<f64>],
    pool: &mut Pool,
    log: &mut EvaluationLog,
    finished: &Finished,
    outcome: &mut OptimizeOutcome,
    progress: &mut dyn Progress,
) -> Result<Vec<Evaluation>, String> {
    let mut slots: Vec<Option<Evaluation>> = vec![None; designs.len()];
    let mut pending = Vec::new();
    for (index, ratios) in designs.iter().enumerate() {
        match finished.get(&(generation, index)) {
            Some(evaluation) if evaluation.ratios == *ratios => {
                outcome.best_cost = outcome.best_cost.min(evaluation.cost);
                outcome.replayed += 1;
                progress.evaluated(outcome.best_cost);
                slots[index] = Some(evaluation.clone());
            }
            _ => pending.push((index, ratios.clone())),
        }
    }
    let best = &mut outcome.best_cost;
    let solved = pool.evaluate_all(&pending, |index, evaluation| {
        *best = best.min(evaluation.cost);
        progress.evaluated(*best);
        log.append(generation, index, evaluation)
    })?;
    for ((index, _), evaluation) in pending.iter().zip(solved) {
        slots[*index] = Some(evaluation);
    }
    Ok(slots.into_iter().flatten().collect())
}
