//! Whether the designs of a CMA-ES generation start from a solution of that generation's mean
//! (docs/model.md, section 10) or from the standard initial guess.

use codesign_core::choice::Choice;
use serde::{Deserialize, Serialize};
use std::fmt;

/// How the inner solves of a CMA-ES run start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WarmStart {
    /// Each generation's mean, projected onto the design space, is solved once (per worker);
    /// while it is feasible, every design of the generation starts from its solution, primal
    /// and multipliers, and falls back to the cold rule when that start finds no feasible
    /// trajectory within `solve::WARM_MAX_ITER` iterations (with the graded penalty, an elastic
    /// warm start that converges stands in for the elastic cold start: docs/model.md, section 10). Only the cost objective: a payload
    /// range and a capacity search start cold (the latter warm-starts its own probes).
    #[default]
    On,
    /// Every design from the standard initial guess (the paper's).
    Off,
}

impl Choice for WarmStart {
    const ALL: &'static [WarmStart] = &[WarmStart::On, WarmStart::Off];

    fn name(self) -> &'static str {
        match self {
            WarmStart::On => "on",
            WarmStart::Off => "off",
        }
    }
}

impl WarmStart {
    /// Whether warm starts are on.
    pub fn is_on(&self) -> bool {
        *self == WarmStart::On
    }

    /// Whether warm starts are off (which result files and log headers leave out).
    pub fn is_off(&self) -> bool {
        *self == WarmStart::Off
    }
}

impl fmt::Display for WarmStart {
    /// The flag's value: `on` or `off`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
