//! What the motion asks at its two ends (docs/model.md, section 6): the task's `motion.ends`.
//!
//! Every formulation fixes q and v at nodes 0 and N. Beyond that the paper asks nothing; holding
//! the load at rest there is a physical refinement, a named choice beside it.

use crate::choice::Choice;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The conditions at the start and the goal of the motion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Ends {
    /// q and v fixed at nodes 0 and N, nothing else: the paper's formulation. The static hold
    /// is reported, never judged.
    Paper,
    /// As `paper`, and the static torques at both ends lie within the problem's control limits
    /// (the motors hold the load at rest there). A task file without `motion.ends` means this.
    #[default]
    Hold,
    /// As `hold`, and zero joint acceleration at nodes 0 and N-1: the motion starts and ends
    /// at rest.
    Rest,
}

impl Choice for Ends {
    const ALL: &'static [Ends] = &[Ends::Paper, Ends::Hold, Ends::Rest];

    fn name(self) -> &'static str {
        Ends::name(self)
    }
}

impl Ends {
    /// Whether the static hold at both ends is a condition of feasibility.
    pub fn judges_hold(self) -> bool {
        self != Ends::Paper
    }

    /// Whether the accelerations at nodes 0 and N-1 are fixed at zero.
    pub fn rests(self) -> bool {
        self == Ends::Rest
    }

    /// `paper`, `hold` or `rest`, as the task file and `--ends` spell it.
    pub fn name(self) -> &'static str {
        match self {
            Ends::Paper => "paper",
            Ends::Hold => "hold",
            Ends::Rest => "rest",
        }
    }
}

impl fmt::Display for Ends {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::Ends;

    #[test]
    fn the_hold_is_judged_under_hold_and_rest_and_rest_alone_rests() {
        assert!(Ends::Hold.judges_hold() && Ends::Rest.judges_hold());
        assert!(!Ends::Paper.judges_hold());
        assert!(Ends::Rest.rests() && !Ends::Hold.rests());
    }
}
