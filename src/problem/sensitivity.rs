//! The exact sensitivity of the optimal cost to the design, by the envelope theorem.
//!
//! At a primal-dual solution (x*, lambda*, z_L*, z_U*) of the trajectory problem,
//! dJ*/dr = dL/dr, the partial derivative of the Lagrangian
//! L = J(x) + lambda^T g(x, r) - z_L^T (x - x_L(r)) + z_U^T (x - x_U(r))
//! with respect to r at fixed (x, lambda, z). The design enters through G(r):
//! - the dynamics rows, whose r-derivative the actuation gives
//!   ([`Actuation::residual_derivative`](crate::transmission::Actuation::residual_derivative):
//!   -dG_l^T u in actuation space, RNEA - G^T u);
//! - the motor-speed rows G v and the motor-torque rows G^-T u of the `exact` modes
//!   (d(G^-T)/dr_l = -G^-T dG_l^T G^-T);
//! - the torque-speed envelope's rows tau_u(u) +- c (G v + B d): d(tau_u)/dr_l (0 in actuation
//!   space, d(G^-T)/dr_l u in joint space) +- c (dG_l v + dB_l d), with d the elastic kind's
//!   speed relaxation and dB_l = dG_l in its box speed modes, 0 otherwise;
//! - the variable bounds of the `paper` and `interval` modes (d/dr_l of |sum_j A_ij l_j| and
//!   sum_j |A_ij| l_j, with A = G^T for torques and G^-1 for speeds and l_j motor j's own
//!   limit), and the same bounds on the speed rows v_k of the elastic kind, where the active
//!   bound's multiplier weighs them.
//!
//! The result holds where the active set does not change with r; at a kink of an absolute
//! value (a bound that is exactly 0, such as joint 4's torque under the `paper` mode) the
//! one-sided derivatives differ and 0 is used.

use super::{Space, TrajectoryProblem};
use crate::ipopt::Solution;
use crate::model::task::LimitMode;
use crate::transmission::{limit_weights, Side};
use nalgebra::{DMatrix, DVector, RowDVector};

/// d(upper bound)/dr of the box limits |x_i| <= b_i(r) of a mode, for A(r), dA/dr and the
/// motors' own limits l (b = |A l| in mode `paper`, b_i = sum_j |A_ij| l_j in mode `interval`).
/// The sums over the motors are formed as the limits' bounds are ([`limit_weights`]).
fn box_bound_derivative(
    mode: LimitMode,
    a: &DMatrix<f64>,
    da: &DMatrix<f64>,
    limits: &[f64],
) -> Option<Vec<f64>> {
    let sign = |value: f64| {
        if value > 0.0 {
            1.0
        } else if value < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    let (scale, weights) = limit_weights(limits);
    let w = RowDVector::from_row_slice(&weights);
    match mode {
        LimitMode::Paper => Some(
            (0..a.nrows())
                .map(|i| {
                    sign(a.row(i).component_mul(&w).sum())
                        * scale
                        * da.row(i).component_mul(&w).sum()
                })
                .collect(),
        ),
        LimitMode::Interval => Some(
            (0..a.nrows())
                .map(|i| {
                    scale
                        * (0..a.ncols())
                            .map(|j| sign(a[(i, j)]) * da[(i, j)] * weights[j])
                            .sum::<f64>()
                })
                .collect(),
        ),
        LimitMode::Exact => None,
    }
}

/// lambda . d/dr_l of node k's envelope rows at `solution`, for `dg` = dG/dr_l (0 where the node
/// has none): with lambda_P and lambda_M the multipliers of the rows P = tau_u + c w and
/// M = tau_u - c w, w = G v + B d the motor speeds they see,
/// (lambda_P + lambda_M) . d(tau_u)/dr_l + (lambda_P - lambda_M) . c (dG_l v + dB_l d).
fn envelope_term(
    problem: &TrajectoryProblem<'_>,
    solution: &Solution,
    k: usize,
    dg: &DMatrix<f64>,
) -> f64 {
    let f = problem.formulation();
    let layout = f.layout();
    let (Some(envelope), Some(plus), Some(minus)) = (
        f.envelope(),
        layout.envelope_row(k, 0, Side::Plus),
        layout.envelope_row(k, 0, Side::Minus),
    ) else {
        return 0.0;
    };
    let n = layout.dof;
    let (x, lambda) = (&solution.x, &solution.lambda);
    let (lambda_plus, lambda_minus) = (&lambda[plus..plus + n], &lambda[minus..minus + n]);
    let v = DVector::from_column_slice(&x[layout.v(k, 0)..layout.v(k, 0) + n]);
    let mut speed_derivative = dg * v;
    // B = G in the elastic kind's box speed modes (dB = dG), the identity in mode `exact`.
    if let (Some(d), LimitMode::Paper | LimitMode::Interval) =
        (problem.speed_relaxation(x, k), f.modes().speed)
    {
        speed_derivative += dg * d;
    }
    let u = &x[layout.u(k, 0)..layout.u(k, 0) + n];
    let torque_derivative = problem.actuation().motor_torque_derivative(dg, u);
    (0..n)
        .map(|i| {
            let torque = torque_derivative.as_ref().map_or(0.0, |d| d[i]);
            (lambda_plus[i] + lambda_minus[i]) * torque
                + (lambda_plus[i] - lambda_minus[i]) * envelope.slope(i) * speed_derivative[i]
        })
        .sum()
}

/// dJ*/dr at `solution`, a solution of `problem` (one entry per ratio). For the elastic kind
/// (docs/model.md, section 14) the derivative of its optimal penalised objective: its slacks
/// and their penalty do not depend on r, and the box speed limits it holds as rows enter
/// through their bounds.
pub fn cost_gradient(problem: &TrajectoryProblem<'_>, solution: &Solution) -> Vec<f64> {
    let f = problem.formulation();
    let layout = f.layout();
    let (n, steps) = (layout.dof, layout.steps);
    let actuation = problem.actuation();
    let g = actuation.coupling().matrix();
    let g_inv = actuation.coupling().inverse();
    let (x, lambda) = (&solution.x, &solution.lambda);
    let segment = |start: usize| DVector::from_column_slice(&x[start..start + n]);
    let multipliers = |row: usize| DVector::from_column_slice(&lambda[row..row + n]);
    (0..f.transmission().num_ratios())
        .map(|l| {
            let dg = f.transmission().matrix_derivative(l);
            let dg_inv = actuation.inverse_derivative(&dg);
            let modes = f.modes();
            let speed_box =
                box_bound_derivative(modes.speed, g_inv, &dg_inv, f.motor_speed_limits());
            let mut total = 0.0;
            for k in 0..steps {
                let u = segment(layout.u(k, 0));
                let state = (
                    &x[layout.v(k, 0)..layout.v(k, 0) + n],
                    &x[layout.a(k, 0)..layout.a(k, 0) + n],
                );
                if let Some(d) = actuation.residual_derivative(&dg, state, u.as_slice()) {
                    total += multipliers(layout.dynamics_row(k, 0)).dot(&d);
                }
                if let Some(row) = layout.speed_row(k, 0) {
                    total += match &speed_box {
                        // Rows G v within fixed bounds (mode `exact`).
                        None => multipliers(row).dot(&(&dg * segment(layout.v(k, 0)))),
                        // Rows v within [-b(r), b(r)] (the elastic kind's box modes): the
                        // active bound's term -lambda . d(bound)/dr is -|lambda| . db/dr.
                        Some(db) => -multipliers(row).abs().dot(&DVector::from_column_slice(db)),
                    };
                }
                if let Some(row) = layout.torque_row(k, 0) {
                    // G^-T u differentiates to -G^-T dG^T G^-T u = dG_inv^T u.
                    total += multipliers(row).dot(&dg_inv.tr_mul(&u));
                }
                total += envelope_term(problem, solution, k, &dg);
            }
            // Bounds x_L = -b(r), x_U = b(r): dL/dr = z_L . dx_L/dr - z_U . dx_U/dr
            // = -(z_L + z_U) . db/dr.
            let mut bound_term = |columns: &dyn Fn(usize, usize) -> usize,
                                  nodes: std::ops::Range<usize>,
                                  db: &[f64]| {
                for k in nodes {
                    for (i, d) in db.iter().enumerate() {
                        let column = columns(k, i);
                        total -= (solution.z_lower[column] + solution.z_upper[column]) * d;
                    }
                }
            };
            if let (Some(db), false) = (&speed_box, layout.speed_rows) {
                bound_term(&|k, i| layout.v(k, i), 1..steps, db);
            }
            if f.space() == Space::Joint {
                let (gt, dgt) = (g.transpose(), dg.transpose());
                if let Some(db) =
                    box_bound_derivative(modes.torque, &gt, &dgt, f.motor_torque_limits())
                {
                    bound_term(&|k, i| layout.u(k, i), 0..steps, &db);
                }
            }
            total
        })
        .collect()
}
