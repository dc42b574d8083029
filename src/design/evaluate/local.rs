//! The evaluator in this process: designs scored on threads, each solve with its own IPOPT
//! problem. The LDLᵀ may solve on several threads at once; MUMPS is not thread-safe, so with it
//! one thread solves (and `ipopt::solve` serialises its solves process-wide besides).

use super::{Designs, Done, EvaluateError, Evaluator};
use crate::design::penalty::Penalty;
use crate::design::score::{Descent, Evaluation, Fitness};
use crate::parallel;
use codesign_core::ipopt::Solution;
use codesign_core::signals;
use codesign_core::solve::StartPoint;

/// Designs scored by `threads` threads of this process with one [`Fitness`].
pub struct InProcess {
    fitness: Fitness,
    threads: usize,
    /// The last anchor and its solution (None when it is invalid or infeasible), solved once
    /// as a worker does.
    anchored: Option<(Vec<f64>, Option<Solution>)>,
}

impl InProcess {
    /// An evaluator scoring with `fitness` on at most `threads` threads (at least one; one
    /// when the linear solver is MUMPS).
    pub fn new(fitness: Fitness, threads: usize) -> InProcess {
        let threads = parallel::solve_threads(Some(threads), fitness.linear_solver());
        InProcess {
            fitness,
            threads,
            anchored: None,
        }
    }

    /// The warm start of designs sampled around `anchor`: its solution, solved when the anchor
    /// changed (see [`Fitness::anchor`]).
    fn warm_start(&mut self, anchor: Option<&[f64]>) -> Option<&Solution> {
        let anchor = anchor?;
        if self.anchored.as_ref().is_none_or(|(a, _)| a != anchor) {
            self.anchored = Some((anchor.to_vec(), self.fitness.anchor(anchor)));
        }
        self.anchored.as_ref()?.1.as_ref()
    }
}

impl InProcess {
    /// Runs `work` on every index below `count` on the evaluator's threads
    /// ([`parallel::in_order`]); `heard` hears each result as it finishes. A host's request to
    /// stop ends the work unfinished: [`EvaluateError::Interrupted`]. A result that finishes
    /// once the stop was asked may come from a stopped solve: it is neither heard nor returned.
    fn on_threads<T: Send>(
        &self,
        count: usize,
        work: impl Fn(usize) -> T + Sync,
        mut heard: impl FnMut(usize, &T) -> Result<(), EvaluateError>,
    ) -> Result<Vec<T>, EvaluateError> {
        let unstopped = |index: usize, result: &T| match signals::stop_requested() {
            true => Err(EvaluateError::Interrupted),
            false => heard(index, result),
        };
        let results = parallel::in_order(
            count,
            self.threads,
            signals::stop_requested,
            work,
            unstopped,
        )?;
        let finished: Option<Vec<T>> = results.into_iter().collect();
        match signals::stop_requested() {
            true => Err(EvaluateError::Interrupted),
            false => finished.ok_or(EvaluateError::Interrupted),
        }
    }
}

impl Evaluator for InProcess {
    fn penalty(&self) -> Penalty {
        self.fitness.penalty()
    }

    fn evaluate(
        &mut self,
        designs: &Designs,
        anchor: Option<&[f64]>,
        done: Done<'_>,
    ) -> Result<Vec<Evaluation>, EvaluateError> {
        let warm = self.warm_start(anchor).cloned();
        let fitness = &self.fitness;
        self.on_threads(
            designs.len(),
            |index| fitness.evaluate_from(&designs[index].1, warm.as_ref()),
            |index, evaluation| done(designs[index].0, evaluation),
        )
    }

    fn descend(
        &self,
        designs: &Designs,
        start: &[StartPoint],
    ) -> Result<Vec<Descent>, EvaluateError> {
        let fitness = &self.fitness;
        self.on_threads(
            designs.len(),
            |index| fitness.descend_from(&designs[index].1, start),
            |_, _| Ok(()),
        )
    }

    fn parallelism(&self) -> usize {
        self.threads
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::score::Objective;
    use codesign_core::problem::Space;

    fn fitness() -> Fitness {
        let task = codesign_core::testing::task();
        let settings = codesign_core::testing::settings();
        let (space, modes) = (Space::Actuation, task.limit_modes);
        Fitness::new(
            &task,
            &settings,
            space,
            modes,
            &Objective::Cost,
            Penalty::PAPER,
        )
        .unwrap()
    }

    /// The evaluations with their times zeroed (the only part that differs between runs).
    fn untimed(evaluations: Vec<Evaluation>) -> Vec<Evaluation> {
        let zero = |e: Evaluation| Evaluation { seconds: 0.0, ..e };
        evaluations.into_iter().map(zero).collect()
    }

    #[test]
    fn threads_answer_as_one_thread_and_the_scoring_itself_in_the_order_asked() {
        let designs: Vec<(usize, Vec<f64>)> = [
            [9.0, 7.7, 3.0, 3.0],
            [20.0, 7.7, 3.0, 3.0],
            [8.9, 7.6, 2.9, 2.95],
        ]
        .iter()
        .enumerate()
        .map(|(id, ratios)| (id + 10, ratios.to_vec()))
        .collect();
        let anchor = [9.0, 7.7, 3.0, 3.0];
        let mut heard = Vec::new();
        let mut two = InProcess::new(fitness(), 2);
        let threaded = two
            .evaluate(&designs, Some(&anchor), &mut |id, _| {
                heard.push(id);
                Ok(())
            })
            .unwrap();
        heard.sort_unstable();
        assert_eq!(heard, vec![10, 11, 12]);
        let mut one = InProcess::new(fitness(), 1);
        let single = one
            .evaluate(&designs, Some(&anchor), &mut |_, _| Ok(()))
            .unwrap();
        let own = fitness();
        let warm = own.anchor(&anchor);
        let direct: Vec<Evaluation> = (designs.iter())
            .map(|(_, ratios)| own.evaluate_from(ratios, warm.as_ref()))
            .collect();
        assert_eq!(untimed(threaded.clone()), untimed(direct));
        assert_eq!(untimed(threaded), untimed(single));
    }

    /// A result that finishes once its work was asked to stop (as a stopped solve's verdict
    /// does) is neither heard, which would log it, nor returned.
    #[test]
    fn results_finished_after_a_stop_are_neither_heard_nor_returned() {
        let token = signals::StopToken::new();
        let evaluator = InProcess::new(fitness(), 2);
        let mut heard = 0;
        let stop_midway = |index: usize| {
            token.stop();
            index
        };
        let outcome = signals::under(Some(token.clone()), || {
            evaluator.on_threads(2, stop_midway, |_, _| {
                heard += 1;
                Ok(())
            })
        });
        assert!(
            matches!(outcome, Err(EvaluateError::Interrupted)),
            "{outcome:?}"
        );
        assert_eq!(heard, 0);
    }
}
