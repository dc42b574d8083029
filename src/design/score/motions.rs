//! One design scored over a task's several motions (docs/model.md, "Several motions"): each
//! motion's problem solved and judged as a task of one motion, their verdicts made one, and
//! for a descent their merits: J = sum_i w_i J_i* (or max_i w_i J_i*), dJ/dr = sum_i w_i dJ_i*/dr
//! (or the active motion's). A payload range (`--objective range`) is such a set: the task's
//! motion once per payload, each of weight 1, their costs' mean J = (1/n) sum_i J_i*.
//!
//! A design infeasible for any motion is infeasible: with the flat penalty by the first such
//! motion (the rest are not solved), with the graded one by the summed shortfall of every
//! motion.

use super::merit::Merit;
use super::objective::{Objective, ScoreError};
use super::solves::{solved, unheld};
use super::{Score, SolveStatus, Verdict};
use crate::design::penalty::Grading;
use codesign_core::ipopt;
use codesign_core::model::task::{LimitModes, MotionTask, MotionsScore, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{SolveSettings, StartPoint};
use codesign_core::transmission::Transmission;

/// One motion's problem.
#[derive(Debug)]
pub struct MotionProblem {
    /// The motion's name (a payload range's: its payload, `1 kg`).
    pub name: String,
    /// What reasons call it: `motion NAME`, or a payload range's `at 1 kg`.
    pub label: String,
    /// Its weight w_i.
    pub weight: f64,
    /// Its trajectory problem (elastic for a graded penalty), at its payload.
    pub formulation: Formulation,
}

/// How the weighted costs w_i J_i* of the problems make one score.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aggregate {
    /// A task's `motions_score`: the weighted sum or the worst.
    Motions(MotionsScore),
    /// The mean of a payload range: the sum in order divided by the number of payloads (so
    /// that it gives the bits the range's mean always gave).
    Mean,
}

impl Aggregate {
    /// The score of `weighted` (in order) with the index of the active problem of the worst;
    /// None for an empty list.
    pub fn combine(self, weighted: &[f64]) -> Option<(f64, Option<usize>)> {
        match self {
            Aggregate::Motions(score) => score.combine(weighted),
            Aggregate::Mean => (MotionsScore::Sum.combine(weighted))
                .map(|(sum, _)| (sum / weighted.len() as f64, None)),
        }
    }

    /// The factor of the weighted sum of gradients: 1 / n for the mean of n, else 1.
    fn scale(self, problems: usize) -> f64 {
        match self {
            Aggregate::Mean => 1.0 / problems as f64,
            Aggregate::Motions(_) => 1.0,
        }
    }
}

/// The problems of a task's motions, in the task's order (or of a payload range, in its
/// order), and how their costs make one.
#[derive(Debug)]
pub struct Motions {
    /// One per motion.
    pub problems: Vec<MotionProblem>,
    /// Their weighted sum, the worst, or a payload range's mean.
    pub score: Aggregate,
}

impl Motions {
    /// The problems of `task`'s motions on `robot` in `space` under `modes`, solved with
    /// `solve`: each motion's task formulated as a task of one motion, minimising its copper
    /// losses for the energy `objective` and its duration for the time objective (its pure
    /// minimum-time problem), elastic for a graded penalty. For the range `objective` the
    /// motions are the task's one motion at each of its payloads, of weight 1, and their mean.
    pub fn new(
        task: &Task,
        robot: &Robot,
        space: Space,
        modes: LimitModes,
        solve: &SolveSettings,
        objective: &Objective,
        grading: Grading,
    ) -> Result<Motions, ScoreError> {
        let problem = |(label, motion): (String, MotionTask)| {
            let task = objective.task(&motion.task);
            let hard = Formulation::new(&task, robot.clone(), space, modes)?;
            let hard = (objective.shape(hard, &motion.task))
                .with_hold_tolerance(solve.constraint_tolerance());
            let hard = match objective {
                Objective::Energy => hard.minimising_copper_loss()?,
                _ => hard,
            };
            let base = match grading {
                Grading::Flat => hard,
                Grading::Graded => hard.elastic(),
            };
            Ok(MotionProblem {
                formulation: base.with_payload(task.payload.mass_kg)?,
                name: motion.name,
                label,
                weight: motion.weight,
            })
        };
        let (motions, score) = match objective {
            Objective::Range(range) => (payloads(task, &range.payloads_kg), Aggregate::Mean),
            _ => (
                (task.motion_tasks().into_iter())
                    .map(|motion| (format!("motion {}", motion.name), motion))
                    .collect(),
                Aggregate::Motions(task.motions_score),
            ),
        };
        let problems = (motions.into_iter())
            .map(problem)
            .collect::<Result<Vec<_>, ScoreError>>()?;
        Ok(Motions { problems, score })
    }

    /// The design space (every motion's problem has the task's).
    pub fn transmission(&self) -> &Transmission {
        self.problems[0].formulation.transmission()
    }

    /// Each problem with its label in reasons, `motion NAME` (or `at 1 kg`).
    pub fn labelled(&self) -> Vec<(String, &Formulation)> {
        (self.problems.iter())
            .map(|p| (p.label.clone(), &p.formulation))
            .collect()
    }

    /// The problems' formulations, in order.
    pub fn formulations(&self) -> Vec<&Formulation> {
        self.problems.iter().map(|p| &p.formulation).collect()
    }

    /// The score of valid `ratios`, held at every motion's ends, each motion solved from the
    /// standard guess (with the flat penalty up to the first not feasible).
    pub fn score(&self, settings: &SolveSettings, ratios: &[f64], graded: bool) -> Score {
        let mut scores = Vec::new();
        for problem in &self.problems {
            let score = solved(&problem.formulation, settings, ratios, None).0;
            let feasible = score.verdict.is_feasible();
            scores.push(score);
            if !graded && !feasible {
                break;
            }
        }
        self.combine(&scores, graded)
    }

    /// The score of valid `ratios` for a descent and its merit: each motion scored for a descent
    /// from its start in `starts` (none: the standard guess) by `one`, as a task of one motion
    /// is; with the flat penalty (`graded` false) up to the first motion not feasible. The
    /// verdict is the one [`Motions::score`] reaches from the same solves.
    pub fn descend(
        &self,
        graded: bool,
        ratios: &[f64],
        starts: &[StartPoint],
        one: impl Fn(&Formulation, Option<&StartPoint>) -> (Score, Option<Merit>),
    ) -> (Score, Option<Merit>) {
        let held = unheld(&self.labelled(), ratios);
        if let (Some(verdict), false) = (&held, graded) {
            return (Score::unsolved(verdict.clone()), None);
        }
        let (mut scores, mut merits) = (Vec::new(), Vec::new());
        for (i, problem) in self.problems.iter().enumerate() {
            let (score, merit) = one(&problem.formulation, starts.get(i));
            let feasible = score.verdict.is_feasible();
            scores.push(score);
            merits.push(merit);
            if !graded && !feasible {
                break;
            }
        }
        let mut score = self.combine(&scores, graded);
        // As for one motion, a design not held at rest is infeasible by the hold alone.
        if let Some(verdict) = held {
            score.verdict = verdict;
        }
        let merit = self.merit(merits, &score.verdict);
        (score, merit)
    }

    /// The score of the motions' scores in order (a flat penalty's list may end at its first
    /// motion not feasible): feasible with the weighted sum, the worst weighted cost or the mean
    /// when each is feasible; with the flat penalty the first verdict that is not; with the
    /// graded one infeasible by the summed shortfall, unless a solve judged nothing. Reasons
    /// name the motion (or the payload).
    fn combine(&self, scores: &[Score], graded: bool) -> Score {
        let iterations = scores.iter().map(|s| s.iterations).sum();
        let seconds = scores.iter().map(|s| s.seconds).sum();
        let (mut weighted, mut short, mut reasons, mut status) = (Vec::new(), 0.0, vec![], None);
        for (problem, score) in self.problems.iter().zip(scores) {
            let label = &problem.label;
            match &score.verdict {
                Verdict::Feasible { cost, .. } => weighted.push(problem.weight * cost),
                Verdict::Infeasible {
                    shortfall,
                    reason,
                    status: why,
                } if graded => {
                    short += shortfall;
                    reasons.push(format!("{label}: {reason}"));
                    status.get_or_insert_with(|| why.clone());
                }
                verdict => {
                    return Score {
                        verdict: verdict.clone().labelled(label),
                        iterations,
                        seconds,
                    }
                }
            }
        }
        let verdict = match status {
            Some(status) => Verdict::Infeasible {
                shortfall: short,
                reason: reasons.join("; "),
                status,
            },
            None => Verdict::Feasible {
                // A task's list of motions is never empty.
                cost: self
                    .score
                    .combine(&weighted)
                    .map_or(f64::NAN, |(cost, _)| cost),
                status: SolveStatus::Ipopt(ipopt::Status::SolveSucceeded.name()),
            },
        };
        Score {
            verdict,
            iterations,
            seconds,
        }
    }

    /// The merit of the motions' merits when every motion has one: the weighted sum (or mean)
    /// of their values and gradients, or the worst weighted value with the active motion's
    /// weighted gradient; its feasible cost the cost of `verdict` when feasible; its starts each
    /// motion's, in order.
    fn merit(&self, merits: Vec<Option<Merit>>, verdict: &Verdict) -> Option<Merit> {
        if merits.len() != self.problems.len() {
            return None;
        }
        let merits: Vec<Merit> = merits.into_iter().collect::<Option<_>>()?;
        let weights: Vec<f64> = self.problems.iter().map(|p| p.weight).collect();
        let weighted: Vec<f64> = (weights.iter().zip(&merits))
            .map(|(w, m)| w * m.value)
            .collect();
        let (value, active) = self.score.combine(&weighted)?;
        let ratios = merits[0].gradient.len();
        let scale = self.score.scale(merits.len());
        let gradient = match active {
            Some(a) => merits[a].gradient.iter().map(|g| weights[a] * g).collect(),
            None => (0..ratios)
                .map(|j| {
                    let sum: f64 = (weights.iter().zip(&merits))
                        .map(|(w, m)| w * m.gradient[j])
                        .sum();
                    sum * scale
                })
                .collect(),
        };
        let feasible_cost = match verdict {
            Verdict::Feasible { cost, .. } => Some(*cost),
            _ => None,
        };
        Some(Merit {
            value,
            gradient,
            feasible_cost,
            starts: merits.into_iter().flat_map(|m| m.starts).collect(),
        })
    }
}

/// The task's one motion at each of `payloads_kg` (in order), each of weight 1 and named by its
/// payload, labelled `at 1 kg` in reasons.
fn payloads(task: &Task, payloads_kg: &[f64]) -> Vec<(String, MotionTask)> {
    (payloads_kg.iter())
        .map(|&kg| {
            let mut task = task.clone();
            task.payload.mass_kg = kg;
            let motion = MotionTask {
                name: format!("{kg} kg"),
                weight: 1.0,
                task,
            };
            (format!("at {kg} kg"), motion)
        })
        .collect()
}
