//! Three-vectors of jets: points and directions whose coordinates are functions of the pose.

use super::{Jet, JetShape};
use nalgebra::Vector3;

/// A 3-vector whose coordinates are jets of one shape (a point in m, or a direction).
#[derive(Clone, Debug)]
pub struct JetVector<'s>(pub [Jet<'s>; 3]);

impl<'s> JetVector<'s> {
    /// The constant vector `value`.
    pub fn constant(shape: &'s JetShape, value: &Vector3<f64>) -> JetVector<'s> {
        JetVector([0, 1, 2].map(|k| Jet::constant(shape, value[k])))
    }

    /// The vector's value.
    pub fn value(&self) -> Vector3<f64> {
        Vector3::new(self.0[0].value(), self.0[1].value(), self.0[2].value())
    }

    /// The sum.
    pub fn add(&self, other: &JetVector<'s>) -> JetVector<'s> {
        JetVector([0, 1, 2].map(|k| &self.0[k] + &other.0[k]))
    }

    /// The difference.
    pub fn sub(&self, other: &JetVector<'s>) -> JetVector<'s> {
        JetVector([0, 1, 2].map(|k| &self.0[k] - &other.0[k]))
    }

    /// Each coordinate times the jet `factor`.
    pub fn times(&self, factor: &Jet<'s>) -> JetVector<'s> {
        JetVector([0, 1, 2].map(|k| &self.0[k] * factor))
    }

    /// The dot product.
    pub fn dot(&self, other: &JetVector<'s>) -> Jet<'s> {
        let [x, y, z] = [0, 1, 2].map(|k| &self.0[k] * &other.0[k]);
        &(&x + &y) + &z
    }

    /// The squared norm.
    pub fn norm_squared(&self) -> Jet<'s> {
        self.dot(self)
    }
}
