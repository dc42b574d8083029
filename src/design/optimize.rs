//! The co-design loop: CMA-ES over the gear ratios, designs evaluated by an [`Evaluator`]
//! (worker processes, or threads of this process), every evaluation logged when a log is given,
//! and finished ones replayed on resume.

use super::bounds::SampleDesigns;
use super::cmaes::{Cmaes, CmaesError, CmaesSettings};
use super::evaluate::{EvaluateError, Evaluator};
use super::outcome::{DesignOutcome, GenerationSummary, MethodOutcome};
use super::score::{Evaluation, Status};
use super::verdicts::VerdictTally;
use super::warm::WarmStart;
use crate::stats::median;
use crate::store;
use codesign_core::text::number;
use std::fmt;

/// The evaluation log of a co-design run: one entry per evaluation (see [`store::log`]).
pub type EvaluationLog = store::log::EvaluationLog<Evaluation>;

/// The finished evaluations of a resumed run by (generation, index).
pub type Finished = store::log::Finished<Evaluation>;

/// Why a CMA-ES run stopped without a result.
#[derive(Debug)]
pub enum OptimizeError {
    /// CMA-ES refused its settings or a generation's fitness.
    Cmaes(CmaesError),
    /// The evaluator stopped (its workers, the log, an interruption).
    Evaluate(EvaluateError),
    /// No solve judged a design: every evaluation failed for a reason not the design's, or was
    /// of a design outside the design space, which nothing solves.
    NotJudged {
        /// The evaluations made.
        evaluations: usize,
        /// Those that failed for a reason not the design's.
        unjudged: usize,
        /// Their status (a solver error, a failed worker).
        status: Status,
        /// Their reason.
        reason: Option<String>,
    },
    /// CMA-ES ended without a best design.
    NoBest,
    /// A feasible design costs at least the penalty, which then ranks penalised designs with
    /// or above feasible ones.
    PenaltyTooLow {
        /// The penalty's base.
        penalty: f64,
        /// The design.
        ratios: Vec<f64>,
        /// Its cost.
        cost: f64,
    },
}

impl fmt::Display for OptimizeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OptimizeError::Cmaes(error) => error.fmt(f),
            OptimizeError::Evaluate(error) => error.fmt(f),
            OptimizeError::NotJudged {
                evaluations,
                unjudged,
                status,
                reason,
            } => {
                let (which, others) = match unjudged == evaluations {
                    true => (format!("every one of the {evaluations}"), ""),
                    false => (
                        format!("{unjudged} of the {evaluations}"),
                        " and the others were of designs outside the design space, which no \
                         solve judges",
                    ),
                };
                write!(
                    f,
                    "{which} evaluations failed for a reason not the design's (the first: \
                     {status}: {}){others}; no design was judged, so no result is written (fix \
                     the cause, then resume: those designs are solved again)",
                    reason.as_deref().unwrap_or("no reason given")
                )
            }
            OptimizeError::NoBest => f.write_str("CMA-ES has no best design"),
            OptimizeError::PenaltyTooLow {
                penalty,
                ratios,
                cost,
            } => write!(
                f,
                "--penalty {}: the feasible design r = {ratios:?} costs {}, at or above it, so \
                 penalised designs would rank with or above feasible ones; choose a penalty \
                 above every feasible cost (the paper's 1e6)",
                number(*penalty),
                number(*cost)
            ),
        }
    }
}

impl std::error::Error for OptimizeError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            OptimizeError::Evaluate(error) => Some(error),
            _ => None,
        }
    }
}

impl From<EvaluateError> for OptimizeError {
    fn from(error: EvaluateError) -> OptimizeError {
        OptimizeError::Evaluate(error)
    }
}

/// The evaluation log of a run with the evaluations a resumed one finished before.
pub struct Logged<'a> {
    /// The log, open for appending.
    pub log: &'a mut EvaluationLog,
    /// Its finished evaluations, replayed where their design matches exactly.
    pub finished: &'a Finished,
}

/// What the CMA-ES loop gathers while it runs.
struct Run {
    generations: Vec<GenerationSummary>,
    evaluations: Vec<Evaluation>,
    replayed: usize,
}

/// Something that hears about progress (a progress line); the no-op is `()`.
pub trait Progress {
    /// One more evaluation finished: solved by this run, or `replayed` from a resumed run's
    /// log.
    fn evaluated(&mut self, evaluation: &Evaluation, replayed: bool);
}

impl Progress for () {
    fn evaluated(&mut self, _evaluation: &Evaluation, _replayed: bool) {}
}

/// How a run's samples become the designs its workers evaluate.
#[derive(Clone, Debug)]
pub struct Sampling<'a> {
    /// The box CMA-ES samples and the design made of each sample: the sample, its projection
    /// onto the space, or its image under the map from the unit box.
    pub designs: SampleDesigns<'a>,
    /// Whether the designs of a generation start from a solution of its mean.
    pub warm_start: WarmStart,
}

impl Sampling<'_> {
    /// The design whose solution the designs of a generation sampled around `mean` start from:
    /// the mean's design ([`SampleDesigns::mean_design`]), from generation 1 on (the initial
    /// population is drawn uniformly, around no mean); None when warm starts are off.
    fn anchor(&self, generation: usize, mean: &[f64]) -> Option<Vec<f64>> {
        (self.warm_start.is_on() && generation > 0).then(|| self.designs.mean_design(mean))
    }
}

/// Runs CMA-ES with `settings` in the box of `sampling.designs`, evaluating with `evaluator` the
/// design `sampling` makes of each sample, logging to `log` when given and replaying its
/// finished evaluations (from a resumed log) whose design matches exactly. Fails when no
/// evaluation judged a design (see [`check_evaluations`]).
pub fn optimize(
    settings: CmaesSettings,
    sampling: Sampling<'_>,
    evaluator: &mut dyn Evaluator,
    mut log: Option<Logged<'_>>,
    progress: &mut dyn Progress,
) -> Result<DesignOutcome, OptimizeError> {
    let designs_of = &sampling.designs;
    let (lower, upper) = designs_of.search_box();
    let mut cmaes = Cmaes::new(settings, lower, upper).map_err(OptimizeError::Cmaes)?;
    let mut outcome = Run {
        generations: Vec::new(),
        evaluations: Vec::new(),
        replayed: 0,
    };
    // The anchor of each generation (none for the initial population).
    let mut anchors = vec![None];
    let initial = designs_of.designs(&cmaes.initial_population());
    let mut evaluations = Generation {
        index: 0,
        anchor: None,
        evaluator,
        log: log.as_mut(),
    }
    .evaluate(&initial, &mut outcome, progress)?;
    let penalty = evaluator.penalty().base;
    let (fitness, feasible) = record(0, evaluations, penalty, &mut outcome)?;
    cmaes
        .tell_initial(&fitness, &feasible)
        .map_err(OptimizeError::Cmaes)?;
    while let Some(samples) = cmaes.ask() {
        let generation = cmaes.generation() + 1;
        let designs = designs_of.designs(&samples);
        let anchor = sampling.anchor(generation, cmaes.mean());
        evaluations = Generation {
            index: generation,
            anchor: anchor.as_deref(),
            evaluator,
            log: log.as_mut(),
        }
        .evaluate(&designs, &mut outcome, progress)?;
        anchors.push(anchor);
        let (fitness, feasible) = record(generation, evaluations, penalty, &mut outcome)?;
        cmaes
            .tell(&fitness, &feasible)
            .map_err(OptimizeError::Cmaes)?;
    }
    check_evaluations(&outcome.evaluations)?;
    finish(&cmaes, &sampling, outcome, &anchors)
}

/// The run's outcome once CMA-ES has stopped: its best design (as evaluated: the projection or
/// the image of CMA-ES's best sample where samples are clipped or mapped; none when no
/// evaluation was feasible), the anchor it was evaluated from, and every evaluation's cost and
/// time.
fn finish(
    cmaes: &Cmaes,
    sampling: &Sampling<'_>,
    outcome: Run,
    anchors: &[Option<Vec<f64>>],
) -> Result<DesignOutcome, OptimizeError> {
    let (best, cost) = cmaes.best().ok_or(OptimizeError::NoBest)?;
    // A design no evaluation found feasible is no result: the run reports none.
    let any_feasible = outcome.evaluations.iter().any(|e| e.feasible);
    // CMA-ES's best is a sample: the design evaluated for it is its projection when clipped,
    // its image when mapped.
    let best_ratios = if any_feasible {
        sampling.designs.design(best)
    } else {
        Vec::new()
    };
    let found = (outcome.evaluations.iter())
        .position(|e| e.ratios == best_ratios && e.cost.to_bits() == cost.to_bits());
    let population = cmaes.settings().population;
    Ok(DesignOutcome {
        best_cost: any_feasible.then_some(cost),
        best_ratios,
        costs: outcome.evaluations.iter().map(|e| e.cost).collect(),
        seconds: outcome
            .evaluations
            .iter()
            .filter(|e| e.iterations > 0)
            .map(|e| e.seconds)
            .collect(),
        verdicts: VerdictTally::of(&outcome.evaluations),
        stop_reason: cmaes
            .stop_reason()
            .map_or_else(|| "stopped".to_owned(), |reason| reason.to_string()),
        method: MethodOutcome::Cmaes {
            best_anchor: found.and_then(|i| anchors.get(i / population).cloned().flatten()),
            generations: outcome.generations,
            replayed: outcome.replayed,
        },
    })
}

/// Fails when no solve judged a design: evaluations failed for a reason that is not the
/// design's (a solver error, a crashed or lying worker), and the others, if any, were of
/// invalid designs, which nothing solves; the run's result would mean nothing. A run of
/// invalid designs alone has judged them all.
pub fn check_evaluations(evaluations: &[Evaluation]) -> Result<(), OptimizeError> {
    let not_judged = |e: &&Evaluation| !e.feasible && !e.status.is_judged();
    let solved = |e: &Evaluation| !not_judged(&e) && e.status != Status::InvalidDesign;
    let unjudged = evaluations.iter().filter(not_judged).count();
    match evaluations.iter().find(not_judged) {
        Some(first) if !evaluations.iter().any(solved) => Err(OptimizeError::NotJudged {
            evaluations: evaluations.len(),
            unjudged,
            status: first.status.clone(),
            reason: first.reason.clone(),
        }),
        _ => Ok(()),
    }
}

/// Fails when a feasible evaluation costs at least `penalty`, the base every penalised design
/// scores at least: CMA-ES would rank penalised designs with or above it.
fn check_penalty(evaluations: &[Evaluation], penalty: f64) -> Result<(), OptimizeError> {
    match evaluations.iter().find(|e| e.feasible && e.cost >= penalty) {
        Some(e) => Err(OptimizeError::PenaltyTooLow {
            penalty,
            ratios: e.ratios.clone(),
            cost: e.cost,
        }),
        None => Ok(()),
    }
}

/// Adds a generation's evaluations to the outcome and returns their costs and whether each was
/// feasible (CMA-ES's stopping tests ignore a generation with no feasible design); fails when a
/// feasible one costs at least `penalty` ([`check_penalty`]).
fn record(
    generation: usize,
    evaluations: Vec<Evaluation>,
    penalty: f64,
    outcome: &mut Run,
) -> Result<(Vec<f64>, Vec<bool>), OptimizeError> {
    check_penalty(&evaluations, penalty)?;
    let costs: Vec<f64> = evaluations.iter().map(|e| e.cost).collect();
    let feasible: Vec<bool> = evaluations.iter().map(|e| e.feasible).collect();
    outcome.generations.push(GenerationSummary {
        generation,
        best: costs.iter().copied().fold(f64::INFINITY, f64::min),
        median: median(&costs),
        feasible: evaluations.iter().filter(|e| e.feasible).count(),
        evaluated: evaluations.len(),
    });
    outcome.evaluations.extend(evaluations);
    Ok((costs, feasible))
}

/// One generation's evaluation: its index, the anchor its designs start from, the evaluator
/// and the log.
struct Generation<'g, 'l> {
    index: usize,
    anchor: Option<&'g [f64]>,
    evaluator: &'g mut dyn Evaluator,
    log: Option<&'g mut Logged<'l>>,
}

impl Generation<'_, '_> {
    /// Evaluates `designs`: a finished evaluation of the log whose design matches exactly is
    /// replayed, the others are evaluated and appended to the log as each finishes.
    fn evaluate(
        self,
        designs: &[Vec<f64>],
        outcome: &mut Run,
        progress: &mut dyn Progress,
    ) -> Result<Vec<Evaluation>, OptimizeError> {
        let generation = self.index;
        let mut slots: Vec<Option<Evaluation>> = vec![None; designs.len()];
        let mut pending = Vec::new();
        let finished = self.log.as_ref().map(|logged| logged.finished);
        for (index, ratios) in designs.iter().enumerate() {
            match finished.and_then(|finished| finished.get(&(generation, index))) {
                // A worker failure or solver error is no score of the design: solved again.
                Some(evaluation)
                    if evaluation.ratios == *ratios && evaluation.status.is_judged() =>
                {
                    outcome.replayed += 1;
                    progress.evaluated(evaluation, true);
                    slots[index] = Some(evaluation.clone());
                }
                _ => pending.push((index, ratios.clone())),
            }
        }
        let mut log = self.log;
        let solved = self
            .evaluator
            .evaluate(&pending, self.anchor, &mut |index, evaluation| {
                progress.evaluated(evaluation, false);
                match log.as_mut() {
                    Some(logged) => (logged.log.append(generation, index, evaluation))
                        .map_err(EvaluateError::Log),
                    None => Ok(()),
                }
            })?;
        for ((index, _), evaluation) in pending.iter().zip(solved) {
            slots[*index] = Some(evaluation);
        }
        Ok(slots.into_iter().flatten().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::check_evaluations;
    use crate::design::penalty::Penalty;
    use crate::design::score::{Evaluation, Score, SolveStatus, Verdict};

    fn penalised(verdict: Verdict) -> Evaluation {
        Evaluation::new(&[6.0], &Score::unsolved(verdict), &Penalty::PAPER)
    }

    #[test]
    fn a_run_fails_when_no_evaluation_judged_a_design() {
        let failed = |message: &str| {
            penalised(Verdict::SolverError {
                message: message.to_owned(),
            })
        };
        let alike = vec![failed("IPOPT rejected option `x` = 3"); 3];
        let error = check_evaluations(&alike).unwrap_err().to_string();
        assert_eq!(
            error,
            "every one of the 3 evaluations failed for a reason not the design's (the first: \
             Solver_Error: IPOPT rejected option `x` = 3); no design was judged, so no result is \
             written (fix the cause, then resume: those designs are solved again)"
        );
        let differing = vec![failed("a"), failed("b")];
        assert!(check_evaluations(&differing).is_err());
        // Invalid designs are judged without a solve: beside solver errors, no solve judged.
        let mut mixed = differing;
        mixed.push(penalised(Verdict::Invalid {
            distance: 1.0,
            reason: "r".into(),
        }));
        let error = check_evaluations(&mixed).unwrap_err().to_string();
        assert!(
            error.starts_with(
                "2 of the 3 evaluations failed for a reason not the design's (the first: \
                 Solver_Error: a) and the others were of designs outside the design space"
            ),
            "{error}"
        );
        mixed.push(penalised(Verdict::Infeasible {
            shortfall: 1.0,
            reason: "short".into(),
            status: SolveStatus::ElasticDeficit,
        }));
        assert!(check_evaluations(&mixed).is_ok(), "one design was judged");
        let invalid = vec![
            penalised(Verdict::Invalid {
                distance: 1.0,
                reason: "r".into()
            });
            2
        ];
        assert!(
            check_evaluations(&invalid).is_ok(),
            "the designs were judged"
        );
    }
}
