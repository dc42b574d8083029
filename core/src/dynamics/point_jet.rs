//! Points and directions fixed to a body, as jets in the joint angles: their derivatives of every
//! order in closed form.
//!
//! A vector x fixed to body b turns with each joint j <= b about its axis u_j through p_j:
//! dx/dq_j = u_j x (x - p_j) for a point, u_j x x for a direction. The axes and origins of the
//! joints beyond i turn with joint i as well, so for sorted joints i1 <= i2 <= ... <= ik <= b,
//!
//!   d^k x / dq_i1 ... dq_ik = u_i1 x (u_i2 x ( ... (u_ik x (x - p_ik)))),
//!
//! (the innermost term u_ik x x for a direction), and zero when a joint lies beyond b. With the
//! world motion vector S_j = (w_j, l_j) the innermost term is w_ik x x + l_ik, which also serves a
//! prismatic joint (w = 0, l = u: it slides a point and turns nothing, so it contributes only as
//! the innermost joint). The Taylor coefficient of a monomial is that derivative over the
//! factorials of its multiplicities.

use super::{Dynamics, Workspace};
use crate::jet::{Jet, JetShape, JetVector};
use crate::model::chain::PointOnBody;
use nalgebra::Vector3;
use std::ops::Range;

/// What a vector fixed to a body is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fixed {
    /// A point, in the body's frame, m.
    Point(Vector3<f64>),
    /// A direction (a free vector), in the body's frame.
    Direction(Vector3<f64>),
}

impl Dynamics {
    /// The world coordinates at `q` of `vector`, fixed to `body` (None: the base), as jets in
    /// the joints `joints`: the shape's primary variable k is joint `joints.start + k`. Its
    /// other variables do not move the vector (their coefficients are zero).
    ///
    /// # Panics
    /// If the shape has fewer primary variables than `joints`, or `joints` or `body` lie beyond
    /// the chain.
    pub fn fixed_jet<'s>(
        &self,
        data: &mut Workspace,
        q: &[f64],
        body: Option<usize>,
        vector: Fixed,
        joints: Range<usize>,
        shape: &'s JetShape,
    ) -> JetVector<'s> {
        assert!(joints.end <= self.dof() && joints.len() <= shape.primary());
        self.update_frames(data, q);
        let (world, origin_counts) = match (vector, body) {
            (Fixed::Point(p), Some(b)) => (data.frames[b].pose.apply(&p), true),
            (Fixed::Direction(d), Some(b)) => (data.frames[b].pose.rotation * d, false),
            (Fixed::Point(p) | Fixed::Direction(p), None) => (p, false),
        };
        let reach = body.map_or(0, |b| b + 1);
        let mut derivatives: Vec<Vector3<f64>> = vec![Vector3::zeros(); shape.len()];
        let mut coefficients = [0, 1, 2].map(|_| vec![0.0; shape.len()]);
        for (m, variables) in shape.monomials().iter().enumerate() {
            let Some((&first, tail)) = variables.split_first() else {
                continue;
            };
            let last = *variables.last().unwrap_or(&first);
            if last >= joints.len() || joints.start + last >= reach {
                continue;
            }
            let axis = data.frames[joints.start + first].s;
            let inner = if tail.is_empty() {
                // u x (x - p) = u x x + p x u = ang x x + lin for a point.
                let turned = axis.ang.cross(&world);
                if origin_counts {
                    turned + axis.lin
                } else {
                    turned
                }
            } else {
                axis.ang.cross(&derivatives[shape.tail(m)])
            };
            derivatives[m] = inner;
            let factor = shape.multiplicity_factorial(m);
            for (coefficient, value) in coefficients.iter_mut().zip(inner.iter()) {
                coefficient[m] = value / factor;
            }
        }
        for (coefficient, value) in coefficients.iter_mut().zip(world.iter()) {
            coefficient[0] = *value;
        }
        JetVector(coefficients.map(|c| Jet::from_coefficients(shape, c)))
    }

    /// [`Dynamics::fixed_jet`] of a point on a body.
    pub fn point_jet<'s>(
        &self,
        data: &mut Workspace,
        q: &[f64],
        point: &PointOnBody,
        joints: Range<usize>,
        shape: &'s JetShape,
    ) -> JetVector<'s> {
        self.fixed_jet(
            data,
            q,
            point.body,
            Fixed::Point(point.point),
            joints,
            shape,
        )
    }
}
