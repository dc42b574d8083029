//! The transmission G(r) (docs/model.md, sections 3 to 5): motor angles q_u = G(r) q, motor
//! speeds qd_u = G(r) qd, joint torques tau = G(r)^T tau_u, with G affine in the design ratios r.
//!
//! The structure of G and the design space come from the task file's `transmission` section;
//! nothing about the belt arm is hard-coded here. Units: ratios are dimensionless, torques N m,
//! speeds rad/s. Rows of G are motors, columns joints.
//!
//! - `spec`: reading the task's `transmission` section (its matrix, bounds, order strings);
//! - `entry`: one entry of G or number of a linkage, a constant or `k*r<i>`;
//! - `design_space`: bounds, order constraints, the original design, checks and projection;
//! - `unit_map`: the map from the unit box onto the design space, and back ([`UnitMap`]);
//! - `active`: the bounds a design sits on, with what widening each would gain;
//! - `coupling`: G(r), dG/dr_i, and G with its inverse at one design;
//! - `limits`: the joint torque and speed limits of each [`LimitMode`](crate::model::task::LimitMode);
//! - `actuation`: the controls' map to joint and motor torques at one design ([`Actuation`]);
//! - `envelope`: the motors' linear torque-speed envelope ([`Envelope`]);
//! - `loss`: the transmissions' losses under an efficiency ([`TransmissionLoss`]);
//! - `linkage`: rows whose motor angle depends on the pose, as geometry;
//! - `pose`: G(q; r) of a transmission with such rows ([`PoseCoupling`]).

mod active;
mod actuation;
mod coupling;
mod design_space;
mod entry;
mod envelope;
mod limits;
pub mod linkage;
mod loss;
mod pose;
mod spec;
mod unit_map;

pub use active::{ActiveBound, BoundSide};
pub use actuation::{Actuation, MotorDynamics, Space};
pub use coupling::Coupling;
pub use design_space::{DesignError, DesignSpace, HalfSpace, OrderConstraint};
pub use envelope::{Envelope, Side};
pub use limits::{limit_weights, JointLimits};
pub use loss::{
    speed_derivatives, transmitted_derivatives, MotorLoss, NodeLoss, TransmissionLoss,
    SPEED_SMOOTHING, TORQUE_SMOOTHING,
};
pub use pose::{Depth, DesignDerivativeAt, PoseCoupling, PoseError, PoseRow};
pub use spec::SpecError;
pub use unit_map::{UnitMap, UnitMapError};

use entry::Entry;

/// The parsed structure of G(r) with its design space.
#[derive(Clone, Debug)]
pub struct Transmission {
    dof: usize,
    /// Row-major entries of G (0 in a linkage row).
    entries: Vec<Entry>,
    /// The rows that depend on the pose, in the order of their motors.
    linkages: Vec<PoseRow>,
    space: DesignSpace,
}

impl Transmission {
    /// Number of design ratios.
    pub fn num_ratios(&self) -> usize {
        self.space.num_ratios()
    }

    /// Size of G: the number of joints (= motors).
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The design space: bounds, order constraints and the original design.
    pub fn design_space(&self) -> &DesignSpace {
        &self.space
    }

    /// The original design r (dimensionless).
    pub fn original(&self) -> &[f64] {
        self.space.original()
    }

    /// Bounds [lower, upper] of each ratio (dimensionless).
    pub fn bounds(&self) -> &[[f64; 2]] {
        self.space.bounds()
    }
}

#[cfg(test)]
mod fixtures;
