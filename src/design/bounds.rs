//! How CMA-ES's samples outside the design space are treated: scored with the penalty (the
//! paper's rule), or projected onto the space before they are evaluated (pagmo's `force_bounds`,
//! extended to the order constraints).

use codesign_core::choice::Choice;
use codesign_core::transmission::DesignSpace;
use serde::{Deserialize, Serialize};
use std::fmt;

/// What becomes of a sample that breaks a bound or an order constraint.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BoundHandling {
    /// Evaluated as drawn: such a design scores the penalty (the paper's rule).
    #[default]
    Penalty,
    /// Replaced by its Euclidean projection onto the design space ([`DesignSpace::project`])
    /// before it is evaluated and logged; CMA-ES keeps its own sample and is told the fitness of
    /// the projected design, as pagmo's `force_bounds` does with the bounds alone.
    Clip,
}

impl Choice for BoundHandling {
    const ALL: &'static [BoundHandling] = &[BoundHandling::Penalty, BoundHandling::Clip];

    fn name(self) -> &'static str {
        match self {
            BoundHandling::Penalty => "penalty",
            BoundHandling::Clip => "clip",
        }
    }
}

impl BoundHandling {
    /// Whether this is the paper's rule (which result files and log headers leave out).
    pub fn is_penalty(&self) -> bool {
        *self == BoundHandling::Penalty
    }

    /// The design evaluated for the sample `x` (dimensionless ratios): `x` itself, or its
    /// projection onto `space`.
    pub fn design(&self, space: &DesignSpace, x: &[f64]) -> Vec<f64> {
        match self {
            BoundHandling::Penalty => x.to_vec(),
            BoundHandling::Clip => space.project(x),
        }
    }

    /// The designs evaluated for the samples `xs`, in their order.
    pub fn designs(&self, space: &DesignSpace, xs: &[Vec<f64>]) -> Vec<Vec<f64>> {
        xs.iter().map(|x| self.design(space, x)).collect()
    }
}

impl fmt::Display for BoundHandling {
    /// The flag's value: `penalty` or `clip`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::BoundHandling;
    use crate::design::cmaes::{Cmaes, CmaesSettings};
    use codesign_core::choice::Choice;
    use codesign_core::transmission::Transmission;

    #[test]
    fn clipped_samples_lie_in_the_design_space() {
        let transmission =
            Transmission::from_spec(&codesign_core::testing::task().transmission).unwrap();
        let space = transmission.design_space();
        let settings = CmaesSettings {
            population: 16,
            generations: 3,
            sigma0: 0.5,
            ..CmaesSettings::default()
        };
        let lower = space.bounds().iter().map(|b| b[0]).collect();
        let upper = space.bounds().iter().map(|b| b[1]).collect();
        let mut es = Cmaes::new(settings, lower, upper).unwrap();
        // Every sample penalised alike, so the run goes on with wide steps.
        es.tell_initial(&[1e6; 16], &[false; 16]).unwrap();
        let (mut outside, mut evaluated) = (0, 0);
        while let Some(samples) = es.ask() {
            let designs = BoundHandling::Clip.designs(space, &samples);
            for (x, design) in samples.iter().zip(&designs) {
                assert!(space.check(design).is_ok(), "{x:?} -> {design:?}");
                if space.check(x).is_err() {
                    outside += 1;
                } else {
                    assert_eq!(x, design, "a design in the space is kept");
                }
                evaluated += 1;
            }
            assert_eq!(BoundHandling::Penalty.designs(space, &samples), samples);
            es.tell(&[1e6; 16], &[false; 16]).unwrap();
        }
        assert_eq!(evaluated, 48);
        assert!(outside > 0, "some samples broke the space");
    }

    #[test]
    fn the_flag_reads_and_prints_alike() {
        for handling in [BoundHandling::Penalty, BoundHandling::Clip] {
            let text = handling.to_string();
            let parsed = BoundHandling::from_name(&text).unwrap();
            assert_eq!(parsed, handling);
            assert_eq!(serde_json::to_value(handling).unwrap(), text.as_str());
        }
        assert!(BoundHandling::default().is_penalty());
    }
}
