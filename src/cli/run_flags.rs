//! The run settings as flags, both ways: the flags `optimize` and `reproduce` share, parsed
//! into a case's [`RunSettings`] and [`Execution`]; the flags of `optimize` that pose a case,
//! derived from the case as its document records it (`reproduce --plan`); and a case's errors
//! worded with the flag that sets the value. A setting's flag is `--` and its key, `_` written
//! `-`, unless [`RENAMED`] says otherwise.

use super::failure::Failure;
use crate::cli::choice::choice;
use crate::design::bounds::BoundHandling;
use crate::design::run::{shell_quote, Case, CaseError, Execution, Method, RunSettings};
use crate::design::warm::WarmStart;
use crate::design::workers::SOLVE_TIMEOUT_S;
use crate::store::log::Start;
use codesign_core::model::task::TaskSource;
use serde_json::{Map, Value};

/// The flags of CMA-ES runs and their workers that `optimize` and `reproduce` share.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// What CMA-ES does with a sample outside the design space (bounds, order constraints):
    /// `penalty` evaluates it as drawn, so it scores the penalty (the paper's rule); `clip`
    /// evaluates and logs its Euclidean projection onto the space instead (pagmo's force_bounds);
    /// `map` draws the samples in the unit box and maps each onto the space, so that every
    /// sample is a design (docs/model.md, section 4). CMA-ES only: the gradient method keeps its
    /// iterates in the space itself.
    #[arg(long, value_parser = choice::<BoundHandling>(), default_value_t = BoundHandling::Penalty)]
    pub bounds: BoundHandling,
    /// Whether CMA-ES starts the designs of each generation from a solution of the generation's
    /// mean (cost objective only), falling back to the standard guess where that fails; `off`
    /// starts every design from the standard guess (the paper's).
    #[arg(long, value_parser = choice::<WarmStart>(), default_value_t = WarmStart::default())]
    pub warm_start: WarmStart,
    #[command(flatten)]
    pub execution: ExecutionArgs,
}

/// The flags of how a run's evaluations run, which change no result: `optimize`, `reproduce`
/// and `parts` share them.
#[derive(Debug, Clone, clap::Args)]
pub struct ExecutionArgs {
    /// Worker processes of CMA-ES; threads of the gradient method's candidate starts and
    /// descents (its worker processes with --worker-command) and of `reproduce`'s capacity
    /// searches (default: one per core).
    #[arg(long, value_name = "N")]
    pub workers: Option<usize>,
    /// A solve taking longer than this (s) counts as a hung worker.
    #[arg(long, value_name = "S", default_value_t = SOLVE_TIMEOUT_S)]
    pub solve_timeout: f64,
    /// Shell command that starts one worker speaking the worker protocol on stdin/stdout; `{}`
    /// stands for this binary's path, e.g. "srun --ntasks=1 --exclusive {} worker" inside a
    /// Slurm allocation or "ssh node7 codesign worker" [default: this binary's `worker`].
    #[arg(long, value_name = "CMD")]
    pub worker_command: Option<String>,
}

impl ExecutionArgs {
    /// How the evaluations run, with `start`.
    pub fn execution(&self, start: Start) -> Execution {
        Execution {
            workers: self.workers,
            solve_timeout_s: self.solve_timeout,
            worker_command: self.worker_command.clone(),
            start,
        }
    }
}

impl RunArgs {
    /// Sets the CMA-ES settings these flags give.
    pub fn apply(&self, settings: &mut RunSettings) {
        settings.bounds = self.bounds;
        settings.warm_start = self.warm_start;
    }

    /// How the evaluations run, with `start`.
    pub fn execution(&self, start: Start) -> Execution {
        self.execution.execution(start)
    }
}

/// The keys whose flag is not their own name, with it; "" for a key that has no flag (it keeps
/// its default, or another flag says it).
const RENAMED: [(&str, &str); 10] = [
    ("sigma0", "sigma"),
    ("ftol", ""),
    ("xtol", ""),
    // `--penalty graded` says the grading with the base.
    ("grading", ""),
    ("solve_timeout_s", "solve-timeout"),
    ("payload_kg", "payload"),
    ("payloads_kg", "payloads"),
    ("resolution_kg", "capacity-resolution"),
    ("first_step_kg", ""),
    ("max_kg", "max"),
];

/// The flag of a setting's key (without `--`); None for a key that has none.
pub fn flag_of(key: &str) -> Option<String> {
    match RENAMED.iter().find(|(renamed, _)| *renamed == key) {
        Some((_, "")) => None,
        Some((_, flag)) => Some((*flag).to_owned()),
        None => Some(key.replace('_', "-")),
    }
}

/// A case's error as a usage error that names the flag setting the value.
pub fn case_error(error: CaseError) -> Failure {
    Failure::Usage(case_message(&error))
}

/// A case's error worded with the flag that sets the value.
pub fn case_message(error: &CaseError) -> String {
    let flag = match (error.key, error.value.as_str()) {
        ("start", value) => format!("--{value}"),
        ("grading", value) => format!("--penalty {value}"),
        (key, value) => format!(
            "--{} {value}",
            flag_of(key).unwrap_or_else(|| key.to_owned())
        ),
    };
    format!("{flag}: {}", error.rule)
}

/// The flags of `codesign optimize` that pose `case` (all but `--out`): its task, robot,
/// payload, ends, space and linear solver, then every setting its document records (those the
/// document leaves out at their defaults, which are the flags' too, left out), its gradient
/// iterations and how its evaluations run.
pub fn case_flags(case: &Case) -> Vec<String> {
    let mut flags = model_flags(case);
    let settings = &case.settings;
    let penalty = settings.penalty().to_string();
    setting_flags(&settings.to_map(), &penalty, &mut flags);
    if settings.method == Method::Gradient {
        push(
            &mut flags,
            "gradient-iterations",
            case.gradient.max_iterations.to_string(),
        );
    }
    if let Value::Object(execution) = to_value(&case.execution) {
        setting_flags(&execution, &penalty, &mut flags);
    }
    flags
}

/// The flags of the problem a case poses.
fn model_flags(case: &Case) -> Vec<String> {
    let mut flags = Vec::new();
    match &case.model.task {
        TaskSource::BuiltIn => {}
        TaskSource::File(task) => push(&mut flags, "task", shell_quote(&task.to_string_lossy())),
        // A task built in memory has no flag: its text is what the run's log records.
        TaskSource::Given(given) => push(&mut flags, "task", shell_quote(&given.label)),
    }
    if let Some(robot) = &case.model.robot {
        push(&mut flags, "robot", shell_quote(&robot.to_string_lossy()));
    }
    if let Some(payload) = case.model.payload {
        push(&mut flags, "payload", payload.to_string());
    }
    if let Some(ends) = case.model.ends {
        push(&mut flags, "ends", ends.to_string());
    }
    push(&mut flags, "space", case.problem.space.name().to_owned());
    if let Some(solver) = case.problem.linear_solver {
        push(&mut flags, "linear-solver", solver.name().to_owned());
    }
    flags
}

/// The flags of the settings `map` (keys as the document writes them): an object's `kind` is
/// its key's value and its other keys are flags of their own; a list is comma-separated; the
/// penalty's base and grading are `penalty`.
fn setting_flags(map: &Map<String, Value>, penalty: &str, flags: &mut Vec<String>) {
    for (key, value) in map {
        let Some(flag) = flag_of(key) else { continue };
        match value {
            Value::Object(inner) => {
                if let Some(kind) = inner.get("kind") {
                    push(flags, &flag, word(kind));
                }
                let rest: Map<String, Value> = (inner.iter().filter(|(key, _)| *key != "kind"))
                    .map(|(key, value)| (key.clone(), value.clone()))
                    .collect();
                setting_flags(&rest, penalty, flags);
            }
            Value::String(start) if key == "start" => match start.as_str() {
                "fresh" => {}
                other => flags.push(format!("--{other}")),
            },
            _ if key == "penalty" => push(flags, &flag, penalty.to_owned()),
            _ => push(flags, &flag, word(value)),
        }
    }
}

/// A value as a flag's argument: strings quoted for the shell where they need it, lists
/// comma-separated.
fn word(value: &Value) -> String {
    match value {
        Value::String(text)
            if text
                .chars()
                .all(|c| c.is_alphanumeric() || "-_.".contains(c)) =>
        {
            text.clone()
        }
        Value::String(text) => shell_quote(text),
        Value::Array(items) => items.iter().map(word).collect::<Vec<_>>().join(","),
        // Numbers as Rust writes them: 1 for 1.0, the shortest text that reads back the same.
        Value::Number(n) if n.is_f64() => n.as_f64().map_or(n.to_string(), |x| x.to_string()),
        other => other.to_string(),
    }
}

/// `--flag value` pushed onto `flags`.
fn push(flags: &mut Vec<String>, flag: &str, value: String) {
    flags.extend([format!("--{flag}"), value]);
}

/// `value` as JSON (a plain struct always serialises).
fn to_value(value: &impl serde::Serialize) -> Value {
    serde_json::to_value(value).unwrap_or(Value::Null)
}

#[cfg(test)]
mod tests {
    use super::{case_flags, case_message, flag_of};
    use crate::design::bounds::BoundHandling;
    use crate::design::cmaes::CmaesSettings;
    use crate::design::penalty::Grading;
    use crate::design::run::{Case, Execution, Method, OptimizeInputs, RunSettings};
    use crate::design::score::{Objective, PayloadRange};
    use crate::design::warm::WarmStart;
    use crate::store::log::Start;
    use clap::Parser;

    /// `codesign optimize`'s flags alone.
    #[derive(Parser)]
    struct Optimize {
        #[command(flatten)]
        args: crate::cli::optimize::Args,
    }

    /// A case with every setting away from its default (CMA-ES's tolerances aside: no flag
    /// sets them). A new setting is added here too, away from its default.
    fn unusual() -> Case {
        let mut case = Optimize::parse_from(["optimize", "--space", "joint"])
            .args
            .case();
        case.settings = RunSettings {
            method: Method::Cmaes,
            objective: Objective::Range(PayloadRange {
                payloads_kg: vec![0.5, 1.25],
            }),
            cmaes: CmaesSettings {
                population: 12,
                generations: 3,
                sigma0: 0.125,
                seed: 7,
                ..CmaesSettings::default()
            },
            penalty: 1e6,
            grading: Grading::Graded,
            bounds: BoundHandling::Map,
            warm_start: WarmStart::Off,
        };
        case.execution = Execution {
            workers: Some(3),
            solve_timeout_s: 42.5,
            worker_command: Some("nice".to_owned()),
            start: Start::Resume,
        };
        case
    }

    #[test]
    fn a_cases_flags_pose_the_same_case() {
        let case = unusual();
        let flags = case_flags(&case);
        let argv = std::iter::once("optimize".to_owned()).chain(flags.iter().cloned());
        let parsed = Optimize::try_parse_from(argv)
            .unwrap_or_else(|e| panic!("{flags:?}: {e}"))
            .args
            .case();
        assert_eq!(parsed.settings, case.settings, "{flags:?}");
        assert_eq!(parsed.execution, case.execution, "{flags:?}");
        assert_eq!(parsed.problem, case.problem);
        // Every recorded setting has its flag, but the tolerances no flag sets.
        for key in case.settings.to_map().keys() {
            let fixed = ["ftol", "xtol", "grading"].contains(&key.as_str());
            assert_eq!(flag_of(key).is_none(), fixed, "{key}");
        }
    }

    #[test]
    fn every_setting_reaches_the_document_and_the_log_header() {
        let case = unusual();
        let mut loaded = crate::design::run::ModelChoice::default().load().unwrap();
        loaded.task.payload.mass_kg = 0.0;
        let inputs = case.inputs(&loaded, loaded.task.limit_modes);
        let document = serde_json::to_value(&inputs).unwrap();
        for (key, value) in case.settings.to_map() {
            assert_eq!(document.get(&key), Some(&value), "{key}");
        }
        // The log's header is the same record, read back whole.
        let back: OptimizeInputs = serde_json::from_value(document).unwrap();
        assert_eq!(back, inputs);
        assert!(case.differences(&back).is_empty());
        let mut other = case.clone();
        other.settings.cmaes.sigma0 = 0.25;
        other.settings.warm_start = WarmStart::On;
        assert_eq!(
            other.differences(&back),
            [
                "sigma0: recorded 0.125, planned 0.25",
                "warm_start: recorded off, planned on"
            ]
        );
    }

    /// The energy objective is a named choice: `--objective energy` poses it, and the document
    /// and the log header record it as the objective's kind; a graded penalty is refused with it.
    #[test]
    fn the_energy_objective_reaches_the_flags_and_the_document() {
        let mut case = unusual();
        case.settings.objective = Objective::Energy;
        case.settings.grading = Grading::Flat;
        let flags = case_flags(&case);
        assert!(
            flags
                .windows(2)
                .any(|pair| pair == ["--objective", "energy"]),
            "{flags:?}"
        );
        let argv = std::iter::once("optimize".to_owned()).chain(flags.iter().cloned());
        let parsed = Optimize::try_parse_from(argv).unwrap().args.case();
        assert_eq!(parsed.settings, case.settings);
        let mut loaded = crate::design::run::ModelChoice::default().load().unwrap();
        loaded.task.payload.mass_kg = 0.0;
        let inputs = case.inputs(&loaded, loaded.task.limit_modes);
        let document = serde_json::to_value(&inputs).unwrap();
        assert_eq!(document["objective"], serde_json::json!({"kind": "energy"}));
        let back: OptimizeInputs = serde_json::from_value(document).unwrap();
        assert_eq!(back.settings.objective, Objective::Energy);
        case.settings.grading = Grading::Graded;
        case.execution.start = Start::Fresh;
        let error = case.validate().unwrap_err();
        assert!(
            case_message(&error).starts_with("--penalty graded: the elastic problem's weights"),
            "{error}"
        );
    }

    #[test]
    fn errors_name_the_flag() {
        let mut case = unusual();
        case.settings.cmaes.sigma0 = -1.0;
        let error = case.validate().unwrap_err();
        let message = case_message(&error);
        assert!(
            message.starts_with("--sigma -1: must be a positive number at most 1 (pagmo's range)"),
            "{message}"
        );
        case.settings.cmaes.sigma0 = 0.3;
        case.model.payload = Some(1.0);
        let error = case.validate().unwrap_err();
        assert!(case_message(&error).starts_with("--payload 1: "), "{error}");
    }
}
