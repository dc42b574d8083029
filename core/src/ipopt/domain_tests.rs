//! A point outside the problem's domain: IPOPT is told it cannot evaluate it, cuts its step
//! back, and still solves; the solution records the last such point.

use super::{solve, EvalError, Nlp, Options, Status};

/// min e^x - 2x (at x = ln 2), defined for x < 10 only. From x = -3 Newton's first step is
/// +39, far outside.
struct Bounded;

impl Bounded {
    fn inside(x: f64) -> Result<(), EvalError> {
        if x < 10.0 {
            Ok(())
        } else {
            Err(EvalError::outside_domain(format!("x = {x} >= 10")))
        }
    }
}

impl Nlp for Bounded {
    fn num_variables(&self) -> usize {
        1
    }
    fn num_constraints(&self) -> usize {
        0
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(f64::NEG_INFINITY);
        upper.fill(f64::INFINITY);
    }
    fn constraint_bounds(&self, _: &mut [f64], _: &mut [f64]) {}
    fn initial_point(&self, x: &mut [f64]) {
        x.fill(-3.0);
    }
    fn objective(&mut self, x: &[f64], _: bool) -> Result<f64, EvalError> {
        Bounded::inside(x[0])?;
        Ok(x[0].exp() - 2.0 * x[0])
    }
    fn gradient(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> Result<(), EvalError> {
        Bounded::inside(x[0])?;
        g[0] = x[0].exp() - 2.0;
        Ok(())
    }
    fn constraints(&mut self, _: &[f64], _: bool, _: &mut [f64]) -> Result<(), EvalError> {
        Ok(())
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        Vec::new()
    }
    fn jacobian_values(&mut self, _: &[f64], _: bool, _: &mut [f64]) -> Result<(), EvalError> {
        Ok(())
    }
    fn hessian_structure(&self) -> Vec<(usize, usize)> {
        vec![(0, 0)]
    }
    fn hessian_values(
        &mut self,
        x: &[f64],
        _: bool,
        obj_factor: f64,
        _: &[f64],
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        Bounded::inside(x[0])?;
        values[0] = obj_factor * x[0].exp();
        Ok(())
    }
}

#[test]
fn ipopt_steps_back_from_points_outside_the_domain() {
    let solution = solve(&mut Bounded, &Options::new()).unwrap();
    assert_eq!(solution.status, Status::SolveSucceeded);
    assert!((solution.x[0] - 2f64.ln()).abs() < 1e-6, "{:?}", solution.x);
    let why = solution.outside_domain.unwrap();
    assert!(why.ends_with(">= 10"), "{why}");
}
