//! Payload capacity: the largest payload for which a design's trajectory problem is feasible.
//!
//! The payload is bracketed by doubling from a first step, then bisected to the requested
//! resolution. Every probe is solved under the one rule of feasibility, so its verdict is the
//! one `codesign solve` gives at that payload: the search keeps the rule's payload continuation
//! ([`PayloadChain`]: the design at 0, 1, 2, 4, ... kg, each step warm-started from the one
//! before) between its probes and tries it first, which makes it the search's warm start.
//! Feasibility is assumed to fall monotonically with the payload; the probes are all reported,
//! so a user can see when it does not. The search never
//! goes beyond the largest payload the motors hold at rest at both ends, which is known in
//! closed form ([`Formulation::hold_capacity`]), so no capacity exceeds it.

use crate::model::task::MAX_PAYLOAD_KG;
use crate::problem::{Formulation, FormulationError};
use crate::solve::{
    solve_design_along, PayloadChain, SolveError, SolveSettings, VerdictBy, CONTINUATION_STEP_KG,
};
use serde::{Deserialize, Serialize};
use std::fmt;

/// How finely and how far to search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacitySettings {
    /// Stop bisecting when the bracket is this narrow, kg.
    pub resolution_kg: f64,
    /// The first payload tried after 0 kg; doubled until infeasible, kg (by default the payload
    /// continuation's first step, so that the bracketing climbs its steps).
    pub first_step_kg: f64,
    /// Give up bracketing beyond this payload, kg.
    pub max_kg: f64,
}

impl Default for CapacitySettings {
    /// 10 g resolution, a first step of [`CONTINUATION_STEP_KG`] (1 kg), at most 64 kg.
    fn default() -> CapacitySettings {
        CapacitySettings {
            resolution_kg: 0.01,
            first_step_kg: CONTINUATION_STEP_KG,
            max_kg: 64.0,
        }
    }
}

/// One solve of the search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacityProbe {
    /// The payload tried, kg.
    pub payload_kg: f64,
    /// Whether its trajectory problem was solved.
    pub feasible: bool,
    /// IPOPT's status of the result that gave the verdict.
    pub status: String,
    /// The optimal cost (meaningful when feasible).
    pub cost: f64,
    /// IPOPT iterations, over every solve the rule tried.
    pub iterations: usize,
    /// Wall time of those solves, s.
    pub seconds: f64,
    /// Whether the first solve was warm-started: from the payload continuation's step below
    /// (from the last feasible payload's solution in files written before the continuation),
    /// else from the standard initial guess of docs/model.md, section 6.
    pub warm_start: bool,
    /// Which solve gave the verdict (absent in files written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict_by: Option<VerdictBy>,
}

/// What ends a capacity search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CapacityLimit {
    /// The trajectory problem: the first payload above the capacity has no feasible trajectory.
    Trajectory,
    /// The static hold: the capacity is the largest payload the motors hold at rest at both
    /// ends (no payload at all when they cannot hold the arm unloaded).
    Hold,
    /// The search: `max_kg` was feasible.
    Search,
}

/// The outcome of a capacity search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Capacity {
    /// The largest payload found feasible, kg (None when even 0 kg is infeasible). A lower
    /// bound: every payload up to it that was tried has a feasible trajectory.
    pub capacity_kg: Option<f64>,
    /// The smallest payload above it for which IPOPT found no feasible trajectory from either
    /// start, kg (None when `max_kg` was feasible or the hold bound ended the search).
    pub first_infeasible_kg: Option<f64>,
    /// The largest payload the motors hold at rest at both ends, kg, in closed form (docs/model.md,
    /// section 11); absent when no payload is too heavy to hold, when not even 0 kg is held
    /// (`limited_by` says `hold`), and in files written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold_kg: Option<f64>,
    /// Which bound the capacity hit (absent in files written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limited_by: Option<CapacityLimit>,
    /// Every solve, in order.
    pub probes: Vec<CapacityProbe>,
}

impl CapacitySettings {
    /// Checks that every mass is a positive number of kg.
    pub fn validate(&self) -> Result<(), CapacityError> {
        let valid = |v: f64| v.is_finite() && v > 0.0;
        if valid(self.resolution_kg)
            && self.resolution_kg >= MIN_RESOLUTION_KG
            && valid(self.first_step_kg)
            && valid(self.max_kg)
        {
            return Ok(());
        }
        Err(CapacityError::Settings(*self))
    }
}

/// Checks a mass of a search's settings given by the user (its largest payload, its first step):
/// a positive number of kg, at most the heaviest payload a task may carry. The rule broken, in
/// words, when it is not.
pub fn check_search_mass(kg: f64) -> Result<(), String> {
    if kg.is_finite() && kg > 0.0 && kg <= MAX_PAYLOAD_KG {
        return Ok(());
    }
    Err(format!(
        "must be a mass > 0 and <= {MAX_PAYLOAD_KG} kg (the heaviest payload a task may carry)"
    ))
}

/// The finest resolution of a capacity search, kg: 1 mg, below what any scale or gripper
/// resolves; bisecting the largest payload a task may carry (1000 kg) to it takes 30 probes.
pub const MIN_RESOLUTION_KG: f64 = 1e-6;

/// Why a capacity search could not run.
#[derive(Clone, Debug, PartialEq)]
pub enum CapacityError {
    /// A mass of the settings is not a positive number of kg.
    Settings(CapacitySettings),
    /// The problem could not be formulated at a payload.
    Payload(FormulationError),
    /// A probe could not be solved (an invalid design, IPOPT could not run).
    Solve(SolveError),
}

impl fmt::Display for CapacityError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CapacityError::Settings(settings) => write!(
                f,
                "capacity settings must be positive numbers of kg, the resolution at least \
                 {MIN_RESOLUTION_KG} kg: resolution {}, first step {}, max {}",
                settings.resolution_kg, settings.first_step_kg, settings.max_kg
            ),
            CapacityError::Payload(error) => error.fmt(f),
            CapacityError::Solve(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for CapacityError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CapacityError::Settings(_) => None,
            CapacityError::Payload(error) => Some(error),
            CapacityError::Solve(error) => Some(error),
        }
    }
}

impl From<FormulationError> for CapacityError {
    fn from(error: FormulationError) -> CapacityError {
        CapacityError::Payload(error)
    }
}

impl From<SolveError> for CapacityError {
    fn from(error: SolveError) -> CapacityError {
        CapacityError::Solve(error)
    }
}

/// The solves of one search: a design at varying payloads, every probe recorded.
struct Search<'a> {
    formulation: &'a Formulation,
    solve: &'a SolveSettings,
    ratios: &'a [f64],
    chain: PayloadChain,
    probes: Vec<CapacityProbe>,
}

impl Search<'_> {
    /// Whether the design is feasible at `payload` under the one rule of feasibility
    /// (`solve::solve_design_along`): IPOPT's verdict of infeasibility is local (the problem is
    /// not convex), so a payload counts as infeasible only when no start leads to a feasible
    /// trajectory.
    fn probe(&mut self, payload: f64) -> Result<bool, CapacityError> {
        let formulation = self.formulation.with_payload(payload)?;
        let warm = self.chain.ready_below(&formulation, self.ratios);
        let (result, _) =
            solve_design_along(&formulation, self.ratios, self.solve, &mut self.chain)?;
        self.probes.push(CapacityProbe {
            payload_kg: payload,
            feasible: result.feasible,
            status: result.status,
            cost: result.cost,
            iterations: result.iterations,
            seconds: result.solve_seconds.total,
            warm_start: warm,
            verdict_by: result.verdict_by,
        });
        Ok(result.feasible)
    }
}

/// Searches the payload capacity of design `ratios` in `formulation` (its payload ignored),
/// each probe solved with `solve`, up to `max_kg`, and, where the task's ends judge the hold,
/// up to the payload the motors hold at rest (always reported, `hold_kg`).
pub fn payload_capacity(
    formulation: &Formulation,
    solve: &SolveSettings,
    ratios: &[f64],
    settings: &CapacitySettings,
) -> Result<Capacity, CapacityError> {
    settings.validate()?;
    let hold = formulation
        .hold_capacity(ratios)
        .map_err(SolveError::Design)?;
    let mut capacity = Capacity {
        capacity_kg: None,
        first_infeasible_kg: Some(0.0),
        hold_kg: hold.filter(|kg| kg.is_finite()),
        limited_by: Some(CapacityLimit::Hold),
        probes: Vec::new(),
    };
    // Under the paper's ends the hold is reported and bounds nothing.
    let judged = formulation.task().motion.ends.judges_hold();
    let top = match hold {
        None if judged => return Ok(capacity),
        Some(hold) if judged => settings.max_kg.min(hold),
        _ => settings.max_kg,
    };
    let mut search = Search {
        formulation,
        solve,
        ratios,
        chain: PayloadChain::new(),
        probes: Vec::new(),
    };
    let (low, high) = bracket(&mut search, top, settings)?;
    capacity.probes = search.probes;
    capacity.capacity_kg = low;
    capacity.first_infeasible_kg = high;
    capacity.limited_by = Some(match (low, high) {
        (None, _) | (_, Some(_)) => CapacityLimit::Trajectory,
        (Some(_), None) if top < settings.max_kg => CapacityLimit::Hold,
        (Some(_), None) => CapacityLimit::Search,
    });
    Ok(capacity)
}

/// The bracketing and bisection of `search` up to `top` kg: the largest feasible payload (None
/// when 0 kg is infeasible) and the first infeasible one above it (None when `top` is feasible).
fn bracket(
    search: &mut Search<'_>,
    top: f64,
    settings: &CapacitySettings,
) -> Result<(Option<f64>, Option<f64>), CapacityError> {
    if !search.probe(0.0)? {
        return Ok((None, Some(0.0)));
    }
    // Bracketing: double the payload until it is infeasible or the largest allowed.
    let (mut low, mut high) = (0.0, None);
    let mut payload = settings.first_step_kg.min(top);
    while high.is_none() && low < top {
        if search.probe(payload)? {
            low = payload;
            payload = (2.0 * payload).min(top);
        } else {
            high = Some(payload);
        }
    }
    // Bisection of the bracket down to the resolution.
    if let Some(mut upper) = high {
        while upper - low > settings.resolution_kg {
            let middle = 0.5 * (low + upper);
            // Adjacent floats: no payload lies between them (a resolution below their spacing).
            if !(low < middle && middle < upper) {
                break;
            }
            if search.probe(middle)? {
                low = middle;
            } else {
                upper = middle;
            }
        }
        high = Some(upper);
    }
    Ok((Some(low), high))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Space;
    use crate::testing;

    /// The searches' settings: 0.05 kg resolution, a first step of 1 kg, up to 16 kg.
    fn settings() -> CapacitySettings {
        CapacitySettings {
            resolution_kg: 0.05,
            first_step_kg: 1.0,
            max_kg: 16.0,
        }
    }

    /// The original design's motors hold at most 0.585 kg at rest: its capacity is that
    /// bound, reached without a search above it (it moves 1.9 kg without the hold). Bad
    /// settings are refused.
    #[test]
    fn the_hold_bounds_the_capacity_of_the_original_design() {
        let formulation = testing::held_formulation(0.0, Space::Actuation);
        let settings = settings();
        let original = formulation.transmission().original().to_vec();
        let capacity =
            payload_capacity(&formulation, &testing::settings(), &original, &settings).unwrap();
        let hold = capacity.hold_kg.unwrap();
        assert!((0.58..0.59).contains(&hold), "{capacity:?}");
        assert_eq!(capacity.capacity_kg, Some(hold));
        assert_eq!(capacity.first_infeasible_kg, None);
        assert_eq!(capacity.limited_by, Some(CapacityLimit::Hold));
        assert!(capacity.probes.iter().all(|p| p.payload_kg <= hold));
        let bad = CapacitySettings {
            resolution_kg: 0.0,
            ..settings
        };
        let error = payload_capacity(&formulation, &testing::settings(), &original, &bad);
        assert_eq!(error, Err(CapacityError::Settings(bad)));
        assert!(error
            .unwrap_err()
            .to_string()
            .starts_with("capacity settings must be positive numbers of kg, the resolution at least 0.000001 kg: resolution 0,"));
    }

    /// Under the paper's ends the hold bounds nothing: the original design's capacity is the
    /// dynamic one, above the load held at rest, which is reported the same.
    #[test]
    fn under_the_papers_ends_the_trajectory_bounds_the_capacity() {
        let original = testing::task().transmission.original;
        let paper = testing::formulation(0.0, Space::Actuation);
        let dynamic =
            payload_capacity(&paper, &testing::settings(), &original, &settings()).unwrap();
        let held = testing::held_formulation(0.0, Space::Actuation);
        assert_eq!(dynamic.hold_kg, held.hold_capacity(&original).unwrap());
        assert_eq!(dynamic.limited_by, Some(CapacityLimit::Trajectory));
        assert!(
            dynamic.capacity_kg.is_some_and(|kg| kg > 1.0),
            "{dynamic:?}"
        );
    }

    /// A design that holds 3.19 kg: the trajectory bounds its capacity, bracketed to the
    /// resolution between 1 and 3 kg, and `solve` gives the probes' verdicts at the capacity
    /// and just above it. On 20 intervals rather than 50: the search's probes near the
    /// capacity are the slow solves, and the smaller problem makes them sooner.
    #[test]
    fn brackets_a_trajectory_bounded_capacity_to_the_resolution() {
        let mut task = testing::held_task();
        task.payload.mass_kg = 0.0;
        task.motion.steps = 20;
        let robot = crate::model::Robot::load(&task).unwrap();
        let formulation =
            crate::problem::Formulation::new(&task, robot, Space::Actuation, task.limit_modes)
                .unwrap();
        let settings = settings();
        let held = [9.0, 8.99, 3.0, 3.0];
        let capacity =
            payload_capacity(&formulation, &testing::settings(), &held, &settings).unwrap();
        let (low, high) = (
            capacity.capacity_kg.unwrap(),
            capacity.first_infeasible_kg.unwrap(),
        );
        assert!(capacity.hold_kg.is_some_and(|kg| kg > 3.0), "{capacity:?}");
        assert_eq!(capacity.limited_by, Some(CapacityLimit::Trajectory));
        assert!((1.0..3.0).contains(&low), "{capacity:?}");
        assert!(high > low && high - low <= 0.05, "{capacity:?}");
        for probe in &capacity.probes {
            assert!(!probe.feasible || probe.payload_kg <= low, "{probe:?}");
            if probe.payload_kg <= low {
                // Every payload up to the capacity was solved by one of the starts.
                assert!(capacity
                    .probes
                    .iter()
                    .any(|p| p.payload_kg == probe.payload_kg && p.feasible));
            }
        }
        for (payload, feasible) in [(low, true), (high, false)] {
            let at = formulation.with_payload(payload).unwrap();
            let result = crate::solve::solve_design(&at, &held, &testing::settings()).unwrap();
            assert_eq!(result.feasible, feasible, "{payload} kg: {result:?}");
        }
    }
}
