//! The sparse nonlinear program that IPOPT solves, as a Rust trait.

use std::fmt;

/// A failure inside a callback: an error reported back to the caller of the solve, or a point
/// outside the problem's domain, which IPOPT is told it cannot evaluate so that it cuts its step
/// back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EvalError {
    /// What failed.
    pub message: String,
    /// The point lies outside the problem's domain (a linkage that does not close there): not
    /// an error of the solve, as long as IPOPT finds points inside.
    pub outside_domain: bool,
}

impl EvalError {
    /// The point lies outside the problem's domain, for `message`'s reason.
    pub fn outside_domain(message: String) -> EvalError {
        EvalError {
            message,
            outside_domain: true,
        }
    }
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for EvalError {}

impl From<String> for EvalError {
    fn from(message: String) -> EvalError {
        EvalError {
            message,
            outside_domain: false,
        }
    }
}

impl From<&str> for EvalError {
    fn from(message: &str) -> EvalError {
        EvalError::from(message.to_owned())
    }
}

/// A sparse NLP: minimise f(x) subject to `g_l <= g(x) <= g_u` and `x_l <= x <= x_u`.
///
/// Sparse matrices are in triplet form with 0-based (row, column) pairs; the structure methods are
/// called once per solve and the value methods must fill `values` in the same order. The Hessian
/// is that of the Lagrangian `obj_factor * f(x) + sum_i lambda_i g_i(x)`, lower triangle only
/// (row >= column). `new_x` is false when x is the point of the previous call, so evaluations
/// can be cached. Infinite bounds are `f64::INFINITY` / `f64::NEG_INFINITY`.
///
/// An `Err` from any evaluation stops IPOPT; the solve then returns that error. So does a panic.
pub trait Nlp {
    /// Number of variables n.
    fn num_variables(&self) -> usize;
    /// Number of constraints m.
    fn num_constraints(&self) -> usize;
    /// Fills the bounds of the variables (length n each).
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// Fills the bounds of the constraints (length m each); equal bounds make an equality.
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// Fills the starting point (length n).
    fn initial_point(&self, x: &mut [f64]);
    /// The objective f(x).
    fn objective(&mut self, x: &[f64], new_x: bool) -> Result<f64, EvalError>;
    /// The gradient of f at x (length n).
    fn gradient(&mut self, x: &[f64], new_x: bool, gradient: &mut [f64]) -> Result<(), EvalError>;
    /// The constraint values g(x) (length m).
    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError>;
    /// The (row, column) positions of the Jacobian's structural non-zeros.
    fn jacobian_structure(&self) -> Vec<(usize, usize)>;
    /// The Jacobian's values at x, in the order of [`Nlp::jacobian_structure`].
    fn jacobian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        values: &mut [f64],
    ) -> Result<(), EvalError>;
    /// The (row, column) positions of the Lagrangian Hessian's non-zeros, lower triangle.
    fn hessian_structure(&self) -> Vec<(usize, usize)>;
    /// The Lagrangian Hessian's values, in the order of [`Nlp::hessian_structure`].
    fn hessian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        values: &mut [f64],
    ) -> Result<(), EvalError>;
}
