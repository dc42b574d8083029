//! A point of a linkage fixed to a link, whose coordinates may be design parameters.

use super::{At, Entry};
use crate::dynamics::{Fixed, Workspace};
use crate::jet::{Jet, JetVector};
use crate::model::chain::{LinkFrame, Placement};
use nalgebra::Vector3;

/// A point fixed to a link: its coordinates in the link's frame, m, each a constant or a
/// multiple of a design parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Anchor {
    /// The link's name in the URDF.
    pub link: String,
    /// The link's body (None: the base) and its pose in that body's frame.
    body: Option<usize>,
    placement: Placement,
    coordinates: [Entry; 3],
}

impl Anchor {
    /// The point of coordinates `coordinates` in the frame of the link `frame`.
    pub(in crate::transmission) fn new(frame: &LinkFrame, coordinates: [Entry; 3]) -> Anchor {
        Anchor {
            link: frame.name.clone(),
            body: frame.body,
            placement: frame.placement,
            coordinates,
        }
    }

    /// The body the point is fixed to (None: the base).
    pub fn body(&self) -> Option<usize> {
        self.body
    }

    /// Its coordinates as written.
    pub(super) fn coordinates(&self) -> &[Entry; 3] {
        &self.coordinates
    }

    /// The point in its body's frame at design `r`, m.
    pub fn on_body(&self, r: &[f64]) -> Vector3<f64> {
        let local = Vector3::from_fn(|k, _| self.coordinates[k].value(r));
        self.placement.apply(&local)
    }

    /// A direction given in the link's frame, in its body's frame.
    pub(super) fn direction_on_body(&self, direction: &Vector3<f64>) -> Vector3<f64> {
        self.placement.rotation * direction
    }

    /// The point's world position as a jet: in the joints through the body's pose, and in the
    /// design parameters of its coordinates.
    pub(super) fn jet<'s>(&self, at: &At<'_, 's>, data: &mut Workspace) -> JetVector<'s> {
        let joints = at.variables.joints.clone();
        let fixed = Fixed::Point(self.on_body(at.r));
        let mut point =
            at.dynamics
                .fixed_jet(data, at.q, self.body, fixed, joints.clone(), at.shape);
        for (k, entry) in self.coordinates.iter().enumerate() {
            let (Entry::Ratio { scale, .. }, Some(variable)) =
                (entry, at.variables.parameter_variable(entry.parameter()))
            else {
                continue;
            };
            // The point moves along the link's k-th axis by scale per unit of its parameter.
            let axis = Fixed::Direction(self.placement.rotation * Vector3::ith(k, 1.0));
            let moved =
                at.dynamics
                    .fixed_jet(data, at.q, self.body, axis, joints.clone(), at.shape);
            let step = Jet::variable(at.shape, variable, 0.0).scaled(*scale, 0.0);
            point = point.add(&moved.times(&step));
        }
        point
    }
}
