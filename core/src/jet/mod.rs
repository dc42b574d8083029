//! Truncated multivariate Taylor polynomials ("jets"): exact derivatives of any order of
//! compositions of a few smooth operations, without writing the chain rule out by hand.
//!
//! A [`Jet`] of shape [`JetShape`] holds the Taylor coefficients of a function f(x0 + h) in the
//! small displacement h, up to a total degree: f(x0) + sum_i c_i h_i + sum_{i<=j} c_ij h_i h_j +
//! ... Sums and products truncate at the shape's order, and a smooth function of one variable
//! composes through its derivatives at the value ([`Jet::compose`]). The partial derivative of
//! a monomial is its coefficient times the factorials of its multiplicities
//! ([`Jet::derivative`]).
//!
//! The linkages of pose-dependent transmissions (docs/model.md, section 17) use them: their motor
//! angle is a short formula (a distance, a loop closure) of point positions whose derivatives in
//! q of every order are nested cross products, and the trajectory problem needs its derivatives
//! to the fourth order in q and the first in the design parameters.

mod coefficients;
mod functions;
mod shape;
mod vector;

pub use shape::{JetShape, MAX_ORDER};
pub use vector::JetVector;

use coefficients::Coefficients;
use std::ops::{Add, Mul, Neg, Sub};

/// A truncated Taylor polynomial of shape `shape`: its coefficients, one per monomial.
#[derive(Clone, Debug)]
pub struct Jet<'s> {
    shape: &'s JetShape,
    coefficients: Coefficients,
}

impl<'s> Jet<'s> {
    /// The constant `value` (all derivatives zero).
    pub fn constant(shape: &'s JetShape, value: f64) -> Jet<'s> {
        let mut coefficients = Coefficients::zeros(shape.len());
        coefficients[0] = value;
        Jet {
            shape,
            coefficients,
        }
    }

    /// Variable number `variable` at `value`: value + h_variable (the constant `value` in a
    /// shape of order 0).
    ///
    /// # Panics
    /// If the shape has no such variable.
    pub fn variable(shape: &'s JetShape, variable: usize, value: f64) -> Jet<'s> {
        assert!(
            variable < shape.primary() + shape.linear(),
            "a variable of the jet's shape"
        );
        let mut jet = Jet::constant(shape, value);
        if let Some(monomial) = shape.monomial(&[variable]) {
            jet.coefficients[monomial] = 1.0;
        }
        jet
    }

    /// The jet with the given coefficients, one per monomial of `shape`.
    ///
    /// # Panics
    /// If there is not one coefficient per monomial.
    pub fn from_coefficients(shape: &'s JetShape, coefficients: Vec<f64>) -> Jet<'s> {
        assert_eq!(
            coefficients.len(),
            shape.len(),
            "one coefficient per monomial"
        );
        Jet {
            shape,
            coefficients: Coefficients::of(coefficients),
        }
    }

    /// The shape.
    pub fn shape(&self) -> &'s JetShape {
        self.shape
    }

    /// The value f(x0).
    pub fn value(&self) -> f64 {
        self.coefficients[0]
    }

    /// The Taylor coefficients, one per monomial of the shape.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The partial derivative of f at x0 in the sorted variables `variables` (a multiset, e.g.
    /// `[0, 0, 2]` for d^3 f / dx0^2 dx2), or 0 where the shape does not keep that monomial.
    pub fn derivative(&self, variables: &[usize]) -> f64 {
        match self.shape.monomial(variables) {
            Some(m) => self.coefficients[m] * self.shape.multiplicity_factorial(m),
            None => 0.0,
        }
    }

    /// `self * factor + addend`, coefficient by coefficient.
    pub fn scaled(&self, factor: f64, addend: f64) -> Jet<'s> {
        let mut jet = self.map(|c| c * factor);
        jet.coefficients[0] += addend;
        jet
    }

    /// The jet with `f` applied to each coefficient.
    fn map(&self, f: impl Fn(f64) -> f64) -> Jet<'s> {
        Jet {
            shape: self.shape,
            coefficients: Coefficients::mapped(&self.coefficients, f),
        }
    }

    /// The jet with `f` applied to the coefficients of `self` and `other`, pairwise.
    fn zip(&self, other: &Jet<'s>, f: impl Fn(f64, f64) -> f64) -> Jet<'s> {
        self.expect_same_shape(other);
        let mut coefficients = Coefficients::zeros(self.coefficients.len());
        let pairs = self.coefficients.iter().zip(other.coefficients.iter());
        for (c, (&a, &b)) in coefficients.iter_mut().zip(pairs) {
            *c = f(a, b);
        }
        Jet {
            shape: self.shape,
            coefficients,
        }
    }

    fn expect_same_shape(&self, other: &Jet<'s>) {
        assert!(
            std::ptr::eq(self.shape, other.shape),
            "jets of one shape combine"
        );
    }
}

impl<'s> Add for &Jet<'s> {
    type Output = Jet<'s>;
    fn add(self, other: &Jet<'s>) -> Jet<'s> {
        self.zip(other, |a, b| a + b)
    }
}

impl<'s> Sub for &Jet<'s> {
    type Output = Jet<'s>;
    fn sub(self, other: &Jet<'s>) -> Jet<'s> {
        self.zip(other, |a, b| a - b)
    }
}

impl<'s> Neg for &Jet<'s> {
    type Output = Jet<'s>;
    fn neg(self) -> Jet<'s> {
        self.map(|c| -c)
    }
}

impl<'s> Mul for &Jet<'s> {
    type Output = Jet<'s>;
    /// The product, truncated to the shape.
    fn mul(self, other: &Jet<'s>) -> Jet<'s> {
        self.expect_same_shape(other);
        let mut coefficients = Coefficients::zeros(self.shape.len());
        // The slices once, not through the enum at every product.
        let (left, right, product) = (
            &*self.coefficients,
            &*other.coefficients,
            &mut *coefficients,
        );
        for &(a, b, c) in self.shape.products() {
            product[c as usize] += left[a as usize] * right[b as usize];
        }
        Jet {
            shape: self.shape,
            coefficients,
        }
    }
}

impl<'s> Mul<f64> for &Jet<'s> {
    type Output = Jet<'s>;
    fn mul(self, factor: f64) -> Jet<'s> {
        self.map(|c| c * factor)
    }
}

#[cfg(test)]
mod tests;
