//! The settings of a CMA-ES run, their defaults and ranges, and why a run stops.

use codesign_core::input::MAX_RESULT_BYTES;
use codesign_core::model::experiment::Budget;
use codesign_core::text::number;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Settings of one run. Units of x are those of the bounds, units of f those of the fitness.
/// Serialised with their field names, as a run's document records them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CmaesSettings {
    /// lambda: designs per generation and in the initial population (at least 5, as in pagmo).
    pub population: usize,
    /// Generations after the initial population (pagmo's `gen`); 0 stops after the initial one.
    pub generations: usize,
    /// Initial step size relative to the bound widths.
    pub sigma0: f64,
    /// Seed of the random stream.
    pub seed: u64,
    /// Stop when |f_best - f_worst| of the generation evaluated last falls under this.
    pub ftol: f64,
    /// Stop when the step |sigma B D z| of the last sample drawn falls under this.
    pub xtol: f64,
}

impl CmaesSettings {
    /// The paper's run: population 100, 30 generations, sigma0 0.3, seed 0, pagmo's tolerances.
    pub const PAPER: CmaesSettings = CmaesSettings {
        population: Budget::PAPER.population,
        generations: Budget::PAPER.generations,
        sigma0: 0.3,
        seed: 0,
        ftol: 1e-6,
        xtol: 1e-6,
    };
}

impl Default for CmaesSettings {
    /// [`CmaesSettings::PAPER`].
    fn default() -> CmaesSettings {
        CmaesSettings::PAPER
    }
}

/// Most designs per generation: 100 times the paper's 100 (each is a solve, or about 10 with the
/// capacity objective).
pub const MAX_POPULATION: usize = 10_000;

/// Most generations: 1000 times the paper's 30 would take months at the paper's population;
/// this bound only keeps sizes and the log's indices sane.
pub const MAX_GENERATIONS: usize = 30_000;

/// Most evaluations of a run, population times (generations + 1): 1600 times the paper's 3100.
/// The result lists every evaluation's cost (at most 30 bytes each as written) and `table` reads
/// results of at most [`MAX_RESULT_BYTES`]; the evaluation log takes about 300 bytes an
/// evaluation (1.5 GB here).
pub const MAX_EVALUATIONS: usize = 5_000_000;

/// The largest initial step size, relative to the widths of the design box: pagmo's bound.
const MAX_SIGMA0: f64 = 1.0;

/// A setting outside its range.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingError {
    /// The field of [`CmaesSettings`] at fault.
    pub field: &'static str,
    /// Its value, as given.
    pub value: String,
    /// The rule it breaks, with its reason.
    pub rule: String,
}

impl fmt::Display for SettingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.field, self.value, self.rule)
    }
}

impl std::error::Error for SettingError {}

impl CmaesSettings {
    /// The evaluations of a run that goes to its last generation: the initial population and
    /// one population per generation, population x (generations + 1) (saturating).
    pub fn evaluations(&self) -> usize {
        self.population
            .saturating_mul(self.generations.saturating_add(1))
    }

    /// Checks every setting against its range; the error names the first that is outside.
    pub fn validate(&self) -> Result<(), SettingError> {
        let error = |field, value: &dyn fmt::Display, rule: String| {
            Err(SettingError {
                field,
                value: value.to_string(),
                rule,
            })
        };
        if !(5..=MAX_POPULATION).contains(&self.population) {
            return error(
                "population",
                &self.population,
                format!(
                    "must be 5 to {MAX_POPULATION} (CMA-ES ranks at least 5 designs per \
                     generation; {MAX_POPULATION} is 100 times the paper's 100)"
                ),
            );
        }
        if self.generations > MAX_GENERATIONS {
            return error(
                "generations",
                &self.generations,
                format!("must be at most {MAX_GENERATIONS} (1000 times the paper's 30)"),
            );
        }
        let evaluations = self.evaluations();
        if evaluations > MAX_EVALUATIONS {
            return error(
                "generations",
                &self.generations,
                format!(
                    "with population {} that is {evaluations} evaluations (population x \
                     (generations + 1)), but a run may make at most {MAX_EVALUATIONS}: its result \
                     lists every evaluation's cost, and `table` reads results of at most {} MiB",
                    self.population,
                    MAX_RESULT_BYTES >> 20
                ),
            );
        }
        if !(self.sigma0 > 0.0 && self.sigma0 <= MAX_SIGMA0) {
            return error(
                "sigma0",
                &number(self.sigma0),
                format!(
                    "must be a positive number at most {MAX_SIGMA0} (pagmo's range): the first \
                     steps are sigma times the widths of the design box, and wider ones sample \
                     far outside it, up to designs that are no finite number"
                ),
            );
        }
        for (field, value) in [("ftol", self.ftol), ("xtol", self.xtol)] {
            if !(value.is_finite() && value >= 0.0) {
                return error(field, &value, "must be a number >= 0".into());
            }
        }
        Ok(())
    }
}

/// Why a run stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopReason {
    /// All the generations of the settings have been evaluated.
    Generations,
    /// The last sample's step from the mean, `step`, fell under xtol.
    Xtol {
        /// |sigma B D z| of the last sample drawn.
        step: f64,
    },
    /// The fitness spread of the generation evaluated last fell under ftol.
    Ftol {
        /// |f_best - f_worst|.
        spread: f64,
    },
    /// A sample drawn was not finite: the step size or the mean grew past any number.
    Diverged {
        /// The step size sigma then.
        sigma: f64,
    },
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::Generations => f.write_str("generation limit reached"),
            StopReason::Xtol { step } => write!(f, "xtol: step {step:e} under the tolerance"),
            StopReason::Ftol { spread } => {
                write!(f, "ftol: fitness spread {spread:e} under the tolerance")
            }
            StopReason::Diverged { sigma } => write!(
                f,
                "diverged: at step size {sigma:e} the next samples are no finite designs"
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{CmaesSettings, MAX_EVALUATIONS, MAX_GENERATIONS};
    use codesign_core::input::MAX_RESULT_BYTES;

    fn budget(population: usize, generations: usize) -> CmaesSettings {
        CmaesSettings {
            population,
            generations,
            ..CmaesSettings::PAPER
        }
    }

    #[test]
    fn a_budget_whose_result_no_reader_takes_is_refused_naming_both_settings() {
        let error = budget(10_000, 30_000).validate().unwrap_err();
        assert_eq!(error.field, "generations");
        assert!(error.rule.contains("population 10000"), "{error}");
        assert!(error.rule.contains("300010000 evaluations"), "{error}");
        assert!(error.rule.contains("256 MiB"), "{error}");
        budget(5000, 999).validate().unwrap();
        assert_eq!(
            budget(5000, 1000).validate().unwrap_err().field,
            "generations"
        );
        budget(100, 30).validate().unwrap();
    }

    #[test]
    fn the_largest_run_writes_a_result_the_table_reads() {
        // Each cost on a line of its own: 4 spaces, at most 24 characters, ",\n"; each
        // generation's record at most 200 bytes; 1 MiB for the rest (designs, trajectories).
        let bytes = MAX_EVALUATIONS * 30 + (MAX_GENERATIONS + 1) * 200 + (1 << 20);
        assert!((bytes as u64) < MAX_RESULT_BYTES, "{bytes}");
    }
}
