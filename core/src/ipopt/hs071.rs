//! Problem 71 of Hock and Schittkowski, the classic IPOPT example, with exact derivatives.
//!
//! minimise x0 x3 (x0 + x1 + x2) + x2 subject to x0 x1 x2 x3 >= 25,
//! x0^2 + x1^2 + x2^2 + x3^2 = 40, 1 <= x <= 5, from x = (1, 5, 5, 1).
//! The optimum is f* = 17.0140173 at x* = (1, 4.7430, 3.8211, 1.3794).
//! It is the installation check of `codesign doctor` and the binding's own test problem.

use super::{EvalError, Nlp};

/// The HS071 problem (stateless).
#[derive(Clone, Copy, Debug, Default)]
pub struct Hs071;

/// HS071's optimal objective value, to the digits published.
pub const HS071_OPTIMUM: f64 = 17.014_017_3;

impl Nlp for Hs071 {
    fn num_variables(&self) -> usize {
        4
    }

    fn num_constraints(&self) -> usize {
        2
    }

    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(1.0);
        upper.fill(5.0);
    }

    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.copy_from_slice(&[25.0, 40.0]);
        upper.copy_from_slice(&[f64::INFINITY, 40.0]);
    }

    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[1.0, 5.0, 5.0, 1.0]);
    }

    fn objective(&mut self, x: &[f64], _new_x: bool) -> Result<f64, EvalError> {
        Ok(x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2])
    }

    fn gradient(&mut self, x: &[f64], _new_x: bool, gradient: &mut [f64]) -> Result<(), EvalError> {
        gradient[0] = x[3] * (2.0 * x[0] + x[1] + x[2]);
        gradient[1] = x[0] * x[3];
        gradient[2] = x[0] * x[3] + 1.0;
        gradient[3] = x[0] * (x[0] + x[1] + x[2]);
        Ok(())
    }

    fn constraints(&mut self, x: &[f64], _new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = x[0] * x[1] * x[2] * x[3];
        g[1] = x.iter().map(|value| value * value).sum();
        Ok(())
    }

    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        (0..2)
            .flat_map(|row| (0..4).map(move |col| (row, col)))
            .collect()
    }

    fn jacobian_values(
        &mut self,
        x: &[f64],
        _new_x: bool,
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        values[0] = x[1] * x[2] * x[3];
        values[1] = x[0] * x[2] * x[3];
        values[2] = x[0] * x[1] * x[3];
        values[3] = x[0] * x[1] * x[2];
        for i in 0..4 {
            values[4 + i] = 2.0 * x[i];
        }
        Ok(())
    }

    fn hessian_structure(&self) -> Vec<(usize, usize)> {
        (0..4)
            .flat_map(|row| (0..=row).map(move |col| (row, col)))
            .collect()
    }

    fn hessian_values(
        &mut self,
        x: &[f64],
        _new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        let (s, l0, l1) = (obj_factor, lambda[0], lambda[1]);
        // Order: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2) (3,3).
        values[0] = s * 2.0 * x[3] + 2.0 * l1;
        values[1] = s * x[3] + l0 * x[2] * x[3];
        values[2] = 2.0 * l1;
        values[3] = s * x[3] + l0 * x[1] * x[3];
        values[4] = l0 * x[0] * x[3];
        values[5] = 2.0 * l1;
        values[6] = s * (2.0 * x[0] + x[1] + x[2]) + l0 * x[1] * x[2];
        values[7] = s * x[0] + l0 * x[0] * x[2];
        values[8] = s * x[0] + l0 * x[0] * x[1];
        values[9] = 2.0 * l1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::{check_derivatives, solve, DerivativeOrder, LinearSolver, Options, Status};

    #[test]
    fn solves_to_the_published_optimum_with_either_linear_solver() {
        for solver in [LinearSolver::Ldl, LinearSolver::Mumps] {
            solves_to_the_published_optimum(solver);
        }
    }

    fn solves_to_the_published_optimum(solver: LinearSolver) {
        let options = Options::new().num("tol", 1e-8).linear_solver(solver);
        let solution = solve(&mut Hs071, &options).unwrap();
        assert_eq!(solution.status, Status::SolveSucceeded);
        assert!(
            (solution.objective - HS071_OPTIMUM).abs() < 1e-6,
            "{}",
            solution.objective
        );
        let expected = [1.0, 4.742_999_64, 3.821_149_98, 1.379_408_29];
        for (got, want) in solution.x.iter().zip(expected) {
            assert!((got - want).abs() < 1e-6, "{:?}", solution.x);
        }
        assert!(solution.iterations > 0 && solution.iterations < 20);
        assert!(solution.lambda.iter().all(|value| value.is_finite()));
        assert!(solution.timing.callbacks <= solution.timing.total);
    }

    #[test]
    fn derivative_checker_finds_no_error() {
        for order in [DerivativeOrder::First, DerivativeOrder::Second] {
            let report = check_derivatives(&mut Hs071, &Options::new(), order).unwrap();
            assert_eq!(report.errors, 0, "{:?}", report.flagged);
        }
    }
}
