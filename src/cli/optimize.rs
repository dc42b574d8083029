//! `codesign optimize`: co-design of one case (space, payload, seed) with CMA-ES or the gradient
//! method.

use super::case::Case;
use super::common::{ModelArgs, ProblemArgs};
use super::preflight::probe_solver;
use crate::design::capacity::CapacitySettings;
use crate::design::cmaes::CmaesSettings;
use crate::design::evaluate::{Objective, PayloadRange};
use crate::design::gradient::{optimize_gradient, GradientSettings};
use crate::design::log::{EvaluationLog, Finished, Start};
use crate::design::optimize::{optimize, Progress};
use crate::design::outcome::DesignOutcome;
use crate::design::penalty::{Grading, Penalty};
use crate::design::score::Fitness;
use crate::design::workers::{Pool, WorkerSetup, SOLVE_TIMEOUT_S};
use crate::model::task::Task;
use crate::problem::Formulation;
use crate::report::codesign::{Method, OptimizeDocument, OptimizeInputs, PayloadCost, RangeCosts};
use crate::report::files::{check_output, write_json};
use crate::report::trajectory::ToolInfo;
use crate::solve::{solve_design, solve_design_from, SolveSettings};
use crate::stats::median;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Flags of `codesign optimize`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Outer-level method: CMA-ES (the paper's) or projected quasi-Newton on dJ*/dr.
    #[arg(long, value_enum, default_value = "cmaes")]
    pub method: Method,
    /// What to minimise: the trajectory cost at the payload, or minus the payload capacity
    /// (each evaluation then bisects the payload: about 10 solves).
    #[arg(long, value_enum, default_value = "cost")]
    pub objective: ObjectiveKind,
    /// Payloads of `--objective range`, kg: each evaluation solves the design at every one (in
    /// its worker) and scores the mean cost, or the penalty when any is infeasible.
    #[arg(long, value_name = "KG,KG,..", value_delimiter = ',', num_args = 1..)]
    pub payloads: Option<Vec<f64>>,
    /// Resolution of the capacity search of `--objective capacity`, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().resolution_kg)]
    pub capacity_resolution: f64,
    /// Iterations per start of the gradient method.
    #[arg(long, value_name = "N", default_value_t = GradientSettings::default().max_iterations)]
    pub gradient_iterations: usize,
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Seed of CMA-ES's random numbers.
    #[arg(long, default_value_t = CmaesSettings::default().seed)]
    pub seed: u64,
    /// CMA-ES population size lambda.
    #[arg(long, default_value_t = CmaesSettings::default().population)]
    pub population: usize,
    /// CMA-ES generations after the initial population.
    #[arg(long, default_value_t = CmaesSettings::default().generations)]
    pub generations: usize,
    /// Initial step size, relative to the width of the design box.
    #[arg(long, default_value_t = CmaesSettings::default().sigma0)]
    pub sigma: f64,
    /// How invalid or infeasible designs score: `flat` (the paper's 1e6 for every one),
    /// `graded` (infeasible designs 1e6 to 2e6 by their torque deficit and speed excess from the
    /// elastic problem, invalid ones 2e6 to 3e6 by their distance from the design space, so that
    /// CMA-ES moves toward feasibility; the gradient method then descends on the elastic
    /// problem's objective, from infeasible starts too), or a number (flat, of that value).
    #[arg(long, value_name = "flat|graded|VALUE", default_value_t = Penalty::PAPER)]
    pub penalty: Penalty,
    /// Worker processes (default: one per core).
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
    /// Result file (JSON); the evaluation log is written beside it as FILE.log.jsonl and locked
    /// for the whole run (a second run on the same file fails at once). A symbolic link is
    /// followed; an input file, a folder or a special file is refused.
    #[arg(long, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
    /// Continue an interrupted run from its evaluation log (a run without a log starts afresh).
    #[arg(long)]
    pub resume: bool,
    /// Start afresh even if the evaluation log of an earlier run exists (it is deleted).
    #[arg(long, conflicts_with = "resume")]
    pub overwrite: bool,
}

impl Args {
    /// The run these flags ask for.
    pub fn case(&self) -> Case {
        let mut case = Case::new(self.model.clone(), self.problem.clone(), self.method);
        case.objective = match self.objective {
            ObjectiveKind::Cost => Objective::Cost,
            ObjectiveKind::Capacity => Objective::Capacity(CapacitySettings {
                resolution_kg: self.capacity_resolution,
                ..CapacitySettings::default()
            }),
            ObjectiveKind::Range => Objective::Range(PayloadRange {
                payloads_kg: self.payloads.clone().unwrap_or_default(),
            }),
        };
        case.cmaes = CmaesSettings {
            population: self.population,
            generations: self.generations,
            sigma0: self.sigma,
            seed: self.seed,
            ..CmaesSettings::default()
        };
        case.gradient.max_iterations = self.gradient_iterations;
        case.penalty = self.penalty;
        case.workers = self.workers;
        case.solve_timeout_s = self.solve_timeout;
        case.worker_command = self.worker_command.clone();
        case.start = Start::from_flags(self.resume, self.overwrite);
        case
    }
}

struct Bar(ProgressBar);

impl Progress for Bar {
    fn evaluated(&mut self, best: f64) {
        self.0.inc(1);
        self.0.set_message(format!("best J {best:.4}"));
    }
}

/// The extension of an evaluation log, which sits beside its result file.
pub const LOG_EXTENSION: &str = "log.jsonl";

/// The evaluation log beside a result file: `x.json` -> `x.log.jsonl`.
pub fn log_path(out: &Path) -> PathBuf {
    out.with_extension(LOG_EXTENSION)
}

/// Runs one co-design case and writes its document to `out`; returns it. A CMA-ES run holds its
/// evaluation log, locked, from before the first evaluation until the document is written.
pub fn run_case(case: &Case, out: &Path) -> Result<OptimizeDocument, String> {
    case.validate()?;
    let (task, robot, mut settings) = case.model.load()?;
    case.problem.configure(&mut settings);
    let read = case.model.inputs(&task);
    check_output("--out", out, &read)?;
    if case.method == Method::Cmaes {
        check_output("--out (its evaluation log)", &log_path(out), &read)?;
    }
    let modes = case.problem.modes(&task);
    probe_solver(&task, &settings, &robot, case, modes)?;
    let formulation =
        Formulation::new(&task, robot, case.problem.space, modes).map_err(|e| e.to_string())?;
    let inputs = case.inputs(&task, &settings, modes);
    let mut log = match case.method {
        Method::Cmaes => Some(open_log(case.start, out, &inputs)?),
        Method::Gradient => None,
    };
    let started = Instant::now();
    let outcome = match log.as_mut() {
        Some((log, finished)) => {
            let setup = worker_setup(case, &inputs, &task, &settings, &formulation)?;
            run_cmaes(case, &inputs, &setup, &formulation, log, finished)
                .map(|o| (o, log.earlier_seconds()))
        }
        None => optimize_gradient(&formulation, &settings, &case.gradient, case.penalty)
            .map(|o| (o, Some(0.0)))
            .map_err(|e| e.to_string()),
    };
    let result = outcome.and_then(|(outcome, earlier_seconds)| {
        let mut document = document(case, &formulation, &settings, inputs, outcome)?;
        document.earlier_seconds = earlier_seconds;
        document.wall_seconds = started.elapsed().as_secs_f64();
        write_json(out, &document)?;
        Ok(document)
    });
    if let (Err(_), Some((log, _))) = (&result, log) {
        log.discard_if_unused()?;
    }
    result
}

/// Opens (locked) the evaluation log of a CMA-ES run as `start` says.
fn open_log(
    start: Start,
    out: &Path,
    inputs: &OptimizeInputs,
) -> Result<(EvaluationLog, Finished), String> {
    let (log, finished) = EvaluationLog::open(&log_path(out), inputs, start)?;
    if let Some(line) = log.dropped_line() {
        eprintln!(
            "note: {} ended in a line cut short by an interruption (line {line}); it was dropped \
             and that evaluation is solved again",
            log_path(out).display()
        );
    }
    Ok((log, finished))
}

/// The result document of a run: the method's outcome with full solves of the best and the
/// original design (at every payload of a range). The wall time and the earlier invocations'
/// time are the caller's to set.
fn document(
    case: &Case,
    formulation: &Formulation,
    settings: &SolveSettings,
    inputs: OptimizeInputs,
    outcome: DesignOutcome,
) -> Result<OptimizeDocument, String> {
    let original_ratios = formulation.transmission().original().to_vec();
    // The designs are solved again as they were scored: the elastic problem for a graded
    // penalty, so that the reported cost is the one behind `best_cost`.
    let elastic;
    let scored = match case.penalty.grading {
        Grading::Flat => formulation,
        Grading::Graded => {
            elastic = formulation.elastic();
            &elastic
        }
    };
    let (best_result, original_result, payload_costs) = match &case.objective {
        Objective::Range(_) => {
            let fitness = Fitness::new(
                formulation.task(),
                settings,
                formulation.space(),
                *formulation.modes(),
                &case.objective,
                case.penalty,
            )
            .map_err(|e| e.to_string())?;
            let best = payload_costs(&fitness, settings, &outcome.best_ratios);
            let original = payload_costs(&fitness, settings, &original_ratios);
            (None, None, Some(RangeCosts { best, original }))
        }
        // Warm-started from the method's own inner solution where it has one, so that the
        // reported trajectory is the one behind `best_cost`.
        _ => (
            solve_design_from(
                scored,
                &outcome.best_ratios,
                settings,
                outcome.best_solution.as_ref(),
            )
            .ok()
            .map(|(result, _)| result),
            solve_design(scored, &original_ratios, settings).ok(),
            None,
        ),
    };
    let original_cost = match (&original_result, &payload_costs) {
        (Some(result), _) if result.feasible => result.cost,
        (_, Some(costs)) if costs.original.iter().all(|c| c.feasible) => {
            costs.original.iter().map(|c| c.cost).sum::<f64>() / costs.original.len() as f64
        }
        _ => case.penalty.base,
    };
    Ok(OptimizeDocument {
        tool: ToolInfo::current(inputs.linear_solver),
        inputs,
        best_ratios: outcome.best_ratios,
        best_cost: outcome.best_cost,
        best_result,
        original_ratios,
        original_cost,
        original_result,
        generations: outcome.generations,
        evaluations: outcome.costs.len(),
        costs: outcome.costs,
        iterates: outcome.iterates,
        replayed: outcome.replayed,
        solves: outcome.seconds.len(),
        solve_seconds_total: outcome.seconds.iter().sum(),
        median_solve_seconds: median(&outcome.seconds),
        stop_reason: outcome.stop_reason,
        wall_seconds: 0.0,
        earlier_seconds: None,
        payload_costs,
    })
}

/// `ratios` solved at every payload of a range `fitness` (none when `ratios` is empty: no
/// feasible design was found).
fn payload_costs(fitness: &Fitness, settings: &SolveSettings, ratios: &[f64]) -> Vec<PayloadCost> {
    if ratios.is_empty() {
        return Vec::new();
    }
    fitness
        .payloads()
        .iter()
        .map(|(payload_kg, formulation)| {
            let solved = solve_design(formulation, ratios, settings);
            PayloadCost {
                payload_kg: *payload_kg,
                feasible: solved.as_ref().is_ok_and(|r| r.feasible),
                cost: solved.as_ref().map_or(f64::NAN, |r| r.cost),
                status: solved.map_or_else(|e| e.to_string(), |r| r.status),
            }
        })
        .collect()
}

/// The objective as a flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectiveKind {
    /// The optimal trajectory cost J (the paper's criterion).
    Cost,
    /// Minus the payload capacity.
    Capacity,
    /// The mean cost over the payloads of `--payloads`: one design for the whole range.
    Range,
}

/// What the workers of a CMA-ES run are told: the task (its robot's path made absolute), the
/// solve settings, the problem and how designs are scored.
fn worker_setup(
    case: &Case,
    inputs: &OptimizeInputs,
    task: &Task,
    settings: &SolveSettings,
    formulation: &Formulation,
) -> Result<WorkerSetup, String> {
    let mut worker_task = task.clone();
    if let Some(robot) = &task.robot {
        worker_task.robot = Some(
            std::fs::canonicalize(robot).map_err(|e| format!("robot {}: {e}", robot.display()))?,
        );
    }
    Ok(WorkerSetup {
        objective: inputs.objective.clone(),
        task: worker_task,
        solve: settings.clone(),
        space: case.problem.space,
        modes: *formulation.modes(),
        penalty: case.penalty,
    })
}

/// The CMA-ES run on its open evaluation log (with the `finished` evaluations of a resumed
/// run): worker pool, progress bar.
fn run_cmaes(
    case: &Case,
    inputs: &OptimizeInputs,
    setup: &WorkerSetup,
    formulation: &Formulation,
    log: &mut EvaluationLog,
    finished: &Finished,
) -> Result<DesignOutcome, String> {
    let workers = case
        .workers
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let program = std::env::current_exe()
        .map_err(|e| format!("cannot locate the codesign executable: {e}"))?;
    let timeout = Duration::from_secs_f64(case.solve_timeout_s);
    let mut pool =
        Pool::new(case.launcher(&program), setup, workers, timeout).map_err(|e| e.to_string())?;
    let settings = &case.cmaes;
    let bar = ProgressBar::new((settings.population * (settings.generations + 1)) as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{elapsed_precise}] {bar:30} {pos}/{len} {msg}")
            .map_err(|e| e.to_string())?,
    );
    bar.set_prefix(format!(
        "{} {} kg seed {}",
        case.problem.space, inputs.payload_kg, settings.seed
    ));
    let mut progress = Bar(bar);
    let bounds = formulation.transmission().bounds();
    let outcome = optimize(
        settings.clone(),
        bounds,
        &mut pool,
        log,
        finished,
        &mut progress,
    )
    .map_err(|e| e.to_string())?;
    progress.0.finish();
    Ok(outcome)
}

/// The run's result in one line: the best design and its fitness, or that none was feasible.
fn summary(document: &OptimizeDocument) -> String {
    let join = |ratios: &[f64]| {
        let texts: Vec<String> = ratios.iter().map(|r| format!("{r:.4}")).collect();
        texts.join(", ")
    };
    let best = join(&document.best_ratios);
    let found = match (&document.inputs.objective, &document.payload_costs) {
        _ if document.best_ratios.is_empty() => "no feasible design found".to_owned(),
        (Objective::Capacity(_), _) => format!(
            "largest payload capacity {:.3} kg at r = ({best})",
            -document.best_cost
        ),
        (Objective::Range(_), Some(costs)) => {
            let per_payload: Vec<String> = costs
                .best
                .iter()
                .map(|c| format!("{} kg: {:.4}", c.payload_kg, c.cost))
                .collect();
            format!(
                "best r = ({best}) with mean J = {:.6} ({}; original design: {:.6})",
                document.best_cost,
                per_payload.join(", "),
                document.original_cost
            )
        }
        _ => format!(
            "best r = ({best}) with J = {:.6} (original design: J = {:.6})",
            document.best_cost, document.original_cost
        ),
    };
    let timing = if document.median_solve_seconds.is_nan() {
        "no solve timed".to_owned()
    } else {
        format!("median solve {:.1} ms", document.median_solve_seconds * 1e3)
    };
    format!(
        "{found}; {} evaluations ({} replayed), {timing}; {}",
        document.evaluations, document.replayed, document.stop_reason
    )
}

/// Runs `codesign optimize` and prints a summary.
pub fn run(args: &Args) -> Result<(), String> {
    let out = args.out.clone().unwrap_or_else(|| {
        let payload = args
            .model
            .payload
            .map_or_else(|| "task".to_owned(), |p| format!("{p}kg"));
        PathBuf::from(format!(
            "optimize-{}-{payload}-seed{}.json",
            args.problem.space, args.seed
        ))
    });
    if args.payloads.is_some() && args.objective != ObjectiveKind::Range {
        return Err("--payloads: only with --objective range".to_owned());
    }
    let document = run_case(&args.case(), &out)?;
    say!("{}", summary(&document));
    match args.method {
        Method::Cmaes => say!(
            "result written to {} (evaluation log {})",
            out.display(),
            log_path(&out).display()
        ),
        Method::Gradient => say!("result written to {}", out.display()),
    }
    Ok(())
}
