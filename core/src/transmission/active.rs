//! Which bounds of the design space a design sits on, and what widening each would gain: the
//! designer's reading of an optimum at its bounds (docs/model.md, section 9).

use super::DesignSpace;
use std::fmt;

/// A design within this share of a bound's range from it is at the bound: CMA-ES, which samples
/// inside the box, converges to within about 1e-4 of it.
const ON_BOUND: f64 = 1e-3;

/// Which side of its interval a ratio sits on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundSide {
    /// Its lower bound.
    Lower,
    /// Its upper bound.
    Upper,
}

/// A ratio on one of its bounds, with dJ*/dr_i there where known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActiveBound {
    /// The ratio's index (r1 is 0).
    pub index: usize,
    /// Which bound.
    pub side: BoundSide,
    /// The bound's value.
    pub bound: f64,
    /// The ratio's value (the bound itself, or within 1e-3 of its range from it).
    pub value: f64,
    /// dJ*/dr_i at the design, where the result has it.
    pub gradient: Option<f64>,
}

/// A slope below this, per unit of a ratio, is flat.
const FLAT: f64 = 1e-6;

/// A slope with four decimals, or three significant digits below 0.01.
fn slope(value: f64) -> String {
    if value.abs() >= 0.01 || value == 0.0 {
        format!("{value:.4}")
    } else {
        format!("{value:.2e}")
    }
}

impl fmt::Display for ActiveBound {
    /// `r1 at its upper bound 9 (dJ*/dr1 = -4.642: raising the bound would lower J by about
    /// 4.642 per unit of r1)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (side, widen) = match self.side {
            BoundSide::Lower => ("lower", "lowering"),
            BoundSide::Upper => ("upper", "raising"),
        };
        let i = self.index + 1;
        write!(f, "r{i} at its {side} bound {}", self.bound)?;
        let mut notes = Vec::new();
        if self.value != self.bound {
            notes.push(format!("r{i} = {:.5}", self.value));
        }
        if let Some(g) = self.gradient {
            // Moving outward changes J by -g per unit below the lower bound, +g above the upper.
            let outward = match self.side {
                BoundSide::Lower => -g,
                BoundSide::Upper => g,
            };
            let effect = if outward < -FLAT {
                format!(
                    "{widen} the bound would lower J by about {} per unit of r{i}",
                    slope(-outward)
                )
            } else if outward > FLAT {
                "the bound does not hold J back (J rises beyond it)".to_owned()
            } else {
                "J is flat there: the bound costs nothing".to_owned()
            };
            notes.push(format!("dJ*/dr{i} = {}: {effect}", slope(g)));
        }
        if notes.is_empty() {
            return Ok(());
        }
        write!(f, " ({})", notes.join("; "))
    }
}

impl DesignSpace {
    /// The bounds design `r` sits on (within 1e-3 of the bound's range), each with dJ*/dr_i from
    /// `gradient` where given.
    pub fn active_bounds(&self, r: &[f64], gradient: Option<&[f64]>) -> Vec<ActiveBound> {
        let mut active = Vec::new();
        for (index, (&value, &[lower, upper])) in r.iter().zip(self.bounds()).enumerate() {
            let near = ON_BOUND * (upper - lower).abs().max(1.0);
            let side = if (value - lower).abs() <= near {
                Some((BoundSide::Lower, lower))
            } else if (upper - value).abs() <= near {
                Some((BoundSide::Upper, upper))
            } else {
                None
            };
            if let Some((side, bound)) = side {
                active.push(ActiveBound {
                    index,
                    side,
                    bound,
                    value,
                    gradient: gradient.and_then(|g| g.get(index).copied()),
                });
            }
        }
        active
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::Task;
    use crate::transmission::Transmission;

    /// The paper's optimum (9, 7.73, 3, 3) sits on three upper bounds of the built-in task's
    /// space; each is named with what widening it would gain.
    #[test]
    fn the_papers_optimum_is_on_three_upper_bounds() {
        let task = Task::built_in().unwrap();
        let transmission = Transmission::from_spec(&task.transmission).unwrap();
        let space = transmission.design_space();
        let gradient = [-4.5, 0.0, -20.0, 1.5];
        let active = space.active_bounds(&[9.0, 7.73, 3.0, 3.0], Some(&gradient));
        let named: Vec<usize> = active.iter().map(|a| a.index).collect();
        assert_eq!(named, [0, 2, 3]);
        assert!(active.iter().all(|a| a.side == BoundSide::Upper));
        let text = active[0].to_string();
        assert_eq!(
            text,
            "r1 at its upper bound 9 (dJ*/dr1 = -4.5000: raising the bound would lower J by \
             about 4.5000 per unit of r1)"
        );
        assert!(active[2].to_string().contains("does not hold J back"));
        assert!(space.active_bounds(&[8.0, 5.0, 2.0, 2.0], None).is_empty());
        let near = space.active_bounds(&[8.99989, 5.0, 2.0, 2.0], Some(&[-1e-9, 0.0, 0.0, 0.0]));
        assert_eq!(
            near[0].to_string(),
            "r1 at its upper bound 9 (r1 = 8.99989; dJ*/dr1 = -1.00e-9: J is flat there: the \
             bound costs nothing)"
        );
    }
}
