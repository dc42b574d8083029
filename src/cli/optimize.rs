//! `codesign optimize`: co-design of one case (space, payload, seed) with CMA-ES.

use super::common::{ModelArgs, ProblemArgs};
use super::preflight::{check_evaluations, check_flags, probe_solver};
use crate::design::capacity::CapacitySettings;
use crate::design::cmaes::CmaesSettings;
use crate::design::evaluate::Objective;
use crate::design::gradient::{
    default_starts, optimize_gradient, spread_designs, GradientIterate, GradientSettings,
};
use crate::design::log::{EvaluationLog, Finished, Start};
use crate::design::optimize::{optimize, GenerationSummary, Progress};
use crate::design::workers::{Pool, WorkerSetup};
use crate::ipopt::Solution;
use crate::model::task::{LimitModes, Task};
use crate::problem::Formulation;
use crate::report::codesign::{Method, OptimizeDocument, OptimizeInputs};
use crate::report::files::{check_output, write_json};
use crate::report::trajectory::ToolInfo;
use crate::solver::{solve_design, solve_design_from, SolveSettings};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Halton designs that the gradient method always solves as candidate starts (beside the
/// original design).
const GRADIENT_SPREAD: u32 = 12;

/// Further Halton designs it solves, in order, while fewer feasible candidates than descents
/// are known.
const GRADIENT_FALLBACKS: u32 = 64;

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
    /// Resolution of the capacity search of `--objective capacity`, kg.
    #[arg(long, value_name = "KG", default_value_t = 0.01)]
    pub capacity_resolution: f64,
    /// Iterations per start of the gradient method.
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub gradient_iterations: usize,
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Seed of CMA-ES's random numbers.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// CMA-ES population size lambda.
    #[arg(long, default_value_t = 100)]
    pub population: usize,
    /// CMA-ES generations after the initial population.
    #[arg(long, default_value_t = 30)]
    pub generations: usize,
    /// Initial step size, relative to the width of the design box.
    #[arg(long, default_value_t = 0.3)]
    pub sigma: f64,
    /// Fitness of invalid or infeasible designs.
    #[arg(long, default_value_t = 1e6)]
    pub penalty: f64,
    /// Worker processes (default: one per core).
    #[arg(long, value_name = "N")]
    pub workers: Option<usize>,
    /// A solve taking longer than this (s) counts as a hung worker.
    #[arg(long, value_name = "S", default_value_t = 600.0)]
    pub solve_timeout: f64,
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

struct Bar(ProgressBar);

impl Progress for Bar {
    fn evaluated(&mut self, best: f64) {
        self.0.inc(1);
        self.0.set_message(format!("best J {best:.4}"));
    }
}

/// The extension of an evaluation log, which sits beside its result file.
pub const LOG_EXTENSION: &str = "log.jsonl";

/// The task as the run's inputs record it: its linear solver moves to
/// [`OptimizeInputs::linear_solver`], so that a log written before the field existed (MUMPS)
/// compares by that field alone.
fn without_linear_solver(task: &Task) -> Task {
    let mut task = task.clone();
    task.solver.linear_solver = None;
    task
}

/// The evaluation log beside a result file: `x.json` -> `x.log.jsonl`.
pub fn log_path(out: &Path) -> PathBuf {
    out.with_extension(LOG_EXTENSION)
}

/// Runs one co-design case and writes its document; returns it. A CMA-ES run holds its
/// evaluation log, locked, from before the first evaluation until the document is written.
pub fn run_case(args: &Args, out: &Path) -> Result<OptimizeDocument, String> {
    check_flags(args)?;
    let (mut task, robot) = args.model.load()?;
    args.problem.configure(&mut task);
    let read = args.model.inputs(&task);
    check_output("--out", out, &read)?;
    if args.method == Method::Cmaes {
        check_output("--out (its evaluation log)", &log_path(out), &read)?;
    }
    let modes = args.problem.modes(&task);
    probe_solver(&task, &robot, args, modes)?;
    let formulation =
        Formulation::new(&task, robot, args.problem.space, modes).map_err(|e| e.to_string())?;
    let inputs = run_inputs(args, &task, modes);
    let mut log = match args.method {
        Method::Cmaes => Some(open_log(args, out, &inputs)?),
        Method::Gradient => None,
    };
    let result = run_with(args, out, &task, &formulation, inputs, log.as_mut());
    if let (Err(_), Some((log, _))) = (&result, log) {
        log.discard_if_unused()?;
    }
    result
}

/// Opens (locked) the evaluation log of a CMA-ES run as `--resume` or `--overwrite` say.
fn open_log(
    args: &Args,
    out: &Path,
    inputs: &OptimizeInputs,
) -> Result<(EvaluationLog, Finished), String> {
    let start = match (args.resume, args.overwrite) {
        (true, _) => Start::Resume,
        (false, true) => Start::Overwrite,
        (false, false) => Start::Fresh,
    };
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

/// The settings of the run, as its document and log header record them.
fn run_inputs(args: &Args, task: &Task, modes: LimitModes) -> OptimizeInputs {
    OptimizeInputs {
        method: args.method,
        objective: objective(args),
        task_file: args.model.source().label(),
        task: without_linear_solver(task),
        linear_solver: task.solver.linear_solver(),
        space: args.problem.space,
        payload_kg: task.payload.mass_kg,
        limit_modes: modes,
        seed: args.seed,
        population: args.population,
        generations: args.generations,
        sigma0: args.sigma,
        penalty: args.penalty,
        ftol: FTOL,
        xtol: XTOL,
    }
}

/// CMA-ES's stopping tolerances on the fitness and on the design.
const FTOL: f64 = 1e-6;
const XTOL: f64 = 1e-6;

/// The objective the flags ask for.
fn objective(args: &Args) -> Objective {
    match args.objective {
        ObjectiveKind::Cost => Objective::Cost,
        ObjectiveKind::Capacity => Objective::Capacity(CapacitySettings {
            resolution_kg: args.capacity_resolution,
            first_step_kg: 1.0,
            max_kg: 64.0,
        }),
    }
}

/// Runs the method (CMA-ES on `log`, or the gradient method) and writes the document.
fn run_with(
    args: &Args,
    out: &Path,
    task: &Task,
    formulation: &Formulation,
    inputs: OptimizeInputs,
    log: Option<&mut (EvaluationLog, Finished)>,
) -> Result<OptimizeDocument, String> {
    let started = Instant::now();
    let mut worker_task = task.clone();
    if let Some(robot) = &task.robot {
        worker_task.robot = Some(
            std::fs::canonicalize(robot).map_err(|e| format!("robot {}: {e}", robot.display()))?,
        );
    }
    let setup = WorkerSetup {
        objective: inputs.objective,
        task: worker_task,
        space: args.problem.space,
        modes: *formulation.modes(),
        penalty: args.penalty,
    };
    let settings = CmaesSettings {
        population: args.population,
        generations: args.generations,
        sigma0: args.sigma,
        seed: args.seed,
        ftol: FTOL,
        xtol: XTOL,
    };
    let run = match args.method {
        Method::Cmaes => {
            let (log, finished) = log.ok_or("a CMA-ES run needs its evaluation log")?;
            run_cmaes(args, &inputs, formulation, settings, &setup, log, finished)?
        }
        Method::Gradient => run_gradient(args, formulation)?,
    };
    let solve = |ratios: &[f64]| solve_design(formulation, ratios, &SolveSettings::default()).ok();
    // Warm-started from the method's own inner solution where it has one, so that the reported
    // trajectory is the one behind `best_cost`.
    let best_result = solve_design_from(
        formulation,
        &run.best_ratios,
        &SolveSettings::default(),
        run.best_solution.as_ref(),
    )
    .ok()
    .map(|(result, _)| result);
    let original_ratios = formulation.transmission().original().to_vec();
    let original_result = solve(&original_ratios);
    let original_cost = match &original_result {
        Some(result) if result.feasible => result.cost,
        _ => args.penalty,
    };
    let mut seconds = run.seconds;
    seconds.sort_by(f64::total_cmp);
    let solves = seconds.len();
    let solve_seconds_total = seconds.iter().sum();
    let document = OptimizeDocument {
        tool: ToolInfo::current(inputs.linear_solver),
        inputs,
        best_ratios: run.best_ratios,
        best_cost: run.best_cost,
        best_result,
        original_ratios,
        original_cost,
        original_result,
        generations: run.generations,
        evaluations: run.costs.len(),
        costs: run.costs,
        iterates: run.iterates,
        replayed: run.replayed,
        solves,
        solve_seconds_total,
        median_solve_seconds: seconds.get(seconds.len() / 2).copied().unwrap_or(f64::NAN),
        stop_reason: run.stop_reason,
        wall_seconds: started.elapsed().as_secs_f64(),
        earlier_seconds: run.earlier_seconds,
    };
    write_json(out, &document)?;
    Ok(document)
}

/// The gradient method's run: projected quasi-Newton from spread starts.
fn run_gradient(args: &Args, formulation: &Formulation) -> Result<RunOutcome, String> {
    let settings = GradientSettings {
        max_iterations: args.gradient_iterations,
        tolerance: 1e-6,
        starts: default_starts(formulation.transmission(), GRADIENT_SPREAD),
        fallback_starts: spread_designs(
            formulation.transmission(),
            GRADIENT_SPREAD + 1..GRADIENT_SPREAD + 1 + GRADIENT_FALLBACKS,
        ),
        descents: 3,
    };
    let outcome = optimize_gradient(formulation, &settings, args.penalty);
    if outcome.best_ratios.is_empty() {
        return Err(format!(
            "the gradient method found no feasible start among {} candidate designs",
            outcome.candidates_solved
        ));
    }
    let solves = outcome.costs.len();
    Ok(RunOutcome {
        best_ratios: outcome.best_ratios,
        best_cost: outcome.best_cost,
        generations: Vec::new(),
        costs: outcome.costs,
        seconds: outcome.seconds.into_iter().filter(|s| *s > 0.0).collect(),
        replayed: 0,
        stop_reason: format!(
            "{} candidate starts solved, {} descents, {} iterates, {solves} solves",
            outcome.candidates_solved,
            settings.descents,
            outcome.iterates.len()
        ),
        iterates: outcome.iterates,
        best_solution: outcome.best_solution,
        earlier_seconds: Some(0.0),
    })
}

/// The objective as a flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectiveKind {
    /// The optimal trajectory cost J (the paper's criterion).
    Cost,
    /// Minus the payload capacity.
    Capacity,
}

/// What either method hands to the document.
struct RunOutcome {
    best_ratios: Vec<f64>,
    best_cost: f64,
    generations: Vec<GenerationSummary>,
    costs: Vec<f64>,
    seconds: Vec<f64>,
    replayed: usize,
    stop_reason: String,
    iterates: Vec<GradientIterate>,
    /// The inner solution of the best design, where the method keeps one.
    best_solution: Option<Solution>,
    /// Working time of the run's earlier invocations, s, where known.
    earlier_seconds: Option<f64>,
}

/// The CMA-ES run on its open evaluation log (with the `finished` evaluations of a resumed
/// run): worker pool, progress bar.
fn run_cmaes(
    args: &Args,
    inputs: &OptimizeInputs,
    formulation: &Formulation,
    settings: CmaesSettings,
    setup: &WorkerSetup,
    log: &mut EvaluationLog,
    finished: &Finished,
) -> Result<RunOutcome, String> {
    let workers = args
        .workers
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let program = std::env::current_exe()
        .map_err(|e| format!("cannot locate the codesign executable: {e}"))?;
    let mut pool = Pool::new(
        program,
        setup,
        workers,
        Duration::from_secs_f64(args.solve_timeout),
    )?;
    let bar = ProgressBar::new((args.population * (args.generations + 1)) as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{elapsed_precise}] {bar:30} {pos}/{len} {msg}")
            .map_err(|e| e.to_string())?,
    );
    bar.set_prefix(format!(
        "{} {} kg seed {}",
        args.problem.space, inputs.payload_kg, args.seed
    ));
    let mut progress = Bar(bar);
    let outcome = optimize(
        settings,
        formulation.transmission().bounds(),
        &mut pool,
        log,
        finished,
        &mut progress,
    )?;
    progress.0.finish();
    drop(pool);
    check_evaluations(&outcome.evaluations)?;

    Ok(RunOutcome {
        best_ratios: outcome.best_ratios,
        best_cost: outcome.best_cost,
        generations: outcome.generations,
        costs: outcome.evaluations.iter().map(|e| e.cost).collect(),
        seconds: outcome
            .evaluations
            .iter()
            .filter(|e| e.iterations > 0)
            .map(|e| e.seconds)
            .collect(),
        replayed: outcome.replayed,
        stop_reason: outcome.stop_reason,
        iterates: Vec::new(),
        best_solution: None,
        earlier_seconds: log.earlier_seconds(),
    })
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
    let document = run_case(args, &out)?;
    if args.objective == ObjectiveKind::Capacity {
        say!(
            "largest payload capacity {:.3} kg at r = ({}); {} evaluations ({} replayed); {}",
            -document.best_cost,
            document
                .best_ratios
                .iter()
                .map(|r| format!("{r:.4}"))
                .collect::<Vec<_>>()
                .join(", "),
            document.evaluations,
            document.replayed,
            document.stop_reason
        );
    } else {
        say!(
            "best r = ({}) with J = {:.6} (original design: J = {:.6}); {} evaluations ({} replayed), {}; {}",
            document.best_ratios.iter().map(|r| format!("{r:.4}")).collect::<Vec<_>>().join(", "),
            document.best_cost,
            document.original_cost,
            document.evaluations,
            document.replayed,
            if document.median_solve_seconds.is_nan() {
                "no solve timed".to_owned()
            } else {
                format!("median solve {:.1} ms", document.median_solve_seconds * 1e3)
            },
            document.stop_reason
        );
    }
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
