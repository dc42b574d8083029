//! Whether an evaluation could have come from the scoring: what a worker answers, or a log
//! replays, is checked against what [`super::Fitness`] can produce before a run believes it.

use super::record::{Evaluation, SolveStatus, Status};
use crate::design::penalty::Penalty;
use codesign_core::ipopt;
use codesign_core::text::number;

/// The longest reason the scoring writes, bytes: a few lines naming ends, motors and limits.
pub const MAX_REASON_BYTES: usize = 4096;

/// The largest multiple of the penalty's base a penalised design scores (graded, invalid:
/// base (2 + e / (1 + e)) < 3 base).
const LARGEST_PENALTY_MULTIPLE: f64 = 3.0;

impl Evaluation {
    /// Why this evaluation cannot be one of the scoring's under `penalty` (None when it can):
    /// a cost that is not finite, or negative where the objective's fitness cannot be
    /// (`negative_fitness`: the capacity's), a feasible design of a status no solve gives it, a
    /// penalised cost outside the penalty's range, a status no solve gives, a time that is not
    /// a non-negative number, or a reason longer than [`MAX_REASON_BYTES`].
    pub fn implausible(&self, penalty: &Penalty, negative_fitness: bool) -> Option<String> {
        let (cost, base) = (self.cost, penalty.base);
        if !cost.is_finite() || (cost < 0.0 && !negative_fitness) {
            return Some(format!(
                "a fitness of {}, which no design has",
                number(cost)
            ));
        }
        if !(self.seconds.is_finite() && self.seconds >= 0.0) {
            return Some(format!("a solve time of {} s", number(self.seconds)));
        }
        if let Some(reason) = self.reason.as_ref().filter(|r| r.len() > MAX_REASON_BYTES) {
            return Some(format!(
                "a reason of {} bytes, where the scoring writes at most {MAX_REASON_BYTES}",
                reason.len()
            ));
        }
        if let Status::Solved(SolveStatus::Ipopt(name)) = &self.status {
            if !ipopt::Status::is_name(name) {
                return Some(format!("the status {name:?}, which IPOPT does not return"));
            }
        }
        let penalised = base..=LARGEST_PENALTY_MULTIPLE * base;
        match (self.feasible, &self.status) {
            // A feasible cost at or above the penalty is the run's to refuse (the penalty is
            // too low for the task: `optimize::check_penalty`).
            (true, Status::Solved(_)) => None,
            (true, status) => Some(format!("a feasible design with the status {status}")),
            (false, _) if penalised.contains(&cost) => None,
            (false, _) => Some(format!(
                "an infeasible design at a fitness of {}, outside the penalty's {} to {}",
                number(cost),
                number(*penalised.start()),
                number(*penalised.end())
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Evaluation, MAX_REASON_BYTES};
    use crate::design::penalty::Penalty;
    use crate::design::score::record::{SolveStatus, Status};

    fn evaluation(cost: f64, feasible: bool, status: &str) -> Evaluation {
        Evaluation {
            ratios: vec![9.0, 7.7, 3.0, 3.0],
            cost,
            feasible,
            status: Status::from(status),
            iterations: 35,
            seconds: 0.02,
            reason: None,
        }
    }

    #[test]
    fn only_what_the_scoring_can_write_is_plausible() {
        let flat = Penalty::PAPER;
        let graded: Penalty = "graded".parse().unwrap();
        assert_eq!(
            evaluation(50.06, true, "Solve_Succeeded").implausible(&flat, false),
            None
        );
        assert_eq!(
            evaluation(1e6, false, "Elastic_Deficit").implausible(&flat, false),
            None
        );
        assert_eq!(
            evaluation(1.4e6, false, "Elastic_Deficit").implausible(&graded, false),
            None
        );
        assert_eq!(
            evaluation(-2.2, true, "Capacity_9_Probes").implausible(&flat, true),
            None
        );
        // The lies of issue 38, item 3.
        for (lie, why) in [
            (
                evaluation(1e300, false, "Solve_Succeeded"),
                "outside the penalty's",
            ),
            (
                evaluation(1e3, false, "Elastic_Deficit"),
                "outside the penalty's",
            ),
            (
                evaluation(5.0, true, "Solved_By_Magic"),
                "which IPOPT does not return",
            ),
            (
                evaluation(5.0, true, "Invalid_Design"),
                "a feasible design with the status",
            ),
            (
                evaluation(f64::NAN, true, "Solve_Succeeded"),
                "which no design has",
            ),
            (
                evaluation(-1.0, true, "Solve_Succeeded"),
                "which no design has",
            ),
        ] {
            let found = lie.implausible(&flat, false).unwrap_or_default();
            assert!(found.contains(why), "{lie:?}: {found}");
        }
        let mut slow = evaluation(5.0, true, "Solve_Succeeded");
        slow.seconds = -1e308;
        assert!(slow
            .implausible(&flat, false)
            .unwrap()
            .contains("solve time"));
        let mut long = evaluation(1e6, false, "Elastic_Deficit");
        long.reason = Some("x".repeat(MAX_REASON_BYTES + 1));
        assert!(long
            .implausible(&flat, false)
            .unwrap()
            .contains("reason of 4097 bytes"));
        assert!(matches!(
            evaluation(1.0, true, "Solve_Succeeded").status,
            Status::Solved(SolveStatus::Ipopt(_))
        ));
    }
}
