//! A run's evaluations counted by the kind of verdict each got (feasible, infeasible, outside
//! the design space, or not judged), with the IPOPT iterations and solver time spent on each
//! kind: where a run's work went, for its summary and its result document.

use super::score::{Evaluation, Status};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The kind of verdict an evaluation got.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VerdictKind {
    /// A valid design whose trajectory problem was solved.
    Feasible,
    /// A valid design judged infeasible (by a solve, the elastic problem or the static hold).
    Infeasible,
    /// A design outside the design space (a bound or an order constraint broken), penalised
    /// without a solve.
    Invalid,
    /// No verdict on the design: the solver could not run, or its worker failed.
    Unjudged,
}

impl VerdictKind {
    /// The kind of `evaluation`'s verdict.
    pub fn of(evaluation: &Evaluation) -> VerdictKind {
        match &evaluation.status {
            _ if evaluation.feasible => VerdictKind::Feasible,
            Status::InvalidDesign => VerdictKind::Invalid,
            status if !status.is_judged() => VerdictKind::Unjudged,
            _ => VerdictKind::Infeasible,
        }
    }
}

/// The evaluations of one kind of verdict and what they cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VerdictCount {
    /// Evaluations.
    pub designs: usize,
    /// IPOPT iterations of their solves.
    pub iterations: usize,
    /// Wall time of their solves, s.
    pub seconds: f64,
}

impl VerdictCount {
    fn add(&mut self, other: &VerdictCount) {
        self.designs += other.designs;
        self.iterations += other.iterations;
        self.seconds += other.seconds;
    }
}

/// A run's evaluations by kind of verdict; every evaluation is in exactly one kind.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VerdictTally {
    /// Feasible designs.
    pub feasible: VerdictCount,
    /// Valid designs judged infeasible.
    pub infeasible: VerdictCount,
    /// Designs outside the design space (no solve: 0 iterations).
    pub invalid: VerdictCount,
    /// Evaluations that judged nothing (a solver error, a failed worker).
    pub unjudged: VerdictCount,
}

impl VerdictTally {
    /// The tally of `evaluations`.
    pub fn of<'a>(evaluations: impl IntoIterator<Item = &'a Evaluation>) -> VerdictTally {
        let mut tally = VerdictTally::default();
        for evaluation in evaluations {
            tally.add(evaluation);
        }
        tally
    }

    /// Counts one more evaluation.
    pub fn add(&mut self, evaluation: &Evaluation) {
        let count = self.kind_mut(VerdictKind::of(evaluation));
        count.add(&VerdictCount {
            designs: 1,
            iterations: evaluation.iterations,
            seconds: evaluation.seconds,
        });
    }

    /// Counts the evaluations of `other` too.
    pub fn merge(&mut self, other: &VerdictTally) {
        self.feasible.add(&other.feasible);
        self.infeasible.add(&other.infeasible);
        self.invalid.add(&other.invalid);
        self.unjudged.add(&other.unjudged);
    }

    /// The count of one kind.
    pub fn kind(&self, kind: VerdictKind) -> &VerdictCount {
        match kind {
            VerdictKind::Feasible => &self.feasible,
            VerdictKind::Infeasible => &self.infeasible,
            VerdictKind::Invalid => &self.invalid,
            VerdictKind::Unjudged => &self.unjudged,
        }
    }

    fn kind_mut(&mut self, kind: VerdictKind) -> &mut VerdictCount {
        match kind {
            VerdictKind::Feasible => &mut self.feasible,
            VerdictKind::Infeasible => &mut self.infeasible,
            VerdictKind::Invalid => &mut self.invalid,
            VerdictKind::Unjudged => &mut self.unjudged,
        }
    }

    /// Evaluations counted.
    pub fn evaluations(&self) -> usize {
        self.feasible.designs
            + self.infeasible.designs
            + self.invalid.designs
            + self.unjudged.designs
    }

    /// The share of the evaluations of `kind`, 0 to 1; None without evaluations.
    pub fn share(&self, kind: VerdictKind) -> Option<f64> {
        let total = self.evaluations();
        (total > 0).then(|| self.kind(kind).designs as f64 / total as f64)
    }
}

impl fmt::Display for VerdictTally {
    /// The shares of invalid and infeasible designs and the iterations and solver time of each
    /// kind, e.g. `invalid 3 of 16 (18.8%), infeasible 2 (12.5%); IPOPT iterations: feasible
    /// 410 (1.2 s), infeasible 3810 (9.8 s), invalid 0`; the unjudged ones only where any.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let percent = |kind| self.share(kind).map_or(0.0, |share| 100.0 * share);
        write!(
            f,
            "invalid {} of {} ({:.1}%), infeasible {} ({:.1}%)",
            self.invalid.designs,
            self.evaluations(),
            percent(VerdictKind::Invalid),
            self.infeasible.designs,
            percent(VerdictKind::Infeasible)
        )?;
        if self.unjudged.designs > 0 {
            write!(f, ", not judged {}", self.unjudged.designs)?;
        }
        let spent = |count: &VerdictCount| format!("{} ({:.1} s)", count.iterations, count.seconds);
        write!(
            f,
            "; IPOPT iterations: feasible {}, infeasible {}, invalid {}",
            spent(&self.feasible),
            spent(&self.infeasible),
            self.invalid.iterations
        )?;
        if self.unjudged.designs > 0 {
            write!(f, ", not judged {}", spent(&self.unjudged))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{VerdictKind, VerdictTally};
    use crate::design::penalty::Penalty;
    use crate::design::score::{Evaluation, Score, SolveStatus, Status, Verdict};

    /// An evaluation of `status`, feasible or not, with its iterations and seconds.
    fn evaluation(status: &str, feasible: bool, iterations: usize, seconds: f64) -> Evaluation {
        let mut evaluation = Evaluation::new(
            &[6.0],
            &Score::unsolved(Verdict::Invalid {
                distance: 1.0,
                reason: "r".into(),
            }),
            &Penalty::PAPER,
        );
        evaluation.status = Status::from(status);
        evaluation.feasible = feasible;
        evaluation.iterations = iterations;
        evaluation.seconds = seconds;
        evaluation
    }

    fn run() -> Vec<Evaluation> {
        vec![
            evaluation("Solve_Succeeded", true, 30, 0.5),
            evaluation("Solve_Succeeded", true, 12, 0.25),
            evaluation("Infeasible_Problem_Detected", false, 1900, 3.0),
            evaluation("Elastic_Deficit", false, 100, 1.0),
            evaluation("Static_Hold_Failed", false, 0, 0.0),
            evaluation("Invalid_Design", false, 0, 0.0),
            evaluation("Invalid_Design", false, 0, 0.0),
            evaluation("Worker_Failed", false, 0, 0.0),
        ]
    }

    #[test]
    fn each_verdict_is_of_one_kind() {
        let kinds: Vec<VerdictKind> = run().iter().map(VerdictKind::of).collect();
        use VerdictKind::*;
        assert_eq!(
            kinds,
            [Feasible, Feasible, Infeasible, Infeasible, Infeasible, Invalid, Invalid, Unjudged]
        );
        // A solver error is no verdict on the design, a capacity found a feasible one.
        assert_eq!(
            VerdictKind::of(&evaluation("Solver_Error", false, 5, 0.1)),
            Unjudged
        );
        let capacity = evaluation(
            &Status::Solved(SolveStatus::Capacity { probes: 7 }).to_string(),
            true,
            70,
            1.0,
        );
        assert_eq!(VerdictKind::of(&capacity), Feasible);
    }

    #[test]
    fn the_tally_counts_designs_iterations_and_seconds_by_kind() {
        let tally = VerdictTally::of(&run());
        assert_eq!(tally.evaluations(), 8);
        assert_eq!((tally.feasible.designs, tally.feasible.iterations), (2, 42));
        assert_eq!(tally.feasible.seconds, 0.75);
        assert_eq!(
            (tally.infeasible.designs, tally.infeasible.iterations),
            (3, 2000)
        );
        assert_eq!(tally.infeasible.seconds, 4.0);
        assert_eq!((tally.invalid.designs, tally.invalid.iterations), (2, 0));
        assert_eq!(tally.unjudged.designs, 1);
        assert_eq!(tally.share(VerdictKind::Invalid), Some(0.25));
        assert_eq!(tally.share(VerdictKind::Infeasible), Some(0.375));
        assert_eq!(VerdictTally::default().share(VerdictKind::Invalid), None);
        // Tallied in two parts and merged, the same.
        let evaluations = run();
        let mut merged = VerdictTally::of(&evaluations[..3]);
        merged.merge(&VerdictTally::of(&evaluations[3..]));
        assert_eq!(merged, tally);
    }

    #[test]
    fn the_tally_reads_as_shares_and_iterations() {
        let tally = VerdictTally::of(&run());
        assert_eq!(
            tally.to_string(),
            "invalid 2 of 8 (25.0%), infeasible 3 (37.5%), not judged 1; IPOPT iterations: \
             feasible 42 (0.8 s), infeasible 2000 (4.0 s), invalid 0, not judged 0 (0.0 s)"
        );
        let judged = VerdictTally::of(&run()[..7]);
        assert_eq!(
            judged.to_string(),
            "invalid 2 of 7 (28.6%), infeasible 3 (42.9%); IPOPT iterations: feasible 42 \
             (0.8 s), infeasible 2000 (4.0 s), invalid 0"
        );
        assert_eq!(
            VerdictTally::default().to_string(),
            "invalid 0 of 0 (0.0%), infeasible 0 (0.0%); IPOPT iterations: feasible 0 (0.0 s), \
             infeasible 0 (0.0 s), invalid 0"
        );
    }
}
