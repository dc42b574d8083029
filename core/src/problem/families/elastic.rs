//! The elastic trajectory problem (docs/model.md, section 14): the hard problem with every way
//! to be infeasible relaxed by non-negative slacks under an exact l1 penalty, so that it always
//! has a solution, and one that is the hard problem's wherever the hard problem is feasible.
//!
//! Relaxed are the dynamics rows, RNEA(q_k, v_k, a_k) - tau_k - s+_k + s-_k = 0 (the torque the
//! motors lack), and the speed limits, as rows A v_k - e+_k + e-_k in [lower, upper] at the nodes
//! 0 < k < N (A = G and |.| <= w in mode `exact`, A = I and the mode's box in `paper` and
//! `interval`, whose variable bounds on v become these rows). Nothing else can be infeasible: with
//! the dynamics relaxed the controls may stay at 0 (inside every torque limit), the accelerations
//! are free, and the straight path from start to goal (both inside the joint limits, checked by
//! `Formulation::new`) held at the goal for the last interval meets the integration rows, the
//! boundary values and the position bounds.

use super::family::{Family, FamilyId, Shape};
use crate::problem::design_data::DesignData;
use crate::problem::kind::ProblemKind;
use crate::problem::layout::Layout;
use crate::problem::setting::Setting;
use crate::transmission::Space;
use std::sync::Arc;

/// Weights of the l1 penalty on the elastic problem's slacks, in units of the cost J per unit
/// of slack at one node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenaltyWeights {
    /// Per N m of joint torque deficit at one node.
    pub torque: f64,
    /// Per rad/s of speed excess at one node (motor speed in mode `exact`, joint speed else).
    pub speed: f64,
}

/// The penalty weights of the elastic problem in `space`: [`multiplier_bounds`] times its
/// safety factor.
pub fn penalty_weights(space: Space) -> PenaltyWeights {
    let (bounds, safety) = multiplier_bounds(space);
    PenaltyWeights {
        torque: safety * bounds.torque,
        speed: safety * bounds.speed,
    }
}

/// Bounds on the hard problem's multipliers of the rows the elastic problem relaxes in `space`,
/// and the safety factor of its penalty weights over them: the one place of the weight rule.
///
/// The rule: an l1 penalty rho |s| on the slack s of a constraint is exact (a local solution of
/// the hard problem with multiplier lambda is a local solution of the elastic one with s = 0,
/// and where the hard problem is feasible nearby the elastic one has no other) as soon as
/// rho > |lambda| (Fletcher, Practical Methods of Optimization, theorem 14.3.1: the slack's
/// reduced cost at s = 0 is rho - |lambda| > 0). The bounds are the rounded-up maxima of |lambda|
/// on every feasible case of `tests/data/ocp_reference.json` and of the committed original
/// designs, speed modes `exact` and `interval`, measured by `weights_exceed_the_hard_multipliers`
/// (which fails if they stop holding): dynamics rows (cost per N m at one node) 4.1 in
/// actuation space and 2850 in joint space (its rows' multipliers are those of the joint torque
/// bounds, and the `paper` bound of joint 4 is 0); speed limits (cost per rad/s) 0.76 and 3.5.
/// The safety factor is 10 in actuation space; in joint space, whose multipliers at 3 kg are
/// those of a design at the edge of feasibility (two hard solves, MUMPS and LDL^T, end in
/// different optima), a factor 10 lets the elastic solve stop at a spurious point with 0.02 N m
/// of slack at one node, and 100 is used. A larger weight makes the problem stiffer: the
/// infeasible design of the benchmark takes twice the iterations at factor 100.
fn multiplier_bounds(space: Space) -> (PenaltyWeights, f64) {
    match space {
        Space::Actuation => (
            PenaltyWeights {
                torque: 5.0,
                speed: 1.0,
            },
            10.0,
        ),
        Space::Joint => (
            PenaltyWeights {
                torque: 3000.0,
                speed: 5.0,
            },
            100.0,
        ),
    }
}

/// What the slacks of an elastic primal point relax.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Relaxation {
    /// Sum over nodes and joints of |s+ - s-| times the step h: the torque the motors lack,
    /// integrated over the horizon, N m s.
    pub torque_deficit: f64,
    /// Sum over nodes and rows of |e+ - e-| times h: the speed above the limit, integrated, rad.
    pub speed_excess: f64,
    /// The largest slack (s+, s-, e+ or e-), N m or rad/s.
    pub largest: f64,
    /// The penalty term of the objective.
    pub penalty: f64,
}

/// The penalty weight of each slack column, in the order of `layout.slacks()`.
fn slack_weights(
    layout: &Layout,
    weights: PenaltyWeights,
) -> impl Iterator<Item = (usize, f64)> + '_ {
    let n = layout.dof;
    let columns = move |family: FamilyId, weight: f64| {
        (0..layout.steps)
            .flat_map(move |k| (0..n).filter_map(move |i| layout.slack(family, k, i)))
            .flat_map(move |columns| columns.map(|c| (c, weight)))
    };
    columns(FamilyId::Dynamics, weights.torque).chain(columns(FamilyId::MotorSpeed, weights.speed))
}

/// The penalty at x: the weighted sum of the slacks (0 in the hard kind).
pub(in crate::problem) fn penalty(setting: &Setting, x: &[f64]) -> f64 {
    let weights = penalty_weights(setting.space());
    slack_weights(setting.layout(), weights)
        .map(|(c, weight)| weight * x[c])
        .sum()
}

/// Writes the penalty's gradient, the weights, into the slack entries of `gradient`.
pub(in crate::problem) fn penalty_gradient(setting: &Setting, gradient: &mut [f64]) {
    let weights = penalty_weights(setting.space());
    for (c, weight) in slack_weights(setting.layout(), weights) {
        gradient[c] = weight;
    }
}

/// What the slacks of the primal point x of a formulation of `setting` relax
/// ([`Formulation::setting`](crate::problem::Formulation::setting)), or None in the hard kind.
pub fn relaxation(setting: &Setting, x: &[f64]) -> Option<Relaxation> {
    let layout = setting.layout();
    if layout.kind == ProblemKind::Hard {
        return None;
    }
    let mut relaxation = Relaxation {
        penalty: penalty(setting, x),
        ..Relaxation::default()
    };
    for k in 0..layout.steps {
        let h = setting.step_at(x, k);
        for i in 0..layout.dof {
            if let Some([plus, minus]) = layout.slack(FamilyId::Dynamics, k, i) {
                relaxation.torque_deficit += h * (x[plus] - x[minus]).abs();
                relaxation.largest = relaxation.largest.max(x[plus]).max(x[minus]);
            }
            if let Some([plus, minus]) = layout.slack(FamilyId::MotorSpeed, k, i) {
                relaxation.speed_excess += h * (x[plus] - x[minus]).abs();
                relaxation.largest = relaxation.largest.max(x[plus]).max(x[minus]);
            }
        }
    }
    Some(relaxation)
}

/// The slacks' bounds: non-negative.
#[derive(Debug)]
struct Slacks;

/// Slacks in the elastic kind only.
pub(super) fn of(shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    (shape.kind == ProblemKind::Elastic).then(|| Arc::new(Slacks) as Arc<dyn Family>)
}

impl Family for Slacks {
    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], _upper: &mut [f64]) {
        lower[p.setting().layout().slacks()].fill(0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt;
    use crate::model::task::{LimitMode, LimitModes};
    use crate::model::Robot;
    use crate::problem::Formulation;

    /// The feasible reference cases: every feasible case of tests/data/ocp_reference.json and
    /// the committed original designs that IPOPT solves (results/original): (space, payload kg,
    /// ratios).
    const FEASIBLE: [(Space, f64, [f64; 4]); 6] = [
        (Space::Actuation, 0.0, [6.0, 3.0, 1.0, 1.0]),
        (Space::Actuation, 1.0, [6.0, 3.0, 1.0, 1.0]),
        (Space::Actuation, 1.0, [9.0, 5.62, 3.0, 1.8]),
        (Space::Joint, 0.0, [6.0, 3.0, 1.0, 1.0]),
        (Space::Joint, 1.0, [6.0, 3.0, 1.0, 1.0]),
        (Space::Joint, 3.0, [6.0, 3.0, 1.0, 1.0]),
    ];

    /// The penalty rule of [`multiplier_bounds`]: on the feasible reference cases the hard
    /// problem's multipliers of the relaxed rows stay below the bounds.
    #[test]
    fn weights_exceed_the_hard_multipliers() {
        let mut task = crate::testing::task();
        for (space, payload, ratios) in FEASIBLE {
            for speed in [LimitMode::Exact, LimitMode::Interval] {
                task.payload.mass_kg = payload;
                let robot = Robot::load(&task).unwrap();
                let modes = LimitModes {
                    speed,
                    ..task.limit_modes
                };
                let f = Formulation::new(&task, robot, space, modes).unwrap();
                let mut problem = f.problem(&ratios).unwrap();
                let options = crate::testing::settings().ipopt_options();
                let solution = ipopt::solve(&mut problem, &options).unwrap();
                let layout = f.layout();
                let (mut torque, mut speed_multiplier) = (0.0_f64, 0.0_f64);
                for k in 0..layout.steps {
                    for i in 0..layout.dof {
                        torque = torque.max(
                            solution.lambda[layout.row(FamilyId::Dynamics, k, i).unwrap()].abs(),
                        );
                        if let Some(row) = layout.row(FamilyId::MotorSpeed, k, i) {
                            speed_multiplier = speed_multiplier.max(solution.lambda[row].abs());
                        } else if k > 0 {
                            let v = layout.v(k, i);
                            let z = solution.z_lower[v].max(solution.z_upper[v]);
                            speed_multiplier = speed_multiplier.max(z);
                        }
                    }
                }
                println!(
                    "{space} {payload} kg {ratios:?} speed {speed:?}: {} , max |lambda| dynamics {torque:.3e}, speed {speed_multiplier:.3e}",
                    solution.status.name()
                );
                assert!(solution.status.is_success());
                let (bounds, _) = multiplier_bounds(space);
                assert!(torque < bounds.torque, "{torque}");
                assert!(speed_multiplier < bounds.speed, "{speed_multiplier}");
            }
        }
    }
}
