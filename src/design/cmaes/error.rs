//! Why CMA-ES refused its settings or a call.

use super::settings::SettingError;
use std::fmt;

/// Why CMA-ES refused its settings, its box, or a call out of order.
#[derive(Clone, Debug, PartialEq)]
pub enum CmaesError {
    /// A setting breaks its rule.
    Settings(SettingError),
    /// The box is not finite, not ordered or empty; says which bound.
    Bounds(String),
    /// A call came out of order: what it needs first.
    Order(&'static str),
    /// The run has stopped, for this reason.
    Stopped(String),
    /// A generation's fitness values or feasibility flags are not one per design.
    Length {
        /// The population size.
        expected: usize,
        /// The values given.
        got: usize,
    },
}

impl fmt::Display for CmaesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CmaesError::Settings(error) => write!(f, "CMA-ES: {error}"),
            CmaesError::Bounds(message) => f.write_str(message),
            CmaesError::Order(message) => f.write_str(message),
            CmaesError::Stopped(reason) => write!(f, "the run has stopped ({reason})"),
            CmaesError::Length { expected, got } => {
                write!(f, "expected {expected} values, one per design, got {got}")
            }
        }
    }
}

impl std::error::Error for CmaesError {}
