//! The exact sensitivity of the optimal cost to the design, by the envelope theorem.
//!
//! At a primal-dual solution (x*, lambda*, z_L*, z_U*) of the trajectory problem,
//! dJ*/dr = dL/dr, the partial derivative of the Lagrangian
//! L = J(x) + lambda^T g(x, r) - z_L^T (x - x_L(r)) + z_U^T (x - x_U(r))
//! with respect to r at fixed (x, lambda, z). The design enters through G(r) (and, where the
//! links carry parts that follow it, through their inertia in the dynamics rows: docs/model.md,
//! section 18), and each
//! constraint family gives its own terms (`families/`): the dynamics rows, the motor speed and
//! torque rows of the `exact` modes, the torque-speed envelope's rows, and the variable bounds of
//! the box modes `paper` and `interval`. This walks them: for each design parameter, every
//! node's row terms, node by node and family by family, then the families' bound terms.
//!
//! The result holds where the active set does not change with r; at a kink of an absolute
//! value (a bound that is exactly 0, such as joint 4's torque under the `paper` mode) the
//! one-sided derivatives differ and 0 is used.
//!
//! Where G depends on the pose (docs/model.md, section 17), each node's terms take dG/dr_l at
//! that node's q_k.

use super::families::{own_torques, speed_terms, DesignDerivative, LoadDerivative, Place};
use super::nlp::TrajectoryProblem;
use crate::ipopt::Solution;
use crate::transmission::{Depth, DesignDerivativeAt, MotorDynamics, PoseCoupling, PoseError};
use nalgebra::DVector;

/// dJ*/dr at `solution`, a solution of `problem` (one entry per ratio). For the elastic kind
/// (docs/model.md, section 14) the derivative of its optimal penalised objective: its slacks
/// and their penalty do not depend on r, and the box speed limits it holds as rows enter
/// through their bounds. Where G depends on the pose, dG/dr_l is taken at each node's q_k; the
/// error says where a linkage does not close on the solution's trajectory.
pub fn cost_gradient(
    problem: &TrajectoryProblem<'_>,
    solution: &Solution,
) -> Result<Vec<f64>, PoseError> {
    let f = problem.formulation();
    let layout = f.layout();
    let per_node = node_derivatives(problem, solution)?;
    let gradient = (0..f.transmission().num_ratios())
        .map(|l| {
            let dg = f.transmission().matrix_derivative(l);
            let design = DesignDerivative {
                dg_inv: problem.actuation().inverse_derivative(&dg),
                dg,
                parameter: l,
                angle: DVector::zeros(layout.dof),
                coupling: None,
                load: None,
            };
            let mut total = 0.0;
            for k in 0..layout.steps {
                let derivative = per_node.as_ref().map_or(&design, |nodes| &nodes[k][l]);
                for (id, family) in f.families() {
                    if let Some(row) = layout.first_row(*id, k) {
                        let place = Place { k, row };
                        family.sensitivity(
                            problem.design(),
                            solution,
                            derivative,
                            place,
                            &mut total,
                        );
                    }
                }
            }
            for (_, family) in f.families() {
                family.bound_sensitivity(problem.design(), solution, &design, &mut total);
            }
            total
        })
        .collect();
    Ok(gradient)
}

/// For a pose-dependent transmission, dG/dr_l and d(G^-1)/dr_l at each node k < N of the
/// solution (indexed [k][l]); None for a constant G(r).
fn node_derivatives(
    problem: &TrajectoryProblem<'_>,
    solution: &Solution,
) -> Result<Option<Vec<Vec<DesignDerivative>>>, PoseError> {
    let f = problem.formulation();
    let transmission = f.transmission();
    if !transmission.is_pose_dependent() {
        return Ok(None);
    }
    let (dynamics, layout) = (f.dynamics(), f.layout());
    let mut data = dynamics.workspace();
    let r = problem.ratios();
    let mut nodes = Vec::with_capacity(layout.steps);
    for k in 0..layout.steps {
        let (q, v, a) = layout.node_state(&solution.x, k);
        // The motors' speed terms need the rows' Hessians.
        let depth = match f.motor_dynamics() {
            Some(_) => Depth::Third,
            None => Depth::First,
        };
        let at = transmission.at_pose(r, (dynamics, &mut data), q, depth)?;
        let g_inv = at.coupling.inverse();
        let derivatives = transmission.design_derivatives_at(r, (dynamics, &mut data), q)?;
        let load = |at_l: &DesignDerivativeAt| {
            let motors = f.motor_dynamics()?;
            Some(load_derivative(motors, (&at, at_l), (v, a)))
        };
        let derivative = |(l, at_l): (usize, DesignDerivativeAt)| DesignDerivative {
            load: load(&at_l),
            coupling: Some(at.coupling.clone()),
            dg_inv: -(g_inv * &at_l.matrix * g_inv),
            dg: at_l.matrix,
            parameter: l,
            angle: at_l.angles,
        };
        nodes.push(
            derivatives
                .into_iter()
                .enumerate()
                .map(derivative)
                .collect(),
        );
    }
    Ok(Some(nodes))
}

/// The motors' own torques m = J_m (G a + h) + B_m G v at a node of speeds `v` and
/// accelerations `a`, with G and the rows' Hessians of `at`, and their derivative in one design
/// parameter, whose dG and d(Hessian) are `derivative`'s (docs/model.md, section 17).
fn load_derivative(
    motors: &MotorDynamics,
    (at, derivative): (&PoseCoupling, &DesignDerivativeAt),
    (v, a): (&[f64], &[f64]),
) -> LoadDerivative {
    let (v, a) = (DVector::from_column_slice(v), DVector::from_column_slice(a));
    let g = at.coupling.matrix();
    let h = speed_terms(
        at.rows.iter().map(|(motor, row)| (*motor, &row.hessian)),
        &v,
    );
    let dh = speed_terms(derivative.hessians.iter().map(|(motor, d)| (*motor, d)), &v);
    let dg = &derivative.matrix;
    LoadDerivative {
        own: own_torques(motors, &(g * &v), &(g * &a + h)),
        own_derivative: own_torques(motors, &(dg * &v), &(dg * &a + dh)),
    }
}
