//! Running a search over parts: each combination's task co-designed by the gradient method
//! ([`run_case`]), its document read back instead where a resumed search finished it, and its
//! point of the front taken from it (the actuator mass at r*, the objective's value).

use super::document::{ParetoDocument, ParetoInputs, PartsObjective, PartsPoint};
use crate::design::capacity::{payload_capacity, CapacitySettings};
use crate::design::gradient::{GradientError, GradientSettings};
use crate::design::penalty::Penalty;
use crate::design::run::{
    run_case, Case, CaseError, Execution, Loaded, Method, ModelChoice, OptimizeDocument,
    ProblemChoice, ProgressDisplay, RecordedHash, RunError,
};
use crate::design::score::Objective;
use crate::store::document::read_document;
use crate::store::log::Start;
use codesign_core::hash::fnv1a;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::part_family::{Combination, PartsFamily};
use codesign_core::model::task::{GivenTask, TaskFile, TaskSource};
use codesign_core::problem::Formulation;
use codesign_core::solve::ToolInfo;
use std::fmt;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// A search over the parts of a family of tasks: how each combination is co-designed.
#[derive(Clone, Debug)]
pub struct PartsSearch {
    /// The task file with candidates.
    pub family: PartsFamily,
    /// The family's file as given (the path or label results record).
    pub task_file: String,
    /// The robot, payload and ends that replace the task's (its `task` is ignored: each
    /// combination's task is the family's).
    pub model: ModelChoice,
    /// Space, limit modes and linear solver.
    pub problem: ProblemChoice,
    /// What judges a design.
    pub objective: PartsObjective,
    /// How the gradient method scores infeasible designs (graded: it descends on the elastic
    /// problem, from infeasible starts too).
    pub penalty: Penalty,
    /// The gradient method's settings.
    pub gradient: GradientSettings,
    /// Workers and timeout of each run; its start is the folder's: a fresh search refuses a
    /// folder holding an earlier one's files, `Resume` reads the combinations it finished,
    /// `Overwrite` runs every combination again.
    pub execution: Execution,
}

/// What a search tells its observer.
pub enum PartsEvent<'a> {
    /// Combination `index` (from 0) of `total` starts.
    Started {
        /// Its place in the order searched.
        index: usize,
        /// How many there are.
        total: usize,
        /// The combination.
        combination: &'a Combination,
    },
    /// Combination `index` of `total` is done; `replayed` when read from an earlier search.
    Done {
        /// Its place in the order searched.
        index: usize,
        /// How many there are.
        total: usize,
        /// Its point.
        point: &'a PartsPoint,
        /// Whether its document was read from an earlier search instead of run.
        replayed: bool,
    },
}

/// Why a search failed.
#[derive(Debug)]
pub enum PartsError {
    /// A setting out of its range, named by its key.
    Case(CaseError),
    /// The output folder cannot be used; the reason names it.
    Folder(String),
    /// A combination's run failed; its parts and the run's error.
    Run {
        /// The combination's parts, comma-separated.
        parts: String,
        /// The run's error.
        error: RunError,
    },
}

impl fmt::Display for PartsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartsError::Case(error) => error.fmt(f),
            PartsError::Folder(why) => f.write_str(why),
            PartsError::Run { parts, error } => write!(f, "parts [{parts}]: {error}"),
        }
    }
}

impl std::error::Error for PartsError {}

/// The file name of each of `combinations` (in their order): its slots that offer candidates,
/// each part's name in lower-case letters and digits joined by `-`, joined by `_`, then
/// `.json` (`parts.json` for a family without a choice). An error where two combinations, or
/// a combination and `pareto.json`, would share a name.
pub fn combination_files(
    family: &PartsFamily,
    combinations: &[Combination],
) -> Result<Vec<String>, String> {
    let slots = family.choice_slots();
    let files: Vec<String> = (combinations.iter())
        .map(|c| {
            let names: Vec<String> = slots.iter().map(|&s| slug(&c.parts[s])).collect();
            match names.is_empty() {
                true => "parts.json".to_owned(),
                false => format!("{}.json", names.join("_")),
            }
        })
        .collect();
    for (i, file) in files.iter().enumerate() {
        if files[..i].contains(file) || file == "pareto.json" {
            return Err(format!(
                "{}: the candidates [{}] make the file name {file}, which another file of the \
                 search takes: rename a part in its catalogue",
                family.source(),
                combinations[i].parts.join(", ")
            ));
        }
    }
    Ok(files)
}

/// `name` in lower-case ASCII letters and digits, every other run of characters one `-`
/// (`part` for a name of neither).
fn slug(name: &str) -> String {
    let mut slug = String::with_capacity(name.len());
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            slug.push(c.to_ascii_lowercase());
        } else if !slug.is_empty() && !slug.ends_with('-') {
            slug.push('-');
        }
    }
    match slug.trim_end_matches('-') {
        "" => "part".to_owned(),
        slug => slug.to_owned(),
    }
}

impl PartsSearch {
    /// The co-design run of `file`, the task of a combination named `label`.
    fn case(&self, file: TaskFile, label: String) -> Case {
        let given = GivenTask { label, file };
        let model = ModelChoice {
            task: TaskSource::Given(Arc::new(given)),
            ..self.model.clone()
        };
        let mut case = Case::new(model, self.problem.clone(), Method::Gradient);
        case.settings.objective = match self.objective {
            PartsObjective::Time => Objective::Time,
            PartsObjective::Cost | PartsObjective::Capacity => Objective::Cost,
        };
        case.settings.set_penalty(self.penalty);
        case.gradient = self.gradient.clone();
        // The folder's start is decided here; a combination run is always run afresh.
        case.execution = Execution {
            start: Start::Overwrite,
            ..self.execution.clone()
        };
        case
    }

    /// Checks the settings that need no file, as a combination's run would.
    pub fn validate(&self) -> Result<(), CaseError> {
        let combination = self.family.combinations().into_iter().next();
        let file = combination.map(|c| self.family.task_of(&c));
        match file {
            Some(Ok(file)) => self.case(file, String::new()).validate(),
            _ => Ok(()),
        }
    }
}

/// Runs `search` into the folder `dir` (made if missing), telling `observe` of each
/// combination, and returns its document (which the caller writes with its plot). An
/// interrupted search keeps every combination it finished: each run's document is written
/// whole as it ends.
pub fn run_parts(
    search: &PartsSearch,
    dir: &Path,
    display: ProgressDisplay<'_>,
    observe: &mut dyn FnMut(PartsEvent<'_>),
) -> Result<ParetoDocument, PartsError> {
    search.validate().map_err(PartsError::Case)?;
    let combinations = search.family.combinations();
    let files = combination_files(&search.family, &combinations).map_err(PartsError::Folder)?;
    prepare_folder(dir, &files, search.execution.start)?;
    let total = combinations.len();
    let mut points = Vec::with_capacity(total);
    let mut payload_kg = 0.0;
    let mut solver = search.problem.linear_solver;
    for (index, (combination, file)) in combinations.iter().zip(&files).enumerate() {
        observe(PartsEvent::Started {
            index,
            total,
            combination,
        });
        let (point, loaded, replayed) = search_one(search, combination, dir, file, display)
            .map_err(|error| PartsError::Run {
                parts: combination.parts.join(", "),
                error,
            })?;
        payload_kg = loaded.task.payload.mass_kg;
        solver = Some(loaded.settings.linear_solver());
        observe(PartsEvent::Done {
            index,
            total,
            point: &point,
            replayed,
        });
        points.push(point);
    }
    let hashes: Vec<&str> = points.iter().map(|p| p.task_hash.as_str()).collect();
    let inputs = ParetoInputs {
        task_file: search.task_file.clone(),
        task_hash: RecordedHash(Some(fnv1a(hashes.join(",").as_bytes()))),
        space: search.problem.space,
        payload_kg,
        objective: search.objective,
        gradient_iterations: search.gradient.max_iterations,
    };
    let tool = ToolInfo::current(solver.unwrap_or(LinearSolver::Ldl));
    Ok(ParetoDocument::new(tool, inputs, points))
}

/// The point of `combination`, its result file `file` in `dir` co-designed (or, resumed and
/// there, read back), with its task as loaded and whether it was read back.
fn search_one(
    search: &PartsSearch,
    combination: &Combination,
    dir: &Path,
    file: &str,
    display: ProgressDisplay<'_>,
) -> Result<(PartsPoint, Loaded, bool), RunError> {
    let task = (search.family.task_of(combination)).map_err(|e| RunError::Load(e.to_string()))?;
    let case = search.case(task, search.family.label_of(combination));
    let mut loaded = case.model.load().map_err(RunError::Load)?;
    case.problem.configure(&mut loaded.settings);
    let path = dir.join(file);
    let (run, replayed) = match search.execution.start {
        Start::Resume if path.exists() => (read_finished(&case, &loaded, &path)?, true),
        _ => (co_design(&case, &path, display)?, false),
    };
    let point = point_of(search, &loaded, combination, file, run)?;
    Ok((point, loaded, replayed))
}

/// Makes `dir` where missing; for a fresh search, refuses it where it holds one of `files`,
/// `pareto.json` or `pareto.svg` (an earlier search's).
fn prepare_folder(dir: &Path, files: &[String], start: Start) -> Result<(), PartsError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        PartsError::Folder(format!("{}: cannot make the folder: {e}", dir.display()))
    })?;
    if start != Start::Fresh {
        return Ok(());
    }
    let outputs = ["pareto.json", "pareto.svg"].map(str::to_owned);
    match files.iter().chain(&outputs).find(|f| dir.join(f).exists()) {
        Some(found) => Err(PartsError::Folder(format!(
            "{} holds {found} of an earlier search: continue it with --resume (Python: \
             resume=True), or start afresh with --overwrite",
            dir.display()
        ))),
        None => Ok(()),
    }
}

/// A combination's co-design: its document, or None where the gradient method found no
/// feasible start (the flat penalty), with the solves that showed it.
struct Run {
    document: Option<OptimizeDocument>,
    why_none: Option<(usize, String)>,
    started: Instant,
}

/// Runs `case` to `path`; a run without a feasible start is a run without a document.
fn co_design(case: &Case, path: &Path, display: ProgressDisplay<'_>) -> Result<Run, RunError> {
    let started = Instant::now();
    match run_case(case, path, display) {
        Ok(document) => Ok(Run {
            document: Some(document),
            why_none: None,
            started,
        }),
        Err(RunError::Gradient(error @ GradientError::NoFeasibleStart { solved })) => Ok(Run {
            document: None,
            why_none: Some((solved, error.to_string())),
            started,
        }),
        Err(error) => Err(error),
    }
}

/// The document an earlier search wrote at `path` for `case`, checked to be a run of it.
fn read_finished(case: &Case, loaded: &Loaded, path: &Path) -> Result<Run, RunError> {
    let refused = |why: String| {
        RunError::Load(format!(
            "{}: {why}; start the search afresh with --overwrite",
            path.display()
        ))
    };
    let document = read_document::<OptimizeDocument>(path).map_err(refused)?;
    let mut differences = case.differences(&document.inputs);
    let recorded = &document.inputs.task_hash;
    if recorded.0.as_deref() != Some(loaded.task_hash.as_str()) {
        differences.push(format!(
            "task_hash: recorded {}, planned {}",
            recorded.0.as_deref().unwrap_or("none"),
            loaded.task_hash
        ));
    }
    if !differences.is_empty() {
        return Err(refused(format!(
            "a run of other settings ({})",
            differences.join("; ")
        )));
    }
    Ok(Run {
        document: Some(document),
        why_none: None,
        started: Instant::now(),
    })
}

/// The point of `combination` (its result file `file`) from its `run`: r*, the actuator mass
/// there, the objective's value (for the capacity, a search at r*), the work.
fn point_of(
    search: &PartsSearch,
    loaded: &Loaded,
    combination: &Combination,
    file: &str,
    run: Run,
) -> Result<PartsPoint, RunError> {
    let mut point = PartsPoint {
        parts: combination.parts.clone(),
        file: None,
        task_hash: loaded.task_hash.clone(),
        motor_mass_kg: combination.motor_mass_kg,
        feasible: false,
        ratios: Vec::new(),
        actuator_mass_kg: None,
        value: None,
        solves: 0,
        iterations: 0,
        wall_seconds: 0.0,
        stop_reason: String::new(),
    };
    let Some(document) = run.document else {
        let (solves, why) = run.why_none.unwrap_or_default();
        point.solves = solves;
        point.stop_reason = why;
        point.wall_seconds = run.started.elapsed().as_secs_f64();
        return Ok(point);
    };
    point.file = Some(file.to_owned());
    point.solves = document.solves;
    point.iterations = (document.verdicts.as_ref()).map_or(0, |v| {
        [&v.feasible, &v.infeasible, &v.invalid, &v.unjudged]
            .iter()
            .map(|count| count.iterations)
            .sum()
    });
    point.wall_seconds = document.wall_seconds + document.earlier_seconds.unwrap_or(0.0);
    point.stop_reason = document.stop_reason.clone();
    let Some(best) = document.best_cost else {
        return Ok(point);
    };
    let ratios = document.best_ratios;
    let modes = search.problem.modes(&loaded.task);
    let formulation = Formulation::new(
        &loaded.task,
        loaded.robot.clone(),
        search.problem.space,
        modes,
    )
    .map_err(|e| RunError::Load(e.to_string()))?
    .with_hold_tolerance(loaded.settings.constraint_tolerance());
    point.actuator_mass_kg = formulation.setting().actuator_mass_kg(&ratios);
    point.value = Some(best);
    point.feasible = true;
    if search.objective == PartsObjective::Capacity {
        let started = Instant::now();
        let settings = CapacitySettings::default();
        let capacity = payload_capacity(&formulation, &loaded.settings, &ratios, &settings)
            .map_err(|e| RunError::Load(e.to_string()))?;
        point.solves += capacity.probes.len();
        point.iterations += capacity.probes.iter().map(|p| p.iterations).sum::<usize>();
        point.wall_seconds += started.elapsed().as_secs_f64();
        point.value = capacity.capacity_kg;
        point.feasible = capacity.capacity_kg.is_some();
    }
    point.ratios = ratios;
    Ok(point)
}

#[cfg(test)]
mod tests {
    use super::slug;

    #[test]
    fn a_parts_name_becomes_letters_digits_and_dashes() {
        assert_eq!(
            slug("Allied Motion HT02501-A00"),
            "allied-motion-ht02501-a00"
        );
        assert_eq!(slug("  Faulhaber 42GPT 3.6:1 "), "faulhaber-42gpt-3-6-1");
        assert_eq!(slug("---"), "part");
    }
}
