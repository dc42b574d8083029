//! How a design that gives no trajectory is scored: the paper's flat penalty, or a penalty
//! graded by how far the design is from giving one, so that CMA-ES can move toward feasibility.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The fitness of an invalid or infeasible design (the paper's flat penalty).
pub const PENALTY: f64 = 1e6;

/// Whether the penalty is the same for every such design or grows with its distance from one
/// that works.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Grading {
    /// Every invalid or infeasible design scores the base (the paper's rule).
    #[default]
    Flat,
    /// An infeasible design scores in [base, 2 base), growing with its deficit from the elastic
    /// problem; an invalid design in [2 base, 3 base), growing with its distance from the design
    /// space. Ranks: feasible < infeasible < invalid, each ordered by how far it is off.
    Graded,
}

impl Grading {
    /// Whether this is the paper's flat rule (which result files leave out).
    pub fn is_flat(&self) -> bool {
        *self == Grading::Flat
    }
}

/// The penalty of a co-design run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Penalty {
    /// The base value, far above every feasible cost.
    pub base: f64,
    /// Flat or graded.
    pub grading: Grading,
}

impl Penalty {
    /// The paper's: 1e6 for every invalid or infeasible design.
    pub const PAPER: Penalty = Penalty {
        base: PENALTY,
        grading: Grading::Flat,
    };

    /// The score of a valid design whose trajectory problem is infeasible, `deficit` (>= 0) its
    /// shortfall: the base, or base (1 + d / (1 + d)) when graded.
    pub fn infeasible(&self, deficit: f64) -> f64 {
        match self.grading {
            Grading::Flat => self.base,
            Grading::Graded => self.base * (1.0 + squash(deficit)),
        }
    }

    /// The score of a design outside the design space (bounds, order constraints), `distance`
    /// its Euclidean distance from it: the base, or base (2 + e / (1 + e)) when graded.
    pub fn invalid(&self, distance: f64) -> f64 {
        match self.grading {
            Grading::Flat => self.base,
            Grading::Graded => self.base * (2.0 + squash(distance)),
        }
    }
}

/// x / (1 + x) for x >= 0: strictly increasing from 0 toward 1 (NaN and negative values count
/// as 0 and infinity as 1).
fn squash(x: f64) -> f64 {
    if x.is_nan() || x <= 0.0 {
        0.0
    } else if x.is_infinite() {
        1.0
    } else {
        x / (1.0 + x)
    }
}

/// A penalty text that is none of `flat`, `graded` or a finite number.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PenaltyError;

impl fmt::Display for PenaltyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("expected flat, graded or a finite number")
    }
}

impl std::error::Error for PenaltyError {}

impl FromStr for Penalty {
    type Err = PenaltyError;

    /// `flat` (the paper's 1e6), `graded`, or a number: a flat penalty of that value.
    fn from_str(text: &str) -> Result<Penalty, PenaltyError> {
        match text {
            "flat" => Ok(Penalty::PAPER),
            "graded" => Ok(Penalty {
                grading: Grading::Graded,
                ..Penalty::PAPER
            }),
            number => match number.parse::<f64>() {
                Ok(base) if base.is_finite() => Ok(Penalty {
                    base,
                    grading: Grading::Flat,
                }),
                _ => Err(PenaltyError),
            },
        }
    }
}

impl fmt::Display for Penalty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.grading, self.base == PENALTY) {
            (Grading::Flat, true) => f.write_str("flat"),
            (Grading::Flat, false) => write!(f, "{}", self.base),
            (Grading::Graded, _) => f.write_str("graded"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Grading, Penalty, PenaltyError, PENALTY};

    #[test]
    fn graded_scores_rank_feasible_infeasible_and_invalid_designs() {
        let graded: Penalty = "graded".parse().unwrap();
        assert_eq!(graded.grading, Grading::Graded);
        assert_eq!(graded.infeasible(0.0), PENALTY);
        assert!(graded.infeasible(0.1) < graded.infeasible(0.2));
        assert!(graded.infeasible(1e12) < graded.invalid(0.0));
        assert!(graded.invalid(0.5) < graded.invalid(1.0));
        assert!(graded.invalid(f64::INFINITY) <= 3.0 * PENALTY);
        let flat: Penalty = "flat".parse().unwrap();
        assert_eq!(flat, Penalty::PAPER);
        assert_eq!(flat.infeasible(5.0), flat.invalid(5.0));
        let value: Penalty = "2e6".parse().unwrap();
        assert_eq!((value.base, value.to_string()), (2e6, "2000000".to_owned()));
        assert_eq!("steep".parse::<Penalty>(), Err(PenaltyError));
        assert!("inf".parse::<Penalty>().is_err());
    }
}
