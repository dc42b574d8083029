//! The shortening of a free horizon (docs/model.md, section 6, "Shortening a free horizon";
//! `SolveSettings::free_horizon` = `descend`): from the free problem's feasible local optimum
//! at duration T, the fixed-horizon rule at T (the task's weights and box shaping its
//! trajectory) starts the free problem bounded to [T_min, T], which ends at T' <= T; the rounds
//! go on while J falls.
//!
//! A minimum-time problem is sharper than the fixed-horizon one: its optima ride the limits,
//! and the standard guess reaches a local optimum whose T the fixed-horizon rule beats (on the
//! built-in arm at 1 kg, 0.7381 s against 0.7131 s). The fixed-horizon problem's weights and box
//! shape trajectories that its starts (the payload continuation among them) reach where the free
//! problem's guess does not, and a bounded free solve from such a trajectory cannot end above it.

use super::result::TrajectoryResult;
use super::run::{Start, Tries};
use super::settings::SolveSettings;
use super::SolveError;
use crate::ipopt::Solution;
use crate::problem::Formulation;

/// The rule from the standard guess, its work counted in the last argument: what shortening a
/// free horizon solves at each fixed duration.
pub(super) type Rule<'a> = &'a dyn Fn(
    &Formulation,
    &[f64],
    &SolveSettings,
    &mut Tries,
) -> Result<(TrajectoryResult, Solution), SolveError>;

/// The most rounds of shortening: each costs a fixed-horizon rule and a bounded free solve; the
/// built-in arm's rounds end by a verdict of infeasibility after 2 to 3 (0, 1 and 3 kg).
pub const MAX_SHORTENING_ROUNDS: usize = 6;

/// The least fall of J, relative, that keeps the rounds going.
const LEAST_FALL: f64 = 1e-6;

/// Shortens `found`, a feasible solve of the free-horizon formulation `free` at design `ratios`,
/// in rounds: each solves the fixed-horizon rule at the current T (`fixed_rule`, its work counted in
/// `tries`) and, where it finds a feasible trajectory, the free problem bounded to [T_min, T]
/// from it. Returns the result and solution of least J; a round whose rule finds nothing, or
/// whose bounded solve fails or does not lower J, ends the rounds.
pub(super) fn shorten(
    free: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    found: (TrajectoryResult, Solution),
    fixed_rule: Rule<'_>,
    tries: &mut Tries,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut best = found;
    for _ in 0..MAX_SHORTENING_ROUNDS {
        let Some(horizon_s) = best.0.horizon_s else {
            break;
        };
        let Some(bounded) = free.free_up_to(horizon_s)? else {
            break;
        };
        let fixed = free.fixed_at(horizon_s)?;
        let (shaped, trajectory) = fixed_rule(&fixed, ratios, settings, tries)?;
        if !shaped.feasible {
            break;
        }
        // The fixed problem's point lacks T alone: its problem-wide variables (via times) follow
        // the trajectory in the free problem's order, after T's column.
        let Some(column) = bounded.layout().horizon() else {
            break;
        };
        let mut start = trajectory.x;
        start.insert(column, horizon_s);
        let shorter = tries.solve(&bounded, ratios, settings, Start::Trajectory(&start))?;
        let falls = shorter.0.cost < best.0.cost - LEAST_FALL * best.0.cost.abs();
        if !(shorter.0.feasible && falls) {
            break;
        }
        best = shorter;
    }
    Ok(best)
}
