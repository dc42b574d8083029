//! Solving the trajectory problem of one design and reading the result.
//!
//! [`solve_design`] runs IPOPT on a [`TrajectoryProblem`] with the task's solver settings and
//! returns a [`TrajectoryResult`]: status, feasibility, cost, timing, the trajectory with joint and
//! motor torques and the TCP path, and the largest violation of each constraint family.
//! [`solve_elastic`] solves the elastic kind of the same problem (docs/model.md, section 14),
//! which always has a solution, and reports how much torque and speed the design lacks.

use crate::ipopt::{self, Nlp, Options, Solution};
use crate::model::task::Motion;
use crate::problem::{cost_gradient, relaxation, Formulation, ProblemKind, TrajectoryProblem};
use crate::transmission::{DesignError, JointLimits};
use serde::{Deserialize, Serialize};
use std::fmt;

/// How to run IPOPT on a trajectory problem beyond the task's `solver` settings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SolveSettings {
    /// Show IPOPT's iteration log.
    pub verbose: bool,
}

/// Why a design could not be solved at all. (A design that is valid but infeasible is not an
/// error: it is a [`TrajectoryResult`] with `feasible: false`.)
#[derive(Clone, Debug, PartialEq)]
pub enum SolveError {
    /// The design is outside its space (bounds, order constraints, not finite, singular G).
    Design(DesignError),
    /// IPOPT could not run (a callback failed, an option was rejected).
    Ipopt(ipopt::Error),
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveError::Design(error) => write!(f, "invalid design: {error}"),
            SolveError::Ipopt(error) => write!(f, "{error}"),
        }
    }
}

impl std::error::Error for SolveError {}

/// Wall time of a solve, s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolveSeconds {
    /// The whole IPOPT call.
    pub total: f64,
    /// Inside the problem's callbacks (dynamics and derivatives).
    pub callbacks: f64,
    /// In IPOPT itself (`total - callbacks`).
    pub ipopt: f64,
}

/// The trajectory at the nodes k = 0..=N (controls at k = 0..N-1).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// Node times, s.
    pub time: Vec<f64>,
    /// Joint positions per node, rad.
    pub q: Vec<Vec<f64>>,
    /// Joint speeds per node, rad/s.
    pub v: Vec<Vec<f64>>,
    /// Joint accelerations per interval, rad/s^2.
    pub a: Vec<Vec<f64>>,
    /// Joint torques per interval, N m.
    pub joint_torque: Vec<Vec<f64>>,
    /// Motor torques per interval, N m (G^-T tau for a joint-space solution).
    pub motor_torque: Vec<Vec<f64>>,
    /// Motor speeds per node, rad/s (G v).
    pub motor_speed: Vec<Vec<f64>>,
    /// TCP world y per node, m.
    pub tcp_y: Vec<f64>,
    /// TCP world z per node, m.
    pub tcp_z: Vec<f64>,
}

/// The largest violation of each constraint family at the returned point (0 when satisfied).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Violations {
    /// |RNEA(q, v, a) - tau|, N m.
    pub dynamics: f64,
    /// Semi-implicit Euler residuals, rad/s or rad.
    pub integration: f64,
    /// Start and goal states, rad or rad/s.
    pub boundary: f64,
    /// Joint position limits, rad.
    pub joint_position: f64,
    /// The problem's speed limits in its speed mode, rad/s.
    pub speed_limits: f64,
    /// The problem's control bounds in its torque mode, N m.
    pub control_limits: f64,
    /// The soft Cartesian box (penalised, not enforced), m.
    pub cartesian_box: f64,
}

/// What an elastic solve's slacks relax (docs/model.md, section 14).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ElasticMeasures {
    /// The joint torque the motors lack, |RNEA - tau| summed over joints and integrated over
    /// the horizon (times the step h), N m s.
    pub torque_deficit: f64,
    /// The speed above the limit (motor speeds in mode `exact`, joint speeds else), summed over
    /// rows and integrated over the horizon, rad.
    pub speed_excess: f64,
    /// The largest single slack, N m or rad/s; the design is feasible when it is at most the
    /// task's `solver.tol`.
    pub largest_slack: f64,
    /// The penalised objective IPOPT minimised: the cost J plus the slacks' penalty.
    pub objective: f64,
    /// Its exact sensitivity to each ratio (envelope theorem, `problem::cost_gradient`), when
    /// IPOPT found an optimum; dJ*/dr where the design is feasible.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objective_gradient: Option<Vec<f64>>,
}

/// The result of one trajectory solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryResult {
    /// The design r.
    pub ratios: Vec<f64>,
    /// IPOPT's name for its return status.
    pub status: String,
    /// Whether IPOPT reported an optimum (strict or acceptable) and, for an elastic solve, every
    /// slack is at most the task's `solver.tol` (N m or rad/s).
    pub feasible: bool,
    /// Why the result is infeasible, when it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The optimal cost J (of an elastic solve: without the slacks' penalty).
    pub cost: f64,
    /// IPOPT iterations.
    pub iterations: usize,
    /// Wall time.
    pub solve_seconds: SolveSeconds,
    /// Largest |motor torque| the trajectory needs, N m.
    pub max_motor_torque: f64,
    /// Largest |motor speed|, rad/s.
    pub max_motor_speed: f64,
    /// Largest violation per constraint family.
    pub violations: Violations,
    /// dJ*/dr, the exact sensitivity of the optimal cost to each ratio (envelope theorem; see
    /// `problem::cost_gradient`), when a hard solve succeeded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_gradient: Option<Vec<f64>>,
    /// The torque deficit and speed excess, for an elastic solve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elastic: Option<ElasticMeasures>,
    /// The trajectory.
    pub trajectory: Trajectory,
}

/// IPOPT options of a trajectory solve: exact Hessian, the task's linear solver, `tol`,
/// `max_iter` and further `options` (validated when the task was loaded).
pub fn ipopt_options(formulation: &Formulation, settings: &SolveSettings) -> Options {
    let solver = &formulation.task().solver;
    let mut options = Options::new()
        .linear_solver(solver.linear_solver())
        .str("hessian_approximation", "exact")
        .num("tol", solver.tol)
        .int(
            "max_iter",
            i32::try_from(solver.max_iter).unwrap_or(i32::MAX),
        )
        .verbose(settings.verbose);
    for (name, value) in &solver.options {
        options = match (
            value.as_i64().and_then(|v| i32::try_from(v).ok()),
            value.as_f64(),
            value.as_str(),
        ) {
            (Some(integer), _, _) => options.int(name, integer),
            (None, Some(number), _) => options.num(name, number),
            (None, None, Some(text)) => options.str(name, text),
            _ => options,
        };
    }
    options
}

/// Solves the elastic trajectory problem (docs/model.md, section 14) of design `ratios` in
/// `formulation` (of either kind) from the standard initial guess: always feasible as a problem,
/// the result reports the torque deficit and the speed excess the design needs.
pub fn solve_elastic(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
) -> Result<TrajectoryResult, SolveError> {
    solve_design(&formulation.elastic(), ratios, settings)
}

/// Solves the trajectory problem of design `ratios`, of the formulation's kind, from the standard
/// initial guess.
pub fn solve_design(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
) -> Result<TrajectoryResult, SolveError> {
    solve_design_from(formulation, ratios, settings, None).map(|(result, _)| result)
}

/// Solves the trajectory problem of design `ratios`, warm-started from `warm` (the raw solution
/// of a nearby design of the same formulation) when given, else from the standard initial guess.
/// Returns the result and the raw solution, to warm-start the next design from.
pub fn solve_design_from(
    formulation: &Formulation,
    ratios: &[f64],
    settings: &SolveSettings,
    warm: Option<&Solution>,
) -> Result<(TrajectoryResult, Solution), SolveError> {
    let mut problem = formulation.problem(ratios).map_err(SolveError::Design)?;
    let mut options = ipopt_options(formulation, settings);
    if warm.is_some() {
        // Keep the warm point and multipliers close to where they were; the barrier parameter
        // starts at IPOPT's default, which measured best for steps of any size (a smaller
        // mu_init halves the iterations after a tiny step but doubles them after a large one).
        options = options
            .num("warm_start_bound_push", 1e-6)
            .num("warm_start_mult_bound_push", 1e-6);
    }
    if formulation.kind() == ProblemKind::Elastic {
        options = options.num(
            "obj_scaling_factor",
            elastic_objective_scaling(&mut problem),
        );
    }
    let solution = ipopt::solve_from(&mut problem, &options, warm).map_err(SolveError::Ipopt)?;
    Ok((read_result(&mut problem, &solution), solution))
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
    let hard = max_abs(gradient[..slacks.start].iter().copied());
    let elastic = max_abs(gradient[slacks].iter().copied()).max(hard);
    let scale = |largest: f64| (SCALING_MAX_GRADIENT / largest).min(1.0);
    scale(hard) / scale(elastic)
}

fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m: f64, v| m.max(v.abs()))
}

/// How far `value` lies outside [lower, upper].
fn outside(value: f64, lower: f64, upper: f64) -> f64 {
    (lower - value).max(value - upper).max(0.0)
}

/// The result of `solution`, a solution of `problem`.
fn read_result(problem: &mut TrajectoryProblem<'_>, solution: &Solution) -> TrajectoryResult {
    let trajectory = read_trajectory(problem, &solution.x);
    let violations = Violations::of(problem, &solution.x, &trajectory);
    let (cost, elastic) = cost_and_measures(problem, solution);
    let f = problem.formulation();
    let reason = infeasibility(solution, elastic.as_ref(), f.task().solver.tol);
    let feasible = reason.is_none();
    TrajectoryResult {
        ratios: problem.ratios().to_vec(),
        status: solution.status.name(),
        feasible,
        reason,
        cost,
        iterations: solution.iterations,
        solve_seconds: SolveSeconds {
            total: solution.timing.total.as_secs_f64(),
            callbacks: solution.timing.callbacks.as_secs_f64(),
            ipopt: solution.timing.ipopt.as_secs_f64(),
        },
        max_motor_torque: trajectory
            .motor_torque
            .iter()
            .flatten()
            .fold(0.0, |m, t| m.max(t.abs())),
        max_motor_speed: trajectory
            .motor_speed
            .iter()
            .flatten()
            .fold(0.0, |m, w| m.max(w.abs())),
        violations,
        cost_gradient: (feasible && f.kind() == ProblemKind::Hard)
            .then(|| cost_gradient(problem, solution)),
        elastic,
        trajectory,
    }
}

/// The cost J at `solution` and, for an elastic problem, what its slacks relax. IPOPT's objective
/// of an elastic problem comes from its own iterate, whose slacks its bound relaxation lets go to
/// about -tol each (worth a penalty of -tol times the weight per slack, far above tol), so the
/// elastic J and objective are evaluated again at the returned point, whose slacks are >= 0.
fn cost_and_measures(
    problem: &mut TrajectoryProblem<'_>,
    solution: &Solution,
) -> (f64, Option<ElasticMeasures>) {
    let f = problem.formulation();
    let Some(relaxed) = relaxation(f, &solution.x) else {
        return (solution.objective, None);
    };
    let objective = problem.objective(&solution.x, true).unwrap_or(f64::NAN);
    let measures = ElasticMeasures {
        torque_deficit: relaxed.torque_deficit,
        speed_excess: relaxed.speed_excess,
        largest_slack: relaxed.largest,
        objective,
        objective_gradient: solution
            .status
            .is_success()
            .then(|| cost_gradient(problem, solution)),
    };
    (objective - relaxed.penalty, Some(measures))
}

/// Why `solution` is infeasible, if it is: IPOPT found no optimum, or (elastic) a slack exceeds
/// `tol` (the task's `solver.tol`, N m or rad/s).
fn infeasibility(
    solution: &Solution,
    elastic: Option<&ElasticMeasures>,
    tol: f64,
) -> Option<String> {
    if !solution.status.is_success() {
        return Some(format!("IPOPT returned {}", solution.status.name()));
    }
    elastic.filter(|e| e.largest_slack > tol).map(|e| {
        format!(
            "the design lacks {:.3e} N m s of torque and exceeds the speed limit by {:.3e} rad",
            e.torque_deficit, e.speed_excess
        )
    })
}

/// The trajectory of `problem`'s primal point x: states, torques, motor speeds, the TCP's path.
fn read_trajectory(problem: &TrajectoryProblem<'_>, x: &[f64]) -> Trajectory {
    let f = problem.formulation();
    let layout = f.layout();
    let (n, steps, h) = (layout.dof, layout.steps, f.step_s());
    let slice = |start: usize| x[start..start + n].to_vec();
    let dynamics = f.dynamics();
    let mut data = dynamics.workspace();
    let mut trajectory = Trajectory::default();
    for k in 0..=steps {
        let (q, v) = (slice(layout.q(k, 0)), slice(layout.v(k, 0)));
        let tcp = dynamics.tcp_position(&mut data, &q);
        trajectory.time.push(k as f64 * h);
        trajectory.tcp_y.push(tcp[1]);
        trajectory.tcp_z.push(tcp[2]);
        trajectory
            .motor_speed
            .push(problem.coupling().motor_speeds(&v));
        if k < steps {
            let u = slice(layout.u(k, 0));
            trajectory.a.push(slice(layout.a(k, 0)));
            trajectory.joint_torque.push(problem.joint_torques(&u));
            trajectory.motor_torque.push(problem.motor_torques(&u));
        }
        trajectory.q.push(q);
        trajectory.v.push(v);
    }
    trajectory
}

impl Violations {
    /// The violations of `problem`'s constraint families at x, whose trajectory is `trajectory`.
    fn of(problem: &TrajectoryProblem<'_>, x: &[f64], trajectory: &Trajectory) -> Violations {
        let f = problem.formulation();
        let layout = f.layout();
        let (n, h) = (layout.dof, f.step_s());
        let limits = f.dynamics().robot().position_limits();
        let speed = problem.speed_limits();
        let control = problem.control_limits();
        Violations {
            dynamics: dynamics_residual(problem, trajectory),
            integration: integration_residual(h, trajectory),
            boundary: boundary_residual(&f.task().motion, trajectory),
            joint_position: trajectory
                .q
                .iter()
                .flat_map(|q| {
                    q.iter()
                        .zip(limits)
                        .map(|(&q, &(lo, hi))| outside(q, lo, hi))
                })
                .fold(0.0, f64::max),
            speed_limits: trajectory
                .v
                .iter()
                .map(|v| limit_violation(&speed, v))
                .fold(0.0, f64::max),
            control_limits: (0..layout.steps)
                .map(|k| limit_violation(&control, &x[layout.u(k, 0)..layout.u(k, 0) + n]))
                .fold(0.0, f64::max),
            cartesian_box: box_violation(problem, trajectory),
        }
    }
}

/// The largest |RNEA(q, v, a) - tau| over the intervals, N m.
fn dynamics_residual(problem: &TrajectoryProblem<'_>, trajectory: &Trajectory) -> f64 {
    let dynamics = problem.formulation().dynamics();
    let mut data = dynamics.workspace();
    let mut rnea = vec![0.0; dynamics.dof()];
    let mut largest = 0.0;
    for (k, (a, tau)) in trajectory
        .a
        .iter()
        .zip(&trajectory.joint_torque)
        .enumerate()
    {
        dynamics.rnea(&mut data, &trajectory.q[k], &trajectory.v[k], a, &mut rnea);
        largest = f64::max(largest, max_abs(rnea.iter().zip(tau).map(|(r, t)| r - t)));
    }
    largest
}

/// The largest semi-implicit Euler residual over the intervals (time step h, s), rad/s or rad.
fn integration_residual(h: f64, trajectory: &Trajectory) -> f64 {
    let (q, v) = (&trajectory.q, &trajectory.v);
    let mut largest: f64 = 0.0;
    for (k, a) in trajectory.a.iter().enumerate() {
        for i in 0..a.len() {
            largest = largest
                .max((v[k + 1][i] - v[k][i] - h * a[i]).abs())
                .max((q[k + 1][i] - q[k][i] - h * v[k + 1][i]).abs());
        }
    }
    largest
}

/// The largest distance of the first and last states from the task's start and goal at rest.
fn boundary_residual(motion: &Motion, trajectory: &Trajectory) -> f64 {
    let last = trajectory.q.len() - 1;
    let mut largest: f64 = 0.0;
    for (k, pose) in [(0, &motion.start), (last, &motion.goal)] {
        largest = largest
            .max(max_abs(
                trajectory.q[k].iter().zip(pose.iter()).map(|(q, p)| q - p),
            ))
            .max(max_abs(trajectory.v[k].iter().copied()));
    }
    largest
}

/// The TCP's largest distance outside the soft Cartesian box over the nodes, m.
fn box_violation(problem: &TrajectoryProblem<'_>, trajectory: &Trajectory) -> f64 {
    let f = problem.formulation();
    let dynamics = f.dynamics();
    let mut data = dynamics.workspace();
    let b = &f.task().cartesian_box;
    let mut largest: f64 = 0.0;
    for q in &trajectory.q {
        let tcp = dynamics.tcp_position(&mut data, q);
        for (axis, interval) in [&b.x, &b.y, &b.z].into_iter().enumerate() {
            if let Some(interval) = interval {
                largest = largest.max(outside(tcp[axis], interval.range[0], interval.range[1]));
            }
        }
    }
    largest
}

/// How far a joint-space vector lies outside `limits`.
fn limit_violation(limits: &JointLimits, values: &[f64]) -> f64 {
    match limits {
        JointLimits::Box { lower, upper } => values
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(&v, (&lo, &hi))| outside(v, lo, hi))
            .fold(0.0, f64::max),
        JointLimits::Linear { matrix, limit } => {
            let mapped = matrix * nalgebra::DVector::from_column_slice(values);
            mapped
                .iter()
                .map(|m| outside(*m, -limit, *limit))
                .fold(0.0, f64::max)
        }
    }
}
