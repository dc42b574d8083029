//! A crank and rod: a motor on one link turns, through a reduction k, a crank of radius a about
//! an axis through a point c; a rod of length b joins the crank pin to a point p of another
//! link. With e1, e2 unit vectors across the axis (fixed to the crank's link) and w = p - c, the
//! pin c + a (cos theta e1 + sin theta e2) is b from p when
//!
//!   A cos theta + B sin theta = C,  A = w.e1, B = w.e2, C = (a^2 + |w|^2 - b^2) / (2 a),
//!
//! so theta = atan2(B, A) + s acos(C / R), R = sqrt(A^2 + B^2), s = +1 or -1 the branch, and
//! q_u = k theta. theta is measured from e1: the direction from the crank's axis to the rod's
//! point at the zero pose (all joints at 0) of the original design.

use super::{checked_length, Anchor, At, Entry, LinkageError};
use crate::dynamics::{Dynamics, Fixed, Workspace};
use crate::jet::Jet;
use crate::model::matrix_row::Branch;
use nalgebra::Vector3;

/// A crank on one link driving a point of another through a rod.
#[derive(Clone, Debug, PartialEq)]
pub struct CrankRod {
    /// The crank's centre, on its axis, on the link that carries the motor.
    pub crank: Anchor,
    /// The crank's unit axis and the directions theta is measured from (e1) and towards (e2 =
    /// axis x e1), in the crank body's frame.
    axis: Vector3<f64>,
    pub(super) across: [Vector3<f64>; 2],
    /// Crank radius a, m; reduction k from motor to crank; rod length b, m.
    pub(in crate::transmission) radius: Entry,
    pub(in crate::transmission) ratio: Entry,
    pub(in crate::transmission) rod: Entry,
    /// The rod's other end, on the driven link.
    pub to: Anchor,
    /// The assembly.
    pub branch: Branch,
}

/// The numbers of a crank and rod as read from a task.
pub(in crate::transmission) struct CrankNumbers {
    pub radius: Entry,
    pub ratio: Entry,
    pub rod: Entry,
}

impl CrankRod {
    /// The crank and rod of centre `crank`, unit `axis` in the crank link's frame, `numbers`, rod
    /// end `to` and `branch`; theta's reference e1 is taken at the zero pose of the design
    /// `original`. None when the rod's point lies on the crank's axis there (no reference).
    pub(in crate::transmission) fn new(
        crank: Anchor,
        axis: Vector3<f64>,
        numbers: CrankNumbers,
        to: Anchor,
        branch: Branch,
        (dynamics, original): (&Dynamics, &[f64]),
    ) -> Option<CrankRod> {
        let axis = crank.direction_on_body(&axis.normalize());
        let mut data = dynamics.workspace();
        let zero = vec![0.0; dynamics.dof()];
        let world = |anchor: &Anchor, data: &mut Workspace| {
            let pose = dynamics.body_pose(data, &zero, anchor.body());
            pose.apply(&anchor.on_body(original))
        };
        let frame = dynamics.body_pose(&mut data, &zero, crank.body());
        let w = frame.rotation.transpose() * (world(&to, &mut data) - world(&crank, &mut data));
        let across = w - axis * axis.dot(&w);
        if across.norm() < 1e-9 {
            return None;
        }
        let e1 = across.normalize();
        Some(CrankRod {
            crank,
            axis,
            across: [e1, axis.cross(&e1)],
            radius: numbers.radius,
            ratio: numbers.ratio,
            rod: numbers.rod,
            to,
            branch,
        })
    }

    /// Every number of the linkage as written.
    pub(super) fn entries(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self.crank.coordinates().to_vec();
        entries.extend(self.to.coordinates());
        entries.extend([self.radius, self.ratio, self.rod]);
        entries
    }

    /// The crank's angle theta from its reference, rad, as a jet.
    pub(super) fn crank_angle<'s>(
        &self,
        at: &At<'_, 's>,
        data: &mut Workspace,
    ) -> Result<Jet<'s>, LinkageError> {
        let radius = checked_length(at.variables.number(&self.radius, at.r, at.shape), "radius")?;
        let rod = checked_length(at.variables.number(&self.rod, at.r, at.shape), "rod length")?;
        let w = self.to.jet(at, data).sub(&self.crank.jet(at, data));
        let [e1, e2] = self.across.map(|direction| {
            let fixed = Fixed::Direction(direction);
            let joints = at.variables.joints.clone();
            at.dynamics
                .fixed_jet(data, at.q, self.crank.body(), fixed, joints, at.shape)
        });
        let (a, b) = (w.dot(&e1), w.dot(&e2));
        let radial = (&(&a * &a) + &(&b * &b)).sqrt();
        let excess = &(&(&radius * &radius) + &w.norm_squared()) - &(&rod * &rod);
        let c = excess.div(&radius.scaled(2.0, 0.0));
        if radial.value().is_nan() || radial.value() <= 0.0 {
            return Err(LinkageError::Open {
                reach: f64::INFINITY,
            });
        }
        let cosine = c.div(&radial);
        let reach = cosine.value().abs();
        if reach.is_nan() || reach >= 1.0 - 1e-9 {
            return Err(LinkageError::Open { reach });
        }
        let offset = &cosine.acos() * self.branch.sign();
        Ok(&Jet::atan2(&b, &a) + &offset)
    }

    /// The motor angle k theta, rad.
    pub(super) fn angle<'s>(
        &self,
        at: &At<'_, 's>,
        data: &mut Workspace,
    ) -> Result<Jet<'s>, LinkageError> {
        let ratio = at.variables.number(&self.ratio, at.r, at.shape);
        Ok(&self.crank_angle(at, data)? * &ratio)
    }

    /// The crank's centre, its pin and the rod's end in the world at pose `q` and design `r`,
    /// m, with the crank's angle `theta` (rad, from [`CrankRod::crank_angle`]).
    pub(super) fn drawn(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
        theta: f64,
    ) -> Vec<Vector3<f64>> {
        let frame = dynamics.body_pose(data, q, self.crank.body());
        let centre = frame.apply(&self.crank.on_body(r));
        let [e1, e2] = self.across;
        let arm = (e1 * theta.cos() + e2 * theta.sin()) * self.radius.value(r);
        let pin = centre + frame.rotation * arm;
        let to = dynamics.body_pose(data, q, self.to.body());
        vec![centre, pin, to.apply(&self.to.on_body(r))]
    }
}
