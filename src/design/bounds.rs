//! How CMA-ES's samples become designs: evaluated as drawn in the box of the bounds, so that a
//! sample outside the design space scores the penalty (the paper's rule); projected onto the
//! space before they are evaluated (pagmo's `force_bounds`, extended to the order constraints);
//! or drawn in the unit box and mapped onto the space, so that every sample is a design.

use codesign_core::choice::Choice;
use codesign_core::transmission::{DesignSpace, UnitMap, UnitMapError};
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
    /// Drawn in the unit box, each coordinate outside [0, 1] folded back by reflection
    /// ([`reflect`]), and mapped onto the design space ([`UnitMap`]), so that every sample is a
    /// design; the design is evaluated and logged, CMA-ES keeps its sample.
    Map,
}

impl Choice for BoundHandling {
    const ALL: &'static [BoundHandling] = &[
        BoundHandling::Penalty,
        BoundHandling::Clip,
        BoundHandling::Map,
    ];

    fn name(self) -> &'static str {
        match self {
            BoundHandling::Penalty => "penalty",
            BoundHandling::Clip => "clip",
            BoundHandling::Map => "map",
        }
    }
}

impl BoundHandling {
    /// Whether this is the paper's rule (which result files and log headers leave out).
    pub fn is_penalty(&self) -> bool {
        *self == BoundHandling::Penalty
    }

    /// What a run under this handling makes of its samples in `space`; fails under `map` when
    /// the space cannot be mapped from the unit box (its order constraints form a cycle).
    pub fn samples(self, space: &DesignSpace) -> Result<SampleDesigns<'_>, UnitMapError> {
        let rule = match self {
            BoundHandling::Penalty => Rule::AsDrawn,
            BoundHandling::Clip => Rule::Projected,
            BoundHandling::Map => Rule::Mapped(UnitMap::new(space)?),
        };
        Ok(SampleDesigns { space, rule })
    }
}

impl fmt::Display for BoundHandling {
    /// The flag's value: `penalty`, `clip` or `map`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The box CMA-ES samples in a run and the design each sample stands for.
#[derive(Clone, Debug)]
pub struct SampleDesigns<'a> {
    space: &'a DesignSpace,
    rule: Rule,
}

/// How a sample becomes a design.
#[derive(Clone, Debug)]
enum Rule {
    /// The sample is the design.
    AsDrawn,
    /// Its projection onto the space.
    Projected,
    /// The image of the sample, reflected into the unit box.
    Mapped(UnitMap),
}

impl SampleDesigns<'_> {
    /// The design space.
    pub fn space(&self) -> &DesignSpace {
        self.space
    }

    /// The lower and upper corners of the box CMA-ES samples: the ratios' bounds, or the unit
    /// box under `map`.
    pub fn search_box(&self) -> (Vec<f64>, Vec<f64>) {
        match self.rule {
            Rule::Mapped(_) => {
                let n = self.space.num_ratios();
                (vec![0.0; n], vec![1.0; n])
            }
            Rule::AsDrawn | Rule::Projected => (
                self.space.bounds().iter().map(|b| b[0]).collect(),
                self.space.bounds().iter().map(|b| b[1]).collect(),
            ),
        }
    }

    /// The design evaluated for the sample `x`: `x` itself (dimensionless ratios), its
    /// projection onto the space, or the image of `x` reflected into the unit box.
    pub fn design(&self, x: &[f64]) -> Vec<f64> {
        match &self.rule {
            Rule::AsDrawn => x.to_vec(),
            Rule::Projected => self.space.project(x),
            Rule::Mapped(map) => map.design(&x.iter().map(|&v| reflect(v)).collect::<Vec<_>>()),
        }
    }

    /// The designs evaluated for the samples `xs`, in their order.
    pub fn designs(&self, xs: &[Vec<f64>]) -> Vec<Vec<f64>> {
        xs.iter().map(|x| self.design(x)).collect()
    }

    /// The design of the search distribution's mean, a design of the space: its design under
    /// `map`, else its projection onto the space.
    pub fn mean_design(&self, mean: &[f64]) -> Vec<f64> {
        match self.rule {
            Rule::Mapped(_) => self.design(mean),
            Rule::AsDrawn | Rule::Projected => self.space.project(mean),
        }
    }
}

/// `x` folded into [0, 1] by reflection at 0 and 1: x itself inside, -x just below 0, 2 - x
/// just above 1, and so on with period 2, so that the fold is continuous.
pub fn reflect(x: f64) -> f64 {
    let t = x.rem_euclid(2.0);
    if t > 1.0 {
        2.0 - t
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::{reflect, BoundHandling};
    use crate::design::cmaes::{Cmaes, CmaesSettings};
    use codesign_core::choice::Choice;
    use codesign_core::transmission::{DesignSpace, Transmission};

    fn belt_arm_space() -> DesignSpace {
        let spec = codesign_core::testing::task().transmission;
        Transmission::from_spec(&spec)
            .unwrap()
            .design_space()
            .clone()
    }

    /// Every (design, sample) pair of a CMA-ES run under `handling` whose designs are all
    /// penalised alike (so that its steps stay wide), its initial population included.
    fn run_designs(handling: BoundHandling, space: &DesignSpace) -> Vec<(Vec<f64>, Vec<f64>)> {
        let samples = handling.samples(space).unwrap();
        let settings = CmaesSettings {
            population: 16,
            generations: 3,
            sigma0: 0.5,
            ..CmaesSettings::default()
        };
        let (lower, upper) = samples.search_box();
        let mut es = Cmaes::new(settings, lower, upper).unwrap();
        let mut pairs: Vec<(Vec<f64>, Vec<f64>)> = (es.initial_population().into_iter())
            .map(|x| (samples.design(&x), x))
            .collect();
        // Every sample penalised alike, so the run goes on with wide steps.
        es.tell_initial(&[1e6; 16], &[false; 16]).unwrap();
        while let Some(xs) = es.ask() {
            let designs = samples.designs(&xs);
            pairs.extend(designs.into_iter().zip(xs));
            es.tell(&[1e6; 16], &[false; 16]).unwrap();
        }
        pairs
    }

    #[test]
    fn clipped_samples_lie_in_the_design_space() {
        let space = belt_arm_space();
        let pairs = run_designs(BoundHandling::Clip, &space);
        let mut outside = 0;
        for (design, x) in &pairs {
            assert!(space.check(design).is_ok(), "{x:?} -> {design:?}");
            if space.check(x).is_err() {
                outside += 1;
            } else {
                assert_eq!(x, design, "a design in the space is kept");
            }
        }
        assert_eq!(pairs.len(), 64);
        assert!(outside > 0, "some samples broke the space");
        let drawn = run_designs(BoundHandling::Penalty, &space);
        assert!(drawn.iter().all(|(design, x)| design == x));
        assert!(drawn.iter().any(|(design, _)| space.check(design).is_err()));
    }

    /// Under `map` every sample, those outside the unit box among them, is a design; the
    /// designs of samples inside the box are the map's images, and the mean's design is one.
    #[test]
    fn mapped_samples_are_designs_of_the_space() {
        let space = belt_arm_space();
        let samples = BoundHandling::Map.samples(&space).unwrap();
        assert_eq!(samples.search_box(), (vec![0.0; 4], vec![1.0; 4]));
        let pairs = run_designs(BoundHandling::Map, &space);
        let outside_box = |x: &[f64]| x.iter().any(|v| !(0.0..=1.0).contains(v));
        assert!(
            pairs.iter().any(|(_, x)| outside_box(x)),
            "wide steps leave the box"
        );
        for (design, x) in &pairs {
            assert!(space.check(design).is_ok(), "{x:?} -> {design:?}");
        }
        let mean = [1.25, -0.25, 0.5, 2.5];
        let folded = [0.75, 0.25, 0.5, 0.5];
        assert_eq!(samples.mean_design(&mean), samples.design(&folded));
        assert!(space.check(&samples.mean_design(&mean)).is_ok());
    }

    #[test]
    fn reflection_folds_the_line_onto_the_unit_interval() {
        for (x, folded) in [
            (0.25, 0.25),
            (1.0, 1.0),
            (0.0, 0.0),
            (1.25, 0.75),
            (-0.25, 0.25),
            (2.5, 0.5),
            (-1.75, 0.25),
            (3.0, 1.0),
        ] {
            assert!((reflect(x) - folded).abs() < 1e-15, "{x} -> {}", reflect(x));
        }
        // Continuous: no jump along a fine sweep of [-3, 3].
        let sweep: Vec<f64> = (-3000..=3000).map(|i| reflect(i as f64 / 1000.0)).collect();
        assert!(sweep.windows(2).all(|w| (w[1] - w[0]).abs() <= 1.0001e-3));
    }

    #[test]
    fn the_flag_reads_and_prints_alike() {
        for &handling in BoundHandling::ALL {
            let text = handling.to_string();
            let parsed = BoundHandling::from_name(&text).unwrap();
            assert_eq!(parsed, handling);
            assert_eq!(serde_json::to_value(handling).unwrap(), text.as_str());
        }
        assert_eq!(BoundHandling::ALL.len(), 3);
        assert!(BoundHandling::default().is_penalty());
    }
}
