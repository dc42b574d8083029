//! [`FormulationError`]: why a formulation cannot be built.

use std::fmt;

/// A formulation that cannot be built; the message names the field at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct FormulationError(pub String);

impl fmt::Display for FormulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FormulationError {}
