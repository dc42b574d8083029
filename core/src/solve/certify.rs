//! The one rule that says whether a design is feasible (docs/model.md, section 8): a design is
//! feasible when some start finds a feasible trajectory, and infeasible only when none does.
//!
//! IPOPT's verdict of infeasibility is local (the problem is not convex), and the hard and the
//! elastic problem, started from the same guess, can end in different local optima. So every
//! command (`solve`, `capacity`, each co-design objective and penalty, the tables) solves a
//! design through [`solve_design_from`], which tries the same starts in an order set by the
//! formulation's kind:
//! - hard: the warm start if given (at most [`WARM_MAX_ITER`](super::WARM_MAX_ITER) iterations), the standard guess,
//!   then the elastic problem from the standard guess, then the hard problem from the elastic
//!   trajectory, then the payload continuation (`continuation`);
//! - elastic: the warm start (kept when it converges) or else the standard guess, then the hard
//!   problem from the elastic trajectory, from the standard guess, and by payload continuation.
//!
//! The verdict is whether any of these starts succeeds, so it does not depend on their order: a
//! capacity search, which keeps the continuation's steps between its probes, tries the
//! continuation first ([`solve_design_along`]).
//!
//! A free horizon's feasible trajectory is then shortened where the settings ask
//! (`FreeHorizonSearch::Descend`, `shorten`); the verdict stays the rule's.
//!
//! It stops at the first feasible trajectory, and skips the rest when the motors cannot hold the
//! load at rest at an end where the task's `motion.ends` judges the hold (no trajectory is then
//! feasible).

use super::continuation::PayloadChain;
use super::result::{TrajectoryResult, VerdictBy};
use super::run::{capped, Start, Tries};
use super::settings::{FreeHorizonSearch, SolveSettings};
use super::shorten::{shorten, Rule};
use super::SolveError;
use crate::ipopt::Solution;
use crate::problem::{Formulation, ProblemKind};

/// Solves the elastic trajectory problem (docs/model.md, section 14) of design `ratios` in
/// `formulation` (of either kind) under the one rule: the result reports the torque deficit and
/// the speed excess the design needs when no start finds a feasible trajectory.
pub fn solve_elastic(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
) -> Result<TrajectoryResult, SolveError> {
    solve_design(&formulation.elastic(), ratios, settings)
}

/// Solves the trajectory problem of design `ratios`, of the formulation's kind, under the one
/// rule from the standard initial guess.
///
/// ```
/// use codesign_core::model::{task::Task, Robot};
/// use codesign_core::problem::{Formulation, Space};
/// use codesign_core::solve::{solve_design, SolveSettings};
///
/// let mut task = Task::built_in()?;
/// task.motion.steps = 10; // a coarse grid, for speed
/// task.payload.mass_kg = 1.0;
/// let robot = Robot::load(&task)?;
/// let formulation = Formulation::new(&task, robot, Space::Actuation, task.limit_modes)?;
/// let result = solve_design(&formulation, &[6.0, 3.0, 1.0, 1.0], &SolveSettings::default())?;
/// assert!(result.feasible);
/// // J*, and the motors' largest torque against their 1.7 N m
/// assert!(result.cost > 0.0 && result.max_motor_torque <= 1.7 + 1e-6);
/// // dJ*/dr, one entry per ratio (envelope theorem)
/// assert_eq!(result.cost_gradient.as_ref().map(Vec::len), Some(4));
/// // the trajectory, node by node: 11 nodes of 4 joints
/// assert_eq!(result.trajectory.q.len(), 11);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn solve_design(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
) -> Result<TrajectoryResult, SolveError> {
    solve_design_from(formulation, ratios, settings, None).map(|(result, _)| result)
}

/// Solves the trajectory problem of design `ratios` under the one rule, first from `warm` (the
/// raw solution of a nearby design of the same formulation) when given: a warm start that finds
/// no feasible trajectory within [`WARM_MAX_ITER`](super::WARM_MAX_ITER) iterations is followed by the cold rule (an
/// elastic warm start that converges with a deficit stands in for the elastic cold start). Returns the result
/// that gives the verdict, its iterations and times summed over every solve tried, and the raw
/// solution of the formulation's kind nearest the verdict, to warm-start the next design from.
pub fn solve_design_from(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    warm: Option<&Solution>,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut tries = Tries::default();
    let (mut result, solution) = rule(formulation, ratios, settings, warm, None, &mut tries)?;
    tries.total_into(&mut result);
    Ok((result, solution))
}

/// Solves design `ratios` under the one rule with `chain`, the payload continuation of the same
/// design kept from solves at other payloads (a capacity search): the verdict is the one
/// [`solve_design`] reaches, and the continuation, which then costs one solve, is tried first.
pub fn solve_design_along(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    chain: &mut PayloadChain,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut tries = Tries::default();
    let (mut result, solution) =
        rule(formulation, ratios, settings, None, Some(chain), &mut tries)?;
    if formulation.kind() == ProblemKind::Hard && formulation.task().payload.mass_kg == 0.0 {
        chain.record(formulation, ratios, result.feasible.then_some(&solution));
    }
    tries.total_into(&mut result);
    Ok((result, solution))
}

/// The rule's starts for `formulation`'s kind, their work counted in `tries`; `chain` holds
/// the continuation's steps when they are kept between solves.
fn rule(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    warm: Option<&Solution>,
    chain: Option<&mut PayloadChain>,
    tries: &mut Tries,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut own = PayloadChain::new();
    let kept = chain.is_some();
    let mut continuation = Continuation {
        chain: chain.unwrap_or(&mut own),
        kept,
        tried: false,
    };
    let found = match formulation.kind() {
        ProblemKind::Hard => hard_first(
            formulation,
            ratios,
            settings,
            warm,
            &mut continuation,
            tries,
        ),
        ProblemKind::Elastic => elastic_first(
            formulation,
            ratios,
            settings,
            warm,
            &mut continuation,
            tries,
        ),
    }?;
    let shortens = settings.free_horizon == FreeHorizonSearch::Descend
        && formulation.kind() == ProblemKind::Hard
        && formulation.layout().horizon().is_some()
        && found.0.feasible;
    if !shortens {
        return Ok(found);
    }
    let fixed_rule: Rule<'_> =
        &|fixed, ratios, settings, tries| rule(fixed, ratios, settings, None, None, tries);
    shorten(formulation, ratios, settings, found, fixed_rule, tries)
}

/// Whether no start can help: the result is feasible, or its motors cannot hold the load at
/// rest at an end where the task's ends judge the hold (the start alone for a TCP goal, whose
/// last pose another start may change).
fn settled(result: &TrajectoryResult) -> bool {
    result.feasible
        || result.static_hold.as_ref().is_some_and(|hold| {
            match result.goal_pose {
                Some(_) => hold.start_failure(),
                None => hold.failure(),
            }
            .is_some()
        })
}

/// The payload continuation of one rule's solve: its chain, whether the chain is kept between
/// solves (the continuation is then tried early, else last), and whether it was tried.
struct Continuation<'a> {
    chain: &'a mut PayloadChain,
    kept: bool,
    tried: bool,
}

impl Continuation<'_> {
    /// Whether to try the continuation before the cold starts: its chain is kept and already
    /// reaches the payload, so it costs one warm-started solve.
    fn early(&self, hard: &Formulation, ratios: &[f64]) -> bool {
        self.kept && self.chain.ready_below(hard, ratios)
    }

    /// The hard problem at `hard`'s payload warm-started from the chain's last step below it
    /// (at most [`WARM_MAX_ITER`](super::WARM_MAX_ITER) iterations), once per rule: the result when feasible.
    fn try_once(
        &mut self,
        hard: &Formulation,
        ratios: &[f64],
        settings: &SolveSettings,
        tries: &mut Tries,
    ) -> Result<Option<(TrajectoryResult, Solution)>, SolveError> {
        if std::mem::replace(&mut self.tried, true) {
            return Ok(None);
        }
        let unloaded = |at: &Formulation, tries: &mut Tries| {
            let (result, solution) = rule(at, ratios, settings, None, None, tries)?;
            Ok(result.feasible.then_some(solution))
        };
        let Some(before) = self
            .chain
            .last_below(hard, ratios, settings, tries, unloaded)?
        else {
            return Ok(None);
        };
        let (mut result, solution) =
            tries.solve(hard, ratios, &capped(settings), Start::Warm(before))?;
        self.chain
            .record(hard, ratios, result.feasible.then_some(&solution));
        if !result.feasible {
            return Ok(None);
        }
        result.verdict_by = Some(VerdictBy::PayloadContinuation);
        Ok(Some((result, solution)))
    }
}

/// The rule for a hard formulation: warm start, standard guess, elastic problem, hard problem
/// from the elastic trajectory, payload continuation (first, after the warm start, when its
/// chain is kept and ready). An infeasible design's result is the elastic one (with its
/// shortfall), and its solution the last hard one.
fn hard_first(
    hard: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    warm: Option<&Solution>,
    continuation: &mut Continuation<'_>,
    tries: &mut Tries,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    if let Some(warm) = warm {
        let warmed = tries.solve(hard, ratios, &capped(settings), Start::Warm(warm))?;
        if warmed.0.feasible {
            return Ok(warmed);
        }
    }
    if continuation.early(hard, ratios) {
        if let Some(found) = continuation.try_once(hard, ratios, settings, tries)? {
            return Ok(found);
        }
    }
    let cold = tries.solve(hard, ratios, settings, Start::Guess)?;
    if settled(&cold.0) {
        return Ok(cold);
    }
    let elastic = hard.elastic();
    let (relaxed, relaxed_solution) = tries.solve(&elastic, ratios, settings, Start::Guess)?;
    let (mut again, solution) = tries.solve(
        hard,
        ratios,
        settings,
        Start::Trajectory(&relaxed_solution.x),
    )?;
    if again.feasible {
        again.verdict_by = Some(VerdictBy::HardFromElastic);
        return Ok((again, solution));
    }
    if let Some(found) = continuation.try_once(hard, ratios, settings, tries)? {
        return Ok(found);
    }
    Ok((relaxed, solution))
}

/// The rule for an elastic formulation (the graded penalty): warm start or standard guess, then,
/// when a deficit is left, the hard problem from the elastic trajectory, from the standard
/// guess and by payload continuation. The solution is always the elastic one; an infeasible
/// design's result is too, so that a warm-started descent on the elastic objective (the
/// gradient method) sees it continue.
fn elastic_first(
    elastic: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    warm: Option<&Solution>,
    continuation: &mut Continuation<'_>,
    tries: &mut Tries,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut first = None;
    if let Some(warm) = warm {
        let warmed = tries.solve(elastic, ratios, &capped(settings), Start::Warm(warm))?;
        // An elastic optimum with a deficit is kept; one not reached within the cap is not.
        if settled(&warmed.0) || warmed.1.status.is_success() {
            first = Some(warmed);
        }
    }
    let (relaxed, solution) = match first {
        Some(warmed) => warmed,
        None => tries.solve(elastic, ratios, settings, Start::Guess)?,
    };
    if settled(&relaxed) {
        return Ok((relaxed, solution));
    }
    let hard = elastic.hard();
    let (mut again, _) = tries.solve(&hard, ratios, settings, Start::Trajectory(&solution.x))?;
    if again.feasible {
        again.verdict_by = Some(VerdictBy::HardFromElastic);
        return Ok((again, solution));
    }
    let (cold, _) = tries.solve(&hard, ratios, settings, Start::Guess)?;
    if cold.feasible {
        return Ok((cold, solution));
    }
    if let Some((found, _)) = continuation.try_once(&hard, ratios, settings, tries)? {
        return Ok((found, solution));
    }
    Ok((relaxed, solution))
}
