//! Linkages from the task's rows: their links found on the chain, their numbers parsed (each a
//! constant or a design parameter), their geometry checked, with errors naming the field.

use super::super::entry::{parse_number, Entry};
use super::crank_rod::CrankNumbers;
use super::{Anchor, CrankRod, LinearActuator, Linkage, LENGTH_RANGE_M};
use crate::dynamics::Dynamics;
use crate::model::matrix_row::{CrankRodSpec, LinearSpec, LinkageSpec, PointSpec};
use crate::model::task::MatrixEntry;
use crate::text::number;
use nalgebra::Vector3;
use std::fmt;

/// Why a linkage row cannot be used: the field at fault (`transmission.matrix[1].linear.lead_m`)
/// and what is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolveError {
    /// The field, from `transmission.matrix[row]` down.
    pub field: String,
    /// What is wrong.
    pub problem: Problem,
}

/// What is wrong with a field of a linkage row.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// The robot has no link of this name.
    UnknownLink(String),
    /// Not a number of magnitude at most 1e6, nor `[-]r<i>` / `k*r<i>` of one of `ratios`.
    Number {
        /// As written.
        written: MatrixEntry,
        /// The number of design parameters.
        ratios: usize,
    },
    /// The crank's axis is zero or not finite.
    Axis,
    /// A length (a lead, a crank's radius, a rod) outside
    /// [`LENGTH_RANGE_M`](super::LENGTH_RANGE_M), m.
    Length(f64),
    /// The stroke is not finite with 0 <= min < max.
    Stroke,
    /// Both ends are on one rigid body: the ratio would be zero for every joint.
    OneBody,
    /// The rod's end lies on the crank's axis at the zero pose: no direction to measure the
    /// crank's angle from.
    NoReference,
}

impl fmt::Display for ResolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let field = &self.field;
        match &self.problem {
            Problem::UnknownLink(link) => {
                write!(f, "{field} = {link:?}: the robot has no such link")
            }
            Problem::Number { written, ratios } => {
                let shown = match written {
                    MatrixEntry::Constant(value) => value.to_string(),
                    MatrixEntry::Ratio(text) => format!("{text:?}"),
                };
                write!(
                    f,
                    "{field} = {shown} must be a number of magnitude at most 1e6, \"r<i>\", \
                     \"-r<i>\" or \"k*r<i>\" with 1 <= i <= {ratios} (the number of bounds)"
                )
            }
            Problem::Axis => write!(f, "{field} must be a finite direction, not zero"),
            Problem::Length(value) => {
                let [low, high] = LENGTH_RANGE_M;
                write!(
                    f,
                    "{field} = {} m is outside [{}, {}] m, the lengths a linkage may have",
                    number(*value),
                    number(low),
                    number(high)
                )
            }
            Problem::Stroke => write!(f, "{field} must be [min, max] in m with 0 <= min < max"),
            Problem::OneBody => write!(
                f,
                "{field}: both ends are fixed to one rigid body, so no joint moves the linkage; \
                 attach its ends to links on either side of the joints it drives"
            ),
            Problem::NoReference => write!(
                f,
                "{field}: the rod's end lies on the crank's axis at the zero pose, so the crank \
                 cannot turn it there; move the rod's end or the crank off that line"
            ),
        }
    }
}

impl std::error::Error for ResolveError {}

/// Resolving the fields of one row.
struct Row<'a> {
    field: String,
    ratios: usize,
    dynamics: &'a Dynamics,
}

impl Row<'_> {
    fn error(&self, field: &str, problem: Problem) -> ResolveError {
        ResolveError {
            field: format!("{}.{field}", self.field),
            problem,
        }
    }

    fn number(&self, field: &str, written: &MatrixEntry) -> Result<Entry, ResolveError> {
        parse_number(written, self.ratios).ok_or_else(|| {
            let problem = Problem::Number {
                written: written.clone(),
                ratios: self.ratios,
            };
            self.error(field, problem)
        })
    }

    fn anchor(
        &self,
        field: &str,
        link: &str,
        point: &[MatrixEntry; 3],
    ) -> Result<Anchor, ResolveError> {
        let chain = self.dynamics.robot().chain();
        let frame = chain
            .links
            .iter()
            .find(|frame| frame.name == link)
            .ok_or_else(|| {
                self.error(&format!("{field}.link"), Problem::UnknownLink(link.into()))
            })?;
        let mut coordinates = [Entry::Constant(0.0); 3];
        for (k, written) in point.iter().enumerate() {
            coordinates[k] = self.number(&format!("{field}.point[{k}]"), written)?;
        }
        Ok(Anchor::new(frame, coordinates))
    }

    fn point(&self, field: &str, spec: &PointSpec) -> Result<Anchor, ResolveError> {
        self.anchor(field, &spec.link, &spec.point)
    }

    fn linear(&self, spec: &LinearSpec) -> Result<Linkage, ResolveError> {
        let (from, to) = (self.point("from", &spec.from)?, self.point("to", &spec.to)?);
        let lead = self.number("lead_m", &spec.lead_m)?;
        if let Some([min, max]) = spec.stroke_m {
            if !(min.is_finite() && max.is_finite() && 0.0 <= min && min < max) {
                return Err(self.error("stroke_m", Problem::Stroke));
            }
        }
        if from.body() == to.body() {
            return Err(self.error("to.link", Problem::OneBody));
        }
        let stroke = spec.stroke_m;
        Ok(Linkage::Linear(LinearActuator {
            from,
            to,
            lead,
            stroke,
        }))
    }

    fn crank_rod(&self, spec: &CrankRodSpec, original: &[f64]) -> Result<Linkage, ResolveError> {
        let written = &spec.crank;
        let crank = self.anchor("crank", &written.link, &written.point)?;
        // Scaled by its largest component before it is normalised, so that neither its norm
        // overflows ([0, -1e308, 0]) nor its square underflows ([0, -1e-300, 0]).
        let axis = Vector3::from(written.axis);
        let largest = axis.amax();
        if !(axis.iter().all(|c| c.is_finite()) && largest > 0.0) {
            return Err(self.error("crank.axis", Problem::Axis));
        }
        let axis = axis / largest;
        let numbers = CrankNumbers {
            radius: self.number("crank.radius_m", &written.radius_m)?,
            ratio: self.number("crank.ratio", &written.ratio)?,
            rod: self.number("rod_m", &spec.rod_m)?,
        };
        let to = self.point("to", &spec.to)?;
        if crank.body() == to.body() {
            return Err(self.error("to.link", Problem::OneBody));
        }
        let at = (self.dynamics, original);
        CrankRod::new(crank, axis, numbers, to, spec.branch, at)
            .map(Linkage::CrankRod)
            .ok_or_else(|| self.error("to", Problem::NoReference))
    }
}

impl Linkage {
    /// The linkage written as row `row` of the task's `transmission.matrix`, on the chain of
    /// `dynamics`, with `original` the original design (one value per design parameter): a
    /// crank's angle is measured from the line to its rod's end at the zero pose of that design.
    pub fn resolve(
        spec: &LinkageSpec,
        row: usize,
        dynamics: &Dynamics,
        original: &[f64],
    ) -> Result<Linkage, ResolveError> {
        let resolving = Row {
            field: format!("transmission.matrix[{row}].{}", spec.kind()),
            ratios: original.len(),
            dynamics,
        };
        let linkage = match spec {
            LinkageSpec::Linear(linear) => resolving.linear(linear),
            LinkageSpec::CrankRod(crank_rod) => resolving.crank_rod(crank_rod, original),
        }?;
        match linkage.constant_length_outside() {
            Some((field, value)) => Err(resolving.error(field, Problem::Length(value))),
            None => Ok(linkage),
        }
    }
}
