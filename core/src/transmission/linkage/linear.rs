//! A linear actuator: a screw of lead l between two points turns its motor 2 pi per l of stroke,
//! q_u = 2 pi |p_to(q) - p_from(q)| / l.

use super::{checked_length, Anchor, At, Entry, LinkageError};
use crate::dynamics::Workspace;
use crate::jet::Jet;
use std::f64::consts::TAU;

/// A ball screw or cylinder between two links.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearActuator {
    /// Its end on one link.
    pub from: Anchor,
    /// Its end on the other.
    pub to: Anchor,
    /// The screw's lead, m per motor turn.
    pub(in crate::transmission) lead: Entry,
    /// The length between its ends it must keep, [min, max], m.
    pub stroke: Option<[f64; 2]>,
}

impl LinearActuator {
    /// Every number of the actuator as written.
    pub(super) fn entries(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self.from.coordinates().to_vec();
        entries.extend(self.to.coordinates());
        entries.push(self.lead);
        entries
    }

    /// The length between its ends, m, as a jet.
    /// The screw's length per motor radian at design `r`, l / 2 pi, m/rad.
    pub(super) fn length_per_angle(&self, r: &[f64]) -> f64 {
        self.lead.value(r) / TAU
    }

    /// d(l / 2 pi)/dr_p, m/rad per unit of r_p: non-zero where the lead is k r_p.
    pub(super) fn length_per_angle_derivative(&self, parameter: usize) -> f64 {
        match self.lead {
            Entry::Ratio { index, scale } if index == parameter => scale / TAU,
            _ => 0.0,
        }
    }

    pub(super) fn length<'s>(
        &self,
        at: &At<'_, 's>,
        data: &mut Workspace,
    ) -> Result<Jet<'s>, LinkageError> {
        let span = self.to.jet(at, data).sub(&self.from.jet(at, data));
        let squared = span.norm_squared();
        // Below a micrometre the screw has no direction the derivatives could follow.
        if squared.value() < 1e-12 {
            return Err(LinkageError::Collapsed {
                length: squared.value().max(0.0).sqrt(),
            });
        }
        Ok(squared.sqrt())
    }

    /// The motor angle 2 pi |p_to - p_from| / l, rad.
    pub(super) fn angle<'s>(
        &self,
        at: &At<'_, 's>,
        data: &mut Workspace,
    ) -> Result<Jet<'s>, LinkageError> {
        let lead = checked_length(at.variables.number(&self.lead, at.r, at.shape), "lead")?;
        let length = self.length(at, data)?;
        Ok(&length.div(&lead) * TAU)
    }
}
