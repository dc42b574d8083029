//! Linkages whose motor angle depends on the pose (docs/model.md, section 17): a motor angle
//! q_u = gamma(q; r) given by the geometry of a screw or a crank and rod, with its derivatives of
//! every order the trajectory problem needs, as jets ([`crate::jet`]) in the joints the linkage
//! spans and, to first order, in its design parameters.
//!
//! - `linear`: a linear actuator (ball screw, cylinder) between two links;
//! - `crank_rod`: a crank turned by a motor on one link and a rod to a point of another.
//!
//! Joints outside the span between the linkage's two links move both its ends as one rigid body,
//! so gamma does not depend on them: a linkage's jets have one variable per joint it spans.

mod anchor;
mod crank_rod;
mod linear;
mod resolve;
mod row;

pub use anchor::Anchor;
pub use crank_rod::CrankRod;
pub use linear::LinearActuator;
pub use resolve::{Problem, ResolveError};
pub use row::{RowDerivatives, RowSensitivity, RowShape};

use super::entry::Entry;
use crate::dynamics::{Dynamics, Workspace};
use crate::jet::{Jet, JetShape};
use crate::text::number;
use nalgebra::Vector3;
use std::fmt;
use std::ops::Range;

/// A pose-dependent row of the transmission.
#[derive(Clone, Debug, PartialEq)]
pub enum Linkage {
    /// A screw between two points: q_u = 2 pi |p_to - p_from| / lead.
    Linear(LinearActuator),
    /// A crank and rod: q_u = k theta(q), theta from the loop closure.
    CrankRod(CrankRod),
}

/// Why a linkage has no motor angle at a pose: its geometry does not close there.
#[derive(Clone, Debug, PartialEq)]
pub enum LinkageError {
    /// The screw's two points coincide: its length is zero, m.
    Collapsed {
        /// The distance between the points, m.
        length: f64,
    },
    /// The rod cannot join the crank pin to its point: |C / R| >= 1 in the closure
    /// R cos(theta - phi) = C (1 at a dead point, where the rod is in line with the crank;
    /// above 1 where the rod is too short or too long).
    Open {
        /// |C / R|, dimensionless.
        reach: f64,
    },
    /// A length of the linkage (a lead, a radius, a rod length) lies outside
    /// [`LENGTH_RANGE_M`] at this design.
    Length {
        /// What the length is.
        what: &'static str,
        /// Its value, m.
        value: f64,
    },
}

/// The range every length of a linkage must lie in, m: a screw's lead, a crank's radius and a
/// rod's length, from a micrometre to a hundred metres. Below it the motor angle's derivatives,
/// which divide by the length up to its fourth power, overflow (a lead of 1e-300 m makes G(q)
/// infinite); above it no arm is built.
pub const LENGTH_RANGE_M: [f64; 2] = [1e-6, 100.0];

impl fmt::Display for LinkageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinkageError::Collapsed { length } => {
                write!(f, "its two points are {length:.3e} m apart: the screw has no length")
            }
            LinkageError::Open { reach } if *reach < 1.0 + 1e-12 => write!(
                f,
                "its crank is at a dead point (the rod in line with the crank, |C/R| = {reach:.6})"
            ),
            LinkageError::Open { reach } => write!(
                f,
                "its rod cannot reach the crank pin (the loop does not close: |C/R| = {reach:.4} > 1)"
            ),
            LinkageError::Length { what, value } => {
                let [low, high] = LENGTH_RANGE_M;
                write!(
                    f,
                    "its {what} is {} m, outside [{}, {}] m",
                    number(*value),
                    number(low),
                    number(high)
                )
            }
        }
    }
}

impl std::error::Error for LinkageError {}

/// The variables of a linkage's jets: the joints it spans (primary, in order), then its design
/// parameters (kept to first order).
#[derive(Clone, Debug, PartialEq)]
pub struct Variables {
    /// The joints, as a range of joint indices.
    pub joints: Range<usize>,
    /// The design parameters' indices in r, in the order of their variables.
    pub parameters: Vec<usize>,
}

impl Variables {
    /// The shape of jets in these variables up to `order`.
    pub fn shape(&self, order: usize) -> JetShape {
        JetShape::new(self.joints.len(), self.parameters.len(), order)
    }

    /// The jet of `entry` at design `r`: its value, with its design parameter as a variable when
    /// that parameter is one of these (a number of a linkage is `k r_i` or a constant).
    fn number<'s>(&self, entry: &Entry, r: &[f64], shape: &'s JetShape) -> Jet<'s> {
        let value = entry.value(r);
        match (*entry, self.parameter_variable(entry.parameter())) {
            (Entry::Ratio { scale, .. }, Some(variable)) => {
                Jet::variable(shape, variable, 0.0).scaled(scale, value)
            }
            _ => Jet::constant(shape, value),
        }
    }

    /// The jet variable of design parameter `parameter`, if it is one of these.
    fn parameter_variable(&self, parameter: Option<usize>) -> Option<usize> {
        let index = parameter?;
        let position = self.parameters.iter().position(|&p| p == index)?;
        Some(self.joints.len() + position)
    }
}

/// Whether `value` is a length a linkage may have ([`LENGTH_RANGE_M`]).
fn in_length_range(value: f64) -> bool {
    (LENGTH_RANGE_M[0]..=LENGTH_RANGE_M[1]).contains(&value)
}

/// The jet of a length within [`LENGTH_RANGE_M`], or the error naming it.
fn checked_length<'s>(jet: Jet<'s>, what: &'static str) -> Result<Jet<'s>, LinkageError> {
    match in_length_range(jet.value()) {
        true => Ok(jet),
        false => Err(LinkageError::Length {
            what,
            value: jet.value(),
        }),
    }
}

impl Linkage {
    /// The joints the linkage spans: those between its two links' bodies.
    pub fn joints(&self) -> Range<usize> {
        match self {
            Linkage::Linear(screw) => span(screw.from.body(), screw.to.body()),
            Linkage::CrankRod(crank) => span(crank.crank.body(), crank.to.body()),
        }
    }

    /// Its design parameters' indices in r, sorted, each once.
    pub fn parameters(&self) -> Vec<usize> {
        let entries = match self {
            Linkage::Linear(screw) => screw.entries(),
            Linkage::CrankRod(crank) => crank.entries(),
        };
        let mut parameters: Vec<usize> = entries.iter().filter_map(Entry::parameter).collect();
        parameters.sort_unstable();
        parameters.dedup();
        parameters
    }

    /// The motor angle gamma(q; r), rad, at pose `q` and design `r`, as a jet in `variables`
    /// (of shape `shape`).
    pub fn angle<'s>(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
        variables: &Variables,
        shape: &'s JetShape,
    ) -> Result<Jet<'s>, LinkageError> {
        let at = At::new(dynamics, (q, r), variables, shape);
        match self {
            Linkage::Linear(screw) => screw.angle(&at, data),
            Linkage::CrankRod(crank) => crank.angle(&at, data),
        }
    }

    /// What the linkage's geometry reads at a pose, as a jet: a screw's length between its
    /// ends, m, or a crank's angle from its reference, rad.
    pub fn measure<'s>(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
        variables: &Variables,
        shape: &'s JetShape,
    ) -> Result<Jet<'s>, LinkageError> {
        let at = At::new(dynamics, (q, r), variables, shape);
        match self {
            Linkage::Linear(screw) => screw.length(&at, data),
            Linkage::CrankRod(crank) => crank.crank_angle(&at, data),
        }
    }

    /// Its lengths ([`LENGTH_RANGE_M`]) with their fields below the row's key: a screw's
    /// `lead_m`, a crank's `crank.radius_m` and `rod_m`.
    fn lengths(&self) -> Vec<(&'static str, Entry)> {
        match self {
            Linkage::Linear(screw) => vec![("lead_m", screw.lead)],
            Linkage::CrankRod(crank) => {
                vec![("crank.radius_m", crank.radius), ("rod_m", crank.rod)]
            }
        }
    }

    /// The first of its lengths that is a constant outside [`LENGTH_RANGE_M`]: its field below
    /// the row's key and its value, m.
    pub(super) fn constant_length_outside(&self) -> Option<(&'static str, f64)> {
        self.lengths()
            .into_iter()
            .find_map(|(field, entry)| match entry {
                Entry::Constant(value) if !in_length_range(value) => Some((field, value)),
                _ => None,
            })
    }

    /// The first of its lengths that depends on the design and lies outside
    /// [`LENGTH_RANGE_M`] at design `r`: its field below the row's key, as written
    /// (`0.001*r2`), and its value, m.
    pub fn design_length_outside(&self, r: &[f64]) -> Option<(&'static str, String, f64)> {
        self.lengths()
            .into_iter()
            .find_map(|(field, entry)| match entry {
                Entry::Ratio { index, scale } if !in_length_range(entry.value(r)) => Some((
                    field,
                    format!("{}*r{}", number(scale), index + 1),
                    entry.value(r),
                )),
                _ => None,
            })
    }

    /// Its key in the task file: `linear` or `crank_rod`.
    pub fn kind(&self) -> &'static str {
        match self {
            Linkage::Linear(_) => "linear",
            Linkage::CrankRod(_) => "crank_rod",
        }
    }

    /// The name of what [`Linkage::measure`] reads, with its unit.
    pub fn measure_name(&self) -> &'static str {
        match self {
            Linkage::Linear(_) => "length between its ends (m)",
            Linkage::CrankRod(_) => "crank angle (rad)",
        }
    }

    /// A screw's length per motor radian at design `r`, l / 2 pi (m/rad): its length is its
    /// motor angle times it. None for a crank.
    pub fn length_per_angle(&self, r: &[f64]) -> Option<f64> {
        match self {
            Linkage::Linear(screw) => Some(screw.length_per_angle(r)),
            Linkage::CrankRod(_) => None,
        }
    }

    /// d(l / 2 pi)/dr_p of a screw (m/rad per unit of r_p): non-zero where its lead is k r_p;
    /// 0 for a crank.
    pub fn length_per_angle_derivative(&self, parameter: usize) -> f64 {
        match self {
            Linkage::Linear(screw) => screw.length_per_angle_derivative(parameter),
            Linkage::CrankRod(_) => 0.0,
        }
    }

    /// The points that draw the linkage at pose `q` (rad) and design `r`, in the world frame,
    /// m: a screw's two ends; a crank's centre, its pin and the rod's end on the driven link.
    /// Err where its loop does not close there (no crank pin) or a length leaves its range.
    pub fn drawn_points(
        &self,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
    ) -> Result<Vec<Vector3<f64>>, LinkageError> {
        match self {
            Linkage::Linear(screw) => Ok([&screw.from, &screw.to]
                .map(|end| {
                    let pose = dynamics.body_pose(data, q, end.body());
                    pose.apply(&end.on_body(r))
                })
                .to_vec()),
            Linkage::CrankRod(crank) => {
                let variables = Variables {
                    joints: self.joints(),
                    parameters: Vec::new(),
                };
                let shape = variables.shape(1);
                let at = At::new(dynamics, (q, r), &variables, &shape);
                let theta = crank.crank_angle(&at, data)?.value();
                Ok(crank.drawn(dynamics, data, (q, r), theta))
            }
        }
    }

    /// The range a screw's length must keep, m, if given.
    pub fn stroke(&self) -> Option<[f64; 2]> {
        match self {
            Linkage::Linear(screw) => screw.stroke,
            Linkage::CrankRod(_) => None,
        }
    }
}

/// Where a linkage is evaluated: the model, the pose, the design and the jets' variables.
struct At<'a, 's> {
    dynamics: &'a Dynamics,
    q: &'a [f64],
    r: &'a [f64],
    variables: &'a Variables,
    shape: &'s JetShape,
}

impl<'a, 's> At<'a, 's> {
    fn new(
        dynamics: &'a Dynamics,
        (q, r): (&'a [f64], &'a [f64]),
        variables: &'a Variables,
        shape: &'s JetShape,
    ) -> At<'a, 's> {
        At {
            dynamics,
            q,
            r,
            variables,
            shape,
        }
    }
}

/// The joints between two bodies of the chain (None: the base).
fn span(one: Option<usize>, other: Option<usize>) -> Range<usize> {
    let reach = |body: Option<usize>| body.map_or(0, |b| b + 1);
    let (a, b) = (reach(one), reach(other));
    a.min(b)..a.max(b)
}

#[cfg(test)]
mod tests;
