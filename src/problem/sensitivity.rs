//! The exact sensitivity of the optimal cost to the design, by the envelope theorem.
//!
//! At a primal-dual solution (x*, lambda*, z_L*, z_U*) of the trajectory problem,
//! dJ*/dr = dL/dr, the partial derivative of the Lagrangian
//! L = J(x) + lambda^T g(x, r) - z_L^T (x - x_L(r)) + z_U^T (x - x_U(r))
//! with respect to r at fixed (x, lambda, z). The design enters through G(r), and each
//! constraint family gives its own terms (`families/`): the dynamics rows, the motor speed and
//! torque rows of the `exact` modes, the torque-speed envelope's rows, and the variable bounds of
//! the box modes `paper` and `interval`. This walks them: for each design parameter, every
//! node's row terms, node by node and family by family, then the families' bound terms.
//!
//! The result holds where the active set does not change with r; at a kink of an absolute
//! value (a bound that is exactly 0, such as joint 4's torque under the `paper` mode) the
//! one-sided derivatives differ and 0 is used.

use super::families::{DesignDerivative, Place};
use super::nlp::TrajectoryProblem;
use crate::ipopt::Solution;

/// dJ*/dr at `solution`, a solution of `problem` (one entry per ratio). For the elastic kind
/// (docs/model.md, section 14) the derivative of its optimal penalised objective: its slacks
/// and their penalty do not depend on r, and the box speed limits it holds as rows enter
/// through their bounds.
pub fn cost_gradient(problem: &TrajectoryProblem<'_>, solution: &Solution) -> Vec<f64> {
    let f = problem.formulation();
    let layout = f.layout();
    (0..f.transmission().num_ratios())
        .map(|l| {
            let dg = f.transmission().matrix_derivative(l);
            let derivative = DesignDerivative {
                dg_inv: problem.actuation().inverse_derivative(&dg),
                dg,
            };
            let mut total = 0.0;
            for k in 0..layout.steps {
                for (id, family) in f.families() {
                    if let Some(row) = layout.first_row(*id, k) {
                        let place = Place { k, row };
                        family.sensitivity(problem, solution, &derivative, place, &mut total);
                    }
                }
            }
            for (_, family) in f.families() {
                family.bound_sensitivity(problem, solution, &derivative, &mut total);
            }
            total
        })
        .collect()
}
