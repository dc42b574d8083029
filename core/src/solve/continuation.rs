//! The payload continuation, the last start of the one rule (docs/model.md, section 8): the
//! design is solved unloaded, then carried up the payloads 0, s, 2s, 4s, ... kg below the
//! payload asked for, each solve warm-started from the one before, and finally at that payload.
//!
//! A heavy payload moves the optimum far from the standard initial guess, and IPOPT can call a
//! design infeasible from there that it solves when the load is added step by step. A capacity
//! search climbs the same steps, so it keeps its [`PayloadChain`] between probes and every probe
//! reaches the verdict `solve` reaches at that payload, from the same solves.

use super::run::{capped, Start, Tries};
use super::settings::SolveSettings;
use super::SolveError;
use crate::ipopt::Solution;
use crate::problem::Formulation;

/// The first step s of the payload continuation, kg: the steps are 0, s, 2s, 4s, ... kg (a
/// capacity search brackets the payload along the same steps by default).
pub const CONTINUATION_STEP_KG: f64 = 1.0;

/// One step of the chain: the hard solution at its payload, or none when the step found no
/// feasible trajectory (the chain ends there).
#[derive(Clone, Debug)]
struct Step {
    payload_kg: f64,
    solution: Option<Solution>,
}

/// The solutions of one design along the continuation's payloads, kept so that solves of that
/// design at several payloads (a capacity search) compute each step once. The step at 0 kg is
/// the rule's solve of the unloaded arm; each later step is the hard problem warm-started from
/// the step before, capped at [`super::WARM_MAX_ITER`] iterations. The chain belongs to one
/// design of one formulation (up to its payload) and one set of settings: solving another design
/// with it starts it afresh.
#[derive(Clone, Debug, Default)]
pub struct PayloadChain {
    ratios: Vec<f64>,
    steps: Vec<Step>,
}

impl PayloadChain {
    /// An empty chain.
    pub fn new() -> PayloadChain {
        PayloadChain::default()
    }

    /// The payloads of the continuation below `payload_kg` (none at or below 0 kg), kg.
    pub fn payloads_below(payload_kg: f64) -> Vec<f64> {
        (0..)
            .map(step_payload)
            .take_while(|&payload| payload < payload_kg)
            .collect()
    }

    /// The solution of the last step below the hard formulation's payload, computing the steps
    /// this chain lacks (their work counted in `tries`; the step at 0 kg by `unloaded`, the
    /// rule's solve of the formulation it is given, feasible or none), or none when a step found
    /// no feasible trajectory or the payload is 0 kg.
    pub(super) fn last_below(
        &mut self,
        hard: &Formulation,
        ratios: &[f64],
        settings: &SolveSettings,
        tries: &mut Tries,
        unloaded: impl FnOnce(&Formulation, &mut Tries) -> Result<Option<Solution>, SolveError>,
    ) -> Result<Option<&Solution>, SolveError> {
        if self.ratios != ratios {
            (self.ratios, self.steps) = (ratios.to_vec(), Vec::new());
        }
        let payloads = PayloadChain::payloads_below(hard.task().payload.mass_kg);
        if payloads.is_empty() {
            return Ok(None);
        }
        if self.steps.is_empty() {
            let solution = unloaded(&hard.with_payload(0.0)?, tries)?;
            self.steps.push(Step {
                payload_kg: 0.0,
                solution,
            });
        }
        for (index, &payload_kg) in payloads.iter().enumerate().skip(1) {
            if index < self.steps.len() {
                debug_assert_eq!(self.steps[index].payload_kg, payload_kg);
                continue;
            }
            let Some(before) = &self.steps[index - 1].solution else {
                return Ok(None);
            };
            let at = hard.with_payload(payload_kg)?;
            let (result, solution) =
                tries.solve(&at, ratios, &capped(settings), Start::Warm(before))?;
            self.steps.push(Step {
                payload_kg,
                solution: result.feasible.then_some(solution),
            });
        }
        Ok(self.steps[..payloads.len()]
            .iter()
            .all(|step| step.solution.is_some())
            .then(|| self.steps[payloads.len() - 1].solution.as_ref())
            .flatten())
    }

    /// Whether the chain of design `ratios` holds a solution at every step below the
    /// formulation's payload (above 0 kg), so that the continuation costs one warm-started solve.
    pub fn ready_below(&self, formulation: &Formulation, ratios: &[f64]) -> bool {
        let below = PayloadChain::payloads_below(formulation.task().payload.mass_kg).len();
        below > 0
            && self.ratios == ratios
            && self.steps.len() >= below
            && self.steps[..below]
                .iter()
                .all(|step| step.solution.is_some())
    }

    /// Keeps the hard solution `found` at the formulation's payload (none: no feasible
    /// trajectory) as the chain's next step, when that payload is the next step and `found` is
    /// what the step computes: the rule's solution at 0 kg, or the solve warm-started from the
    /// step before.
    pub(super) fn record(&mut self, hard: &Formulation, ratios: &[f64], found: Option<&Solution>) {
        if self.ratios != ratios {
            (self.ratios, self.steps) = (ratios.to_vec(), Vec::new());
        }
        let payload_kg = hard.task().payload.mass_kg;
        let continues = self.steps.last().is_none_or(|step| step.solution.is_some());
        if continues && step_payload(self.steps.len()) == payload_kg {
            self.steps.push(Step {
                payload_kg,
                solution: found.cloned(),
            });
        }
    }
}

/// The payload of step `index` of the chain: 0, s, 2s, 4s, ... kg.
fn step_payload(index: usize) -> f64 {
    match index {
        0 => 0.0,
        _ => CONTINUATION_STEP_KG * 2f64.powi(index as i32 - 1),
    }
}
