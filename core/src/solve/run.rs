//! Running IPOPT once on the trajectory problem of one design.

use super::result::{read_result, SolveSeconds, TrajectoryResult};
use super::settings::SolveSettings;
use super::SolveError;
use crate::ipopt::{self, Nlp, Solution};
use crate::problem::{Formulation, ProblemKind, TrajectoryProblem};

/// Where one IPOPT solve starts.
#[derive(Clone, Copy, Debug)]
pub(super) enum Start<'a> {
    /// The standard initial guess.
    Guess,
    /// The raw solution (point and multipliers) of a nearby design of the same formulation.
    Warm(&'a Solution),
    /// The primal point of the same design in the other kind (its trajectory only).
    Trajectory(&'a [f64]),
}

/// Solves the trajectory problem of design `ratios`, of the formulation's kind, once from
/// `start`: the result and the raw solution, to warm-start another design from.
pub(super) fn solve_once(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    start: Start<'_>,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut problem = formulation.problem(ratios)?;
    let mut options = settings.ipopt_options();
    let warm = match start {
        Start::Guess => None,
        Start::Trajectory(x) => {
            problem.start_at(x)?;
            None
        }
        Start::Warm(solution) => {
            // Keep the warm point and multipliers close to where they were; the barrier
            // parameter starts at IPOPT's default, which measured best for steps of any size (a
            // smaller mu_init halves the iterations after a tiny step but doubles them after a
            // large one).
            options = options
                .num("warm_start_bound_push", 1e-6)
                .num("warm_start_mult_bound_push", 1e-6);
            Some(solution)
        }
    };
    if formulation.kind() == ProblemKind::Elastic {
        options = options.num(
            "obj_scaling_factor",
            elastic_objective_scaling(&mut problem),
        );
    }
    let solution = ipopt::solve_from(&mut problem, &options, warm)?;
    Ok((
        read_result(&mut problem, &solution, settings.tol)?,
        solution,
    ))
}

/// IPOPT's default `nlp_scaling_max_gradient`: its gradient-based scaling scales the objective
/// down when its largest gradient entry at the starting point exceeds this.
const SCALING_MAX_GRADIENT: f64 = 100.0;

/// The objective scaling that undoes, for an elastic problem, the extra scaling its penalty
/// weights cause: IPOPT scales the objective by min(1, 100 / max |grad f(x0)|), in which the
/// weights (up to 3e4 in joint space) would dominate the hard problem's gradient g. This
/// factor restores the hard problem's scale min(1, 100 / g), so that the elastic solve follows
/// the hard solve's path towards the same local optimum where that one is feasible.
fn elastic_objective_scaling(problem: &mut TrajectoryProblem<'_>) -> f64 {
    let n = problem.num_variables();
    let (mut x, mut gradient) = (vec![0.0; n], vec![0.0; n]);
    problem.initial_point(&mut x);
    if problem.gradient(&x, true, &mut gradient).is_err() {
        return 1.0;
    }
    let slacks = problem.formulation().layout().slacks();
    let hard = super::verify::max_abs(gradient[..slacks.start].iter().copied());
    let elastic = super::verify::max_abs(gradient[slacks].iter().copied()).max(hard);
    let scale = |largest: f64| (SCALING_MAX_GRADIENT / largest).min(1.0);
    scale(hard) / scale(elastic)
}

/// The work of the solves tried for one design.
#[derive(Default)]
pub(super) struct Tries {
    /// IPOPT iterations over the solves.
    pub(super) iterations: usize,
    /// Their times.
    pub(super) seconds: SolveSeconds,
}

impl Tries {
    /// Gives `result` the iterations and times of every solve tried.
    pub(super) fn total_into(&self, result: &mut TrajectoryResult) {
        result.iterations = self.iterations;
        result.solve_seconds = self.seconds;
    }

    /// Solves once and counts the work.
    pub(super) fn solve(
        &mut self,
        formulation: &Formulation,
        ratios: &[f64],
        settings: &SolveSettings,
        start: Start<'_>,
    ) -> Result<(TrajectoryResult, Solution), SolveError> {
        let (result, solution) = solve_once(formulation, ratios, settings, start)?;
        self.iterations += result.iterations;
        let (sum, one) = (&mut self.seconds, &result.solve_seconds);
        sum.total += one.total;
        sum.callbacks += one.callbacks;
        sum.ipopt += one.ipopt;
        Ok((result, solution))
    }
}

/// The most IPOPT iterations a warm start may take, the cold limit of the one rule
/// ([`super::solve_design_from`]):
/// a warm start that needs more has started in the wrong place, and the cold rule takes over
/// (measured in CMA-ES at 1 kg: a median of 25 iterations from the generation's mean, 57 cold).
pub const WARM_MAX_ITER: u32 = 150;

/// `settings` with `max_iter` at most [`WARM_MAX_ITER`].
pub(super) fn capped(settings: &SolveSettings) -> SolveSettings {
    SolveSettings {
        max_iter: settings.max_iter.min(WARM_MAX_ITER),
        ..settings.clone()
    }
}
