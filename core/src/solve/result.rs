//! The result of a trajectory solve, as result files record it (their schema), and how it is
//! read from IPOPT's solution.

use super::dead_points::{dead_points, DeadPoint};
use super::execute::MotorsExecute;
use super::figures::PhysicalFigures;
use super::keyed::Violations;
use super::readback::read_trajectory;
use super::trajectory::Trajectory;
use super::SolveError;
use crate::ipopt::{LinearSolver, Nlp, Solution};
use crate::model::carried::CarriedMassAt;
use crate::problem::{
    cost_gradient, relaxation, CostTerms, Formulation, ProblemKind, StaticHold, TrajectoryProblem,
};
use serde::{Deserialize, Serialize};

/// Which program and solver produced a result file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToolInfo {
    /// Always `codesign`.
    pub name: String,
    /// The codesign version.
    pub version: String,
    /// The IPOPT version linked.
    pub ipopt_version: String,
    /// The linear solver IPOPT factorised with.
    pub linear_solver: LinearSolver,
}

impl ToolInfo {
    /// This binary, solving with `linear_solver`.
    pub fn current(linear_solver: LinearSolver) -> ToolInfo {
        ToolInfo {
            name: env!("CARGO_PKG_NAME").to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            ipopt_version: crate::ipopt::IPOPT_VERSION.to_owned(),
            linear_solver,
        }
    }
}

/// Which solve of the one rule of feasibility (docs/model.md, section 8) gave a result's
/// verdict. A feasible result is that solve's optimum; an infeasible one is the elastic solve,
/// which measures the shortfall, or the hard solve when the motors cannot hold the load at rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VerdictBy {
    /// The hard problem, from the standard initial guess or a warm start.
    Hard,
    /// The elastic problem, from the standard initial guess or a warm start.
    Elastic,
    /// The hard problem started from the elastic problem's trajectory.
    HardFromElastic,
    /// The hard problem carried up from the unloaded arm by payload continuation.
    PayloadContinuation,
}

impl VerdictBy {
    /// In plain words, for a reader without docs/model.md: how the verdict was reached, to
    /// follow `feasible` or `infeasible`.
    pub fn describe(self, feasible: bool) -> &'static str {
        match (self, feasible) {
            (VerdictBy::Hard, _) => "judged by solving the trajectory problem directly",
            (VerdictBy::Elastic, true) => {
                "judged by the relaxed problem, whose limits may give way: none had to, the \
                 motors need no extra torque or speed"
            }
            (VerdictBy::Elastic, false) => {
                "judged by the relaxed problem, whose limits may give way: the least extra \
                 torque and speed the motors would need is above zero"
            }
            (VerdictBy::HardFromElastic, _) => {
                "judged by solving the trajectory problem from the relaxed problem's trajectory"
            }
            (VerdictBy::PayloadContinuation, _) => {
                "judged by solving the trajectory problem step by step up from the unloaded arm"
            }
        }
    }

    /// The name result files give it.
    pub fn name(self) -> &'static str {
        match self {
            VerdictBy::Hard => "hard",
            VerdictBy::Elastic => "elastic",
            VerdictBy::HardFromElastic => "hard_from_elastic",
            VerdictBy::PayloadContinuation => "payload_continuation",
        }
    }
}

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

/// What an elastic solve's slacks relax (docs/model.md, section 14).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ElasticMeasures {
    /// The joint torque the motors lack, |RNEA - tau| summed over joints and integrated over
    /// the horizon (times the step h), N m s.
    pub torque_deficit: f64,
    /// The speed above the limit (motor speeds in mode `exact`, joint speeds else), summed over
    /// rows and integrated over the horizon, rad; where the motors have a torque-speed envelope,
    /// the speed its rows are relieved of as well (docs/model.md, section 14).
    pub speed_excess: f64,
    /// The largest single slack, N m or rad/s; the design is feasible when it is at most the
    /// solve settings' `tol`.
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
    /// Whether IPOPT reported an optimum (strict or acceptable), for an elastic solve every
    /// slack is at most the solve settings' `tol` (N m or rad/s), and, where the task's
    /// `motion.ends` judges it (`hold`, `rest`), the motors hold the load at rest at both ends
    /// (`static_hold`).
    pub feasible: bool,
    /// Why the result is infeasible, when it is: the end and the motors that cannot hold the
    /// load at rest first, then IPOPT's or the elastic solve's reason; null when feasible.
    pub reason: Option<String>,
    /// Which solve gave the verdict (docs/model.md, section 8): the hard problem, the elastic
    /// one, or the hard one started from the elastic trajectory. Absent in files written before
    /// the rule was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict_by: Option<VerdictBy>,
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
    /// Whether the motors can execute the trajectory: the motor torques and speeds recovered
    /// through G against each motor's own limits, with what each exceeds by. A joint-space
    /// problem under the limit modes `paper` and `interval` bounds the joints, not the motors
    /// (absent in files written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motors_execute: Option<MotorsExecute>,
    /// dJ*/dr, the exact sensitivity of the optimal cost to each ratio (envelope theorem; see
    /// `problem::cost_gradient`), wherever the result is feasible (of an elastic solve: its
    /// objective's, whose slacks are then within tol).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_gradient: Option<Vec<f64>>,
    /// The steps across which a linkage passes a dead point (G(q) singular between two nodes):
    /// a result with any is infeasible (docs/model.md, section 17); absent where there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dead_points: Vec<DeadPoint>,
    /// The static torques at the start and the goal against the problem's control limits
    /// (docs/model.md, section 6), computed without IPOPT (absent in files written before it
    /// was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_hold: Option<StaticHold>,
    /// The torque deficit and speed excess, for an elastic solve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elastic: Option<ElasticMeasures>,
    /// J by term (absent in files written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_terms: Option<CostTerms>,
    /// The duration T the solve chose, s, where the task's horizon is free (`{"free": [T_min,
    /// T_max]}`); absent for a fixed horizon, whose T is the task's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizon_s: Option<f64>,
    /// The time of each via point's node on the solved grid, s, in the order of `motion.via`
    /// (absent without via points): for a via point with a window, the time the solve chose.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub via_times_s: Vec<f64>,
    /// The last node's pose q_N the solve chose, rad, where the task's goal is a TCP position;
    /// absent for a joint goal, which fixes it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal_pose: Option<Vec<f64>>,
    /// The moving joints' names in the URDF, from the base outward (the order of every
    /// per-joint vector; empty in files written before it was recorded).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<String>,
    /// Per motor and in total: int tau_u^2 dt, RMS and peak torque, peak speed, peak power and
    /// work (`solve::PhysicalFigures`; absent in files of version 1 and before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub figures: Option<PhysicalFigures>,
    /// The parts the links carry (the task's `carried`) with their masses at the design, in
    /// the task's order; absent without.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub carried: Vec<CarriedMassAt>,
    /// The actuators' mass at the design, kg: the motors of `motors.parts` and the carried
    /// parts; absent where the task has neither or a motor part's mass is unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub actuator_mass_kg: Option<f64>,
    /// The trajectory.
    pub trajectory: Trajectory,
}

/// The result of `solution`, a solution of `problem`; an elastic solution is feasible when its
/// largest slack is at most `tol` (the settings' `tol`, N m or rad/s).
pub(super) fn read_result(
    problem: &mut TrajectoryProblem<'_>,
    solution: &Solution,
    tol: f64,
) -> Result<TrajectoryResult, SolveError> {
    let trajectory = read_trajectory(problem, &solution.x)
        .map_err(|(node, error)| SolveError::Pose { node, error })?;
    let violations = Violations::of(problem, &solution.x, &trajectory);
    let (cost, elastic) = cost_and_measures(problem, solution);
    let f = problem.formulation();
    let last = trajectory.q.last().map_or(&[][..], Vec::as_slice);
    let (static_hold, dead_points, reason) =
        judged(problem, solution, elastic.as_ref(), tol, &trajectory)?;
    let feasible = reason.is_none();
    let electrical =
        (f.task().motors).electrical(trajectory.motor_torque.first().map_or(0, Vec::len));
    Ok(TrajectoryResult {
        ratios: problem.ratios().to_vec(),
        status: solution.status.name(),
        feasible,
        reason,
        verdict_by: Some(match f.kind() {
            ProblemKind::Hard => VerdictBy::Hard,
            ProblemKind::Elastic => VerdictBy::Elastic,
        }),
        cost,
        iterations: solution.iterations,
        solve_seconds: SolveSeconds {
            total: solution.timing.total.as_secs_f64(),
            callbacks: solution.timing.callbacks.as_secs_f64(),
            ipopt: solution.timing.ipopt.as_secs_f64(),
        },
        max_motor_torque: trajectory
            .motor_torque_peaks()
            .into_iter()
            .fold(0.0, f64::max),
        max_motor_speed: trajectory
            .motor_speed_peaks()
            .into_iter()
            .fold(0.0, f64::max),
        violations,
        motors_execute: Some(MotorsExecute::of(
            (
                &trajectory.motor_torque_peaks(),
                &trajectory.motor_speed_peaks(),
            ),
            (f.motor_torque_limits(), f.motor_speed_limits()),
        )),
        // A feasible elastic solution has no slack beyond tol: the gradient of its objective
        // is dJ*/dr (section 9), and it is the one measured.
        cost_gradient: feasible
            .then(|| match &elastic {
                Some(measures) => measures.objective_gradient.clone(),
                None => cost_gradient(problem, solution).ok(),
            })
            .flatten(),
        dead_points,
        static_hold: Some(static_hold),
        elastic,
        cost_terms: Some(cost_terms(problem, &solution.x, &trajectory)),
        horizon_s: (f.layout().horizon()).map(|_| f.setting().horizon_at(&solution.x)),
        via_times_s: (f.setting().targets().nodes.iter())
            .map(|&k| trajectory.time[k])
            .collect(),
        goal_pose: (f.task().motion.goal.tcp()).map(|_| last.to_vec()),
        joints: f.dynamics().robot().joint_names().to_vec(),
        figures: PhysicalFigures::of(&trajectory, electrical.as_deref()),
        carried: (f.setting().carried()).masses_at(&f.task().carried, problem.ratios()),
        actuator_mass_kg: f.setting().actuator_mass_kg(problem.ratios()),
        trajectory,
    })
}

/// What judges `solution`'s design: the static hold at its last node, the linkages' dead points
/// crossed, and why the design is infeasible (None where it is feasible).
fn judged(
    problem: &mut TrajectoryProblem<'_>,
    solution: &Solution,
    elastic: Option<&ElasticMeasures>,
    tol: f64,
    trajectory: &Trajectory,
) -> Result<(StaticHold, Vec<DeadPoint>, Option<String>), SolveError> {
    let last = trajectory.q.last().map_or(&[][..], Vec::as_slice);
    let static_hold = (problem.static_hold_at(last)).map_err(|error| SolveError::Pose {
        node: trajectory.q.len() - 1,
        error,
    })?;
    let dead_points = dead_points(&trajectory.ratio);
    let crossings = dead_points
        .iter()
        .map(|crossing| crossing.text(&trajectory.q));
    let reasons: Vec<String> = [
        static_hold.failure(),
        infeasibility(problem.formulation(), solution, elastic, tol),
    ]
    .into_iter()
    .flatten()
    .chain(crossings)
    .collect();
    let reason = (!reasons.is_empty()).then(|| reasons.join("; "));
    Ok((static_hold, dead_points, reason))
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
    let Some(relaxed) = relaxation(f.setting(), &solution.x) else {
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
            .then(|| cost_gradient(problem, solution).ok())
            .flatten(),
    };
    (objective - relaxed.penalty, Some(measures))
}

/// Why `solution`, a solution of a problem of `formulation`, is infeasible, if it is: IPOPT
/// found no optimum, or (elastic) a slack exceeds `tol` (the solve settings' `tol`, N m or
/// rad/s). The speed excess relaxes the torque-speed envelope too, where the motors have one.
fn infeasibility(
    formulation: &Formulation,
    solution: &Solution,
    elastic: Option<&ElasticMeasures>,
    tol: f64,
) -> Option<String> {
    if !solution.status.is_success() {
        let status = solution.status.name();
        return Some(match &solution.outside_domain {
            None => format!("IPOPT returned {status}"),
            Some(why) => {
                format!("IPOPT returned {status} (the last point it could not evaluate: {why})")
            }
        });
    }
    let limits = match formulation.envelope() {
        Some(_) => "the speed limit or the torque-speed envelope",
        None => "the speed limit",
    };
    elastic.filter(|e| e.largest_slack > tol).map(|e| {
        format!(
            "the design lacks {:.3e} N m s of torque and exceeds {limits} by {:.3e} rad",
            e.torque_deficit, e.speed_excess
        )
    })
}

/// J at x by term; the TCP path is the trajectory's.
fn cost_terms(problem: &TrajectoryProblem<'_>, x: &[f64], trajectory: &Trajectory) -> CostTerms {
    let t = trajectory;
    let tcp = |k: usize| [t.tcp_x[k], t.tcp_y[k], t.tcp_z[k]];
    problem.cost_terms(x, tcp)
}
