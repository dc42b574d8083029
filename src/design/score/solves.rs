//! One design's solves judged: the verdict of a design whose motors cannot hold the load at rest
//! at an end, and the score of one solve with its result and raw solution.

use super::{judge, shortfall_of, solve, Score, SolveStatus, Verdict};
use codesign_core::ipopt::Solution;
use codesign_core::problem::Formulation;
use codesign_core::solve::{SolveSettings, TrajectoryResult};

/// The verdict of valid `ratios` when its motors cannot hold the load at rest at an end of some
/// problem of `formulations` (a payload or a motion, named by its label when there are
/// several): infeasible whatever IPOPT would say, so nothing is solved. Its shortfall is the
/// hold's deficit alone, summed over the problems (docs/model.md, section 10). None when every
/// one is held.
pub(super) fn unheld(formulations: &[(String, &Formulation)], ratios: &[f64]) -> Option<Verdict> {
    let (mut short, mut reasons) = (0.0, Vec::new());
    for (label, formulation) in formulations {
        // A design whose problem cannot be built is judged by its solve.
        let hold = formulation.static_hold(ratios).ok()?;
        let Some(reason) = hold.failure() else {
            continue;
        };
        short += shortfall_of(formulation, 0.0, hold.judged_deficit_nm(), 0.0);
        reasons.push(match formulations.len() {
            1 => reason,
            _ => format!("{label}: {reason}"),
        });
    }
    (!reasons.is_empty()).then(|| Verdict::Infeasible {
        shortfall: short,
        reason: reasons.join("; "),
        status: SolveStatus::StaticHoldFailed,
    })
}

/// The score of one solve of valid `ratios` (first from `warm`): its optimal cost J, or why it
/// is infeasible; with, when the solve ran, its result and raw solution (what a descent's merit
/// is made of).
pub(super) fn solved(
    formulation: &Formulation,
    settings: &SolveSettings,
    ratios: &[f64],
    warm: Option<&Solution>,
) -> (Score, Option<(TrajectoryResult, Solution)>) {
    match solve(formulation, settings, ratios, warm) {
        Ok((result, solution)) => {
            let score = Score {
                verdict: judge(formulation, &result),
                iterations: result.iterations,
                seconds: result.solve_seconds.total,
            };
            (score, Some((result, solution)))
        }
        Err(verdict) => (Score::unsolved(verdict), None),
    }
}
