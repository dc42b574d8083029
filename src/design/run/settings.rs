//! The settings of a co-design run, each written once: [`RunSettings`], what decides its result
//! and what its document and log header record (flattened into `OptimizeInputs`), and
//! [`Execution`], how its evaluations run, which changes no result. Every check of them is
//! here, and its [`CaseError`] names the setting by its key in the document; the command line
//! words it as a flag, Python as a keyword.

use crate::design::bounds::BoundHandling;
use crate::design::cmaes::CmaesSettings;
use crate::design::penalty::{Grading, Penalty, PENALTY};
use crate::design::score::{Objective, PayloadRange};
use crate::design::warm::WarmStart;
use crate::design::workers::SOLVE_TIMEOUT_S;
use crate::store::log::Start;
use codesign_core::choice::Choice;
use codesign_core::model::task::{check_payload, Task};
use codesign_core::text::number;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::fmt;

/// The outer-level method of a co-design run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// CMA-ES as in pagmo (the paper's method), designs evaluated by worker processes.
    #[default]
    Cmaes,
    /// Projected quasi-Newton with the exact sensitivity dJ*/dr, warm-started inner solves.
    Gradient,
}

impl Choice for Method {
    const ALL: &'static [Method] = &[Method::Cmaes, Method::Gradient];

    fn name(self) -> &'static str {
        match self {
            Method::Cmaes => "cmaes",
            Method::Gradient => "gradient",
        }
    }
}

/// The settings that decide a co-design run's result, as its document records them (their
/// keys are the document's). Two runs with equal settings, problem and task give equal results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSettings {
    /// The outer-level method.
    pub method: Method,
    /// What is minimised.
    pub objective: Objective,
    /// CMA-ES's settings (`seed`, `population`, `generations`, `sigma0`, `ftol`, `xtol`); a
    /// gradient run records them too (`reproduce`'s with population and generations 0).
    #[serde(flatten)]
    pub cmaes: CmaesSettings,
    /// Fitness of invalid or infeasible designs (the base of a graded penalty).
    pub penalty: f64,
    /// Whether the penalty is graded by the distance from feasibility; flat (the paper's) when
    /// left out.
    #[serde(default, skip_serializing_if = "Grading::is_flat")]
    pub grading: Grading,
    /// Whether CMA-ES's samples outside the design space were projected onto it before they
    /// were evaluated (`clip`), or drawn in the unit box and mapped onto it (`map`); penalised
    /// as drawn (the paper's rule) when left out.
    #[serde(default, skip_serializing_if = "BoundHandling::is_penalty")]
    pub bounds: BoundHandling,
    /// Whether each generation's designs started from a solution of its mean; always written.
    pub warm_start: WarmStart,
}

impl RunSettings {
    /// A run of `method` with every setting at its default: the paper's CMA-ES settings and
    /// flat penalty, samples penalised as drawn, warm starts on (CMA-ES).
    pub fn new(method: Method) -> RunSettings {
        RunSettings {
            method,
            objective: Objective::Cost,
            cmaes: CmaesSettings::default(),
            penalty: PENALTY,
            grading: Grading::Flat,
            bounds: BoundHandling::Penalty,
            warm_start: WarmStart::default(),
        }
    }

    /// The penalty.
    pub fn penalty(&self) -> Penalty {
        Penalty {
            base: self.penalty,
            grading: self.grading,
        }
    }

    /// Sets the penalty.
    pub fn set_penalty(&mut self, penalty: Penalty) {
        self.penalty = penalty.base;
        self.grading = penalty.grading;
    }

    /// The settings as the run records them: a gradient run has no warm starts of CMA-ES.
    pub fn recorded(&self) -> RunSettings {
        let mut recorded = self.clone();
        if self.method == Method::Gradient {
            recorded.warm_start = WarmStart::Off;
        }
        recorded
    }

    /// The settings as JSON, keyed as the document records them.
    pub fn to_map(&self) -> Map<String, Value> {
        match serde_json::to_value(self) {
            Ok(Value::Object(map)) => map,
            // A struct of plain fields serialises to an object.
            _ => Map::new(),
        }
    }

    /// The settings in which `recorded` (those of a run's document or log header) differ from
    /// these, as `key: recorded X, planned Y`, compared key by key as the document writes them.
    pub fn differences(&self, recorded: &RunSettings) -> Vec<String> {
        let (planned, recorded) = (self.recorded().to_map(), recorded.to_map());
        let mut keys: Vec<&String> = planned.keys().chain(recorded.keys()).collect();
        keys.sort();
        keys.dedup();
        keys.into_iter()
            .filter_map(|key| {
                let (was, is) = (recorded.get(key), planned.get(key));
                (was != is).then(|| format!("{key}: recorded {}, planned {}", text(was), text(is)))
            })
            .collect()
    }

    /// Checks every setting and their combinations; `payload` is the case's own payload, kg.
    pub fn validate(&self, payload: Option<f64>, start: Start) -> Result<(), CaseError> {
        if self.method == Method::Cmaes {
            // The gradient method has no population or generations (reproduce records 0).
            self.cmaes
                .validate()
                .map_err(|e| CaseError::new(e.field, e.value, e.rule))?;
        }
        if self.grading == Grading::Graded && matches!(self.objective, Objective::Capacity(_)) {
            return Err(CaseError::new(
                "grading",
                "graded",
                "the capacity search has no elastic form; use the cost or range objective",
            ));
        }
        if self.grading == Grading::Graded && self.objective == Objective::Energy {
            return Err(CaseError::new(
                "grading",
                "graded",
                "the elastic problem's weights are set above the multipliers of J, not of the \
                 copper losses; use the flat penalty with the energy objective",
            ));
        }
        if self.method == Method::Gradient && !self.bounds.is_penalty() {
            return Err(CaseError::new(
                "bounds",
                self.bounds,
                "the gradient method is a projected method: it keeps its iterates in the design \
                 space (bounds and order constraints) itself; only CMA-ES projects or maps its \
                 samples",
            ));
        }
        self.check_objective(payload, start)
    }

    /// Checks what the objective asks of `task`: the capacity and range objectives are of one
    /// motion (a payload capacity, a mean over payloads of one motion), so a task with a
    /// `motions` list is co-designed with the cost, energy or time objective only.
    pub fn check_task(&self, task: &Task) -> Result<(), CaseError> {
        let name = match &self.objective {
            Objective::Capacity(_) => "capacity",
            Objective::Range(_) => "range",
            Objective::Cost | Objective::Energy | Objective::Time => return Ok(()),
        };
        if !task.has_motions() {
            return Ok(());
        }
        let what = match name {
            "capacity" => "a payload capacity is the heaviest payload of one motion",
            _ => "a payload range is one motion's cost averaged over payloads",
        };
        Err(CaseError::new(
            "objective",
            name,
            format!(
                "{what}, and the task lists {} motions (`motions`); co-design them with the cost, \
                 energy or time objective (each motion may give its own payload_kg)",
                task.motions.len()
            ),
        ))
    }

    /// Checks what the objective asks of the method, the payload and the start.
    fn check_objective(&self, payload: Option<f64>, start: Start) -> Result<(), CaseError> {
        let gradient = self.method == Method::Gradient;
        match &self.objective {
            Objective::Capacity(_) if gradient => Err(CaseError::new(
                "objective",
                "capacity",
                "the capacity is not differentiable in r; use the method cmaes",
            )),
            Objective::Range(_) if gradient => Err(CaseError::new(
                "objective",
                "range",
                "the gradient method descends one payload's cost; use the method cmaes",
            )),
            Objective::Range(range) => check_range(range, payload),
            _ if gradient && start == Start::Resume => Err(CaseError::new(
                "start",
                "resume",
                "only CMA-ES runs are resumed; a gradient run is short, start it again",
            )),
            Objective::Capacity(search) => search
                .validate()
                .map_err(|e| CaseError::new(e.key, number(e.value), e.rule())),
            _ => Ok(()),
        }
    }
}

/// Checks the payloads of a range: at least one, each a valid payload, and no case payload.
fn check_range(range: &PayloadRange, payload: Option<f64>) -> Result<(), CaseError> {
    if let Some(payload) = payload {
        return Err(CaseError::new(
            "payload_kg",
            number(payload),
            "the range objective solves every payload of its range; leave the payload out",
        ));
    }
    if range.payloads_kg.is_empty() {
        return Err(CaseError::new(
            "payloads_kg",
            "[]",
            "the range objective needs at least one payload",
        ));
    }
    for &payload in &range.payloads_kg {
        check_payload(payload)
            .map_err(|why| CaseError::new("payloads_kg", number(payload), why.to_string()))?;
    }
    Ok(())
}

/// A JSON value in words: strings unquoted; a value the document leaves out (a setting at the
/// default it leaves out) as `left out`.
fn text(value: Option<&Value>) -> String {
    match value {
        None => "left out".to_owned(),
        Some(Value::String(text)) => text.clone(),
        Some(value) => value.to_string(),
    }
}

/// The longest solve timeout, s: a week, beyond any solve of a task (the largest problem
/// allowed solves in minutes).
pub const MAX_SOLVE_TIMEOUT_S: f64 = 604_800.0;

/// The shortest solve timeout, s: a worker process must start, load its task and say hello
/// within it, which takes a fraction of a second.
pub const MIN_SOLVE_TIMEOUT_S: f64 = 1.0;

/// How a run's evaluations run: nothing here changes its result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Execution {
    /// Worker processes of CMA-ES; threads of the gradient method's candidate starts and
    /// descents (its worker processes with a worker command) and of an experiment's capacity
    /// searches (None: one per core).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub workers: Option<usize>,
    /// A solve taking longer than this counts as a hung worker, s.
    pub solve_timeout_s: f64,
    /// The shell command that starts one worker, `{}` standing for this binary's path (None:
    /// this binary's `worker`, started directly).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worker_command: Option<String>,
    /// Fresh start, resumption of its evaluation log, or replacement of it.
    pub start: Start,
}

impl Default for Execution {
    /// One worker per core, started directly, the default timeout, a fresh start.
    fn default() -> Execution {
        Execution {
            workers: None,
            solve_timeout_s: SOLVE_TIMEOUT_S,
            worker_command: None,
            start: Start::Fresh,
        }
    }
}

impl Execution {
    /// Checks the worker count, the timeout and the worker command.
    pub fn validate(&self) -> Result<(), CaseError> {
        let timeout = self.solve_timeout_s;
        if !(timeout.is_finite() && (MIN_SOLVE_TIMEOUT_S..=MAX_SOLVE_TIMEOUT_S).contains(&timeout))
        {
            return Err(CaseError::new(
                "solve_timeout_s",
                number(timeout),
                format!(
                    "must be {MIN_SOLVE_TIMEOUT_S} to {MAX_SOLVE_TIMEOUT_S} seconds (a worker \
                     needs about a second to start and say hello; no solve of a task takes a \
                     week)"
                ),
            ));
        }
        if self.workers == Some(0) {
            return Err(CaseError::new("workers", 0, "must be at least 1"));
        }
        if (self.worker_command.as_ref()).is_some_and(|line| line.trim().is_empty()) {
            return Err(CaseError::new(
                "worker_command",
                "''",
                "must be a shell command, e.g. \"{} worker\"",
            ));
        }
        Ok(())
    }
}

/// A setting of a case out of its range, or at odds with another.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseError {
    /// The setting at fault, by its key in the document ([`RunSettings`], [`Execution`],
    /// `payload_kg`, or a key of the objective).
    pub key: &'static str,
    /// Its value, in words.
    pub value: String,
    /// The rule it breaks, with its reason.
    pub rule: String,
}

impl CaseError {
    /// The error of `key` at `value`, breaking `rule`.
    pub fn new(key: &'static str, value: impl fmt::Display, rule: impl Into<String>) -> CaseError {
        CaseError {
            key,
            value: value.to_string(),
            rule: rule.into(),
        }
    }
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.key, self.value, self.rule)
    }
}

impl std::error::Error for CaseError {}
