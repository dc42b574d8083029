//! `codesign solve`: one trajectory problem for one design (each motion's, for a task with
//! several: `solve_motions`).

use super::common::{finite_ratio, ModelArgs, ProblemArgs};
use super::export::ExportArgs;
use super::failure::{Failure, INFEASIBLE_EXIT};
use super::solve_motions::{pick_motion, solve_each};
use super::solve_summary::print_summary;
use super::store_hints::check_output;
use crate::design::run::Loaded;
use crate::report::solve_document::{SolveDocument, StartRecord};
use crate::report::start::{read_start, StartFile};
use crate::report::trajectory::{every_plot_file, write_plots};
use crate::store::document::write_document;
use crate::store::files::check_folder;
use codesign_core::ipopt::{check_derivatives, DerivativeOrder};
use codesign_core::model::task::{check_horizon, check_steps, Horizon, Task};
use codesign_core::model::Robot;
use codesign_core::problem::Formulation;
use codesign_core::solve::{
    solve_design_from, SolveError, SolveSettings, StartPoint, TrajectoryResult,
};
use codesign_core::text::{listed, number};
use std::path::PathBuf;

/// Flags of `codesign solve`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub(super) model: ModelArgs,
    #[command(flatten)]
    pub(super) problem: ProblemArgs,
    /// Gear ratios of the design, one per ratio of the task's transmission (r1,r2,..); default:
    /// the task's original design.
    #[arg(
        long,
        value_name = "R1,R2,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = finite_ratio
    )]
    ratios: Option<Vec<f64>>,
    /// Duration of the motion, s; default: the task's horizon.
    #[arg(long, value_name = "S")]
    pub(super) duration: Option<f64>,
    /// Number of intervals N; default: the task's steps.
    #[arg(long, value_name = "N")]
    pub(super) steps: Option<usize>,
    /// Solve only this motion of the task's `motions` list, by its name, with every other flag;
    /// without it a task with a `motions` list solves each motion in turn, and takes none of
    /// `--out`, `--plot`, `--export`, `--start`, `--check-derivatives` (each is of one motion).
    #[arg(long, value_name = "NAME")]
    motion: Option<String>,
    /// Write the result as JSON to this file (checked before the solve; a symbolic link is
    /// followed, an input file, a folder, a special file or a file the user may not write
    /// refused; a file replaced keeps its permissions).
    #[arg(long, value_name = "FILE.json")]
    pub(super) out: Option<PathBuf>,
    /// Draw SVG plots of the trajectory into this folder.
    #[arg(long, value_name = "DIR")]
    pub(super) plot: Option<PathBuf>,
    #[command(flatten)]
    pub(super) export: ExportArgs,
    /// Show IPOPT's iteration log.
    #[arg(long)]
    pub(super) verbose: bool,
    /// Solve the elastic problem (docs/model.md, section 14): always feasible, it reports the
    /// torque the design lacks and the speed above its limit instead of failing.
    #[arg(long)]
    elastic: bool,
    /// Instead of solving, run IPOPT's derivative checker (first and second order) at the
    /// initial guess and report what it flags. IPOPT 3.11's checker takes about 13 minutes on
    /// the full 50-step problem: `--steps 5` checks the same structure in 0.1 s. It writes no
    /// result, plot or export, so it takes none of `--out`, `--plot`, `--export`.
    #[arg(
        long,
        conflicts_with_all = ["out", "plot", "export", "rate", "start", "fail_if_infeasible"]
    )]
    pub(super) check_derivatives: bool,
    /// Start from the trajectory and multipliers of an earlier `solve --out` result of the same
    /// task, space, steps and kind (hard or `--elastic`): another design or payload converges
    /// in fewer iterations. A start that does not fit is refused, naming why; where the start
    /// finds no feasible trajectory, the cold starts follow as without it.
    #[arg(long, value_name = "FILE.json")]
    pub(super) start: Option<PathBuf>,
    /// Exit with code 3 (after writing the result and plots) when the design is infeasible;
    /// without it an infeasible verdict, like a feasible one, exits 0.
    #[arg(long)]
    pub(super) fail_if_infeasible: bool,
}

/// Checks, before any solve, that `--out`, the files of `--plot` and `--export` can be written
/// and are none of the inputs of `task` (`--start` among them), and that `--rate` makes an
/// export.
fn check_outputs(args: &Args, task: &Task) -> Result<(), Failure> {
    let choice = args.model.choice();
    let mut inputs = choice.inputs(task);
    inputs.extend(args.start.as_deref().map(|path| ("--start", path)));
    if let Some(path) = &args.out {
        check_output("--out", path, &inputs)?;
    }
    if let Some(folder) = &args.plot {
        check_folder(folder).map_err(|e| format!("--plot: {e}"))?;
        // A folder not made yet holds nothing to protect.
        let motors = task.transmission.matrix.len();
        for name in every_plot_file(motors).iter().filter(|_| folder.is_dir()) {
            check_output("--plot", &folder.join(name), &inputs)?;
        }
    }
    // A free horizon's rows are bounded by its longest duration.
    let duration = task.motion.horizon.initial_s();
    args.export.check(duration, args.out.as_deref(), &inputs)
}

/// Checks the flags that need no file: `--payload`, `--duration`, `--steps`.
fn check_flags(args: &Args) -> Result<(), Failure> {
    args.model.validate()?;
    if let Some(duration) = args.duration {
        check_horizon(duration)
            .map_err(|why| Failure::Usage(format!("--duration {}: {why}", number(duration))))?;
    }
    if let Some(steps) = args.steps {
        check_steps(steps).map_err(|why| Failure::Usage(format!("--steps {steps}: {why}")))?;
    }
    Ok(())
}

/// Fails, naming the design by `source`, where `result` is no result to report: a number in it
/// is not finite, or it judges no design.
pub(super) fn refuse_unwritable(result: &TrajectoryResult, source: &str) -> Result<(), Failure> {
    if let Some(part) = result.non_finite() {
        return Err(Failure::from(format!(
            "{source}: the solve (IPOPT status {}) gave a result whose {part} holds a number \
             that is not finite (infinite or NaN); no result is written",
            result.status
        )));
    }
    if let Some(why) = result.unjudged() {
        return Err(Failure::from(format!(
            "{source}: {why}; no result is written (raise solver.max_iter, or see IPOPT's log \
             with --verbose)"
        )));
    }
    Ok(())
}

/// The design to solve, `--ratios` or the task's original one, with the words that name it.
pub(super) fn design(args: &Args, task: &Task) -> (Vec<f64>, String) {
    match &args.ratios {
        Some(ratios) => (ratios.clone(), format!("--ratios {}", listed(ratios))),
        None => (
            task.transmission.original.clone(),
            format!(
                "{} transmission.original ({})",
                args.model.source(),
                listed(&task.transmission.original)
            ),
        ),
    }
}

/// The start of `--start`, read and checked to fit `formulation` for the task of `task_hash`.
fn read_start_flag(
    args: &Args,
    formulation: &Formulation,
    task_hash: &str,
) -> Result<Option<StartFile>, Failure> {
    let Some(path) = &args.start else {
        return Ok(None);
    };
    let start = read_start(path, formulation, task_hash).map_err(|e| format!("--start {e}"))?;
    Ok(Some(start))
}

/// Solves, prints a summary, writes the requested files; fails after writing them where
/// `--fail-if-infeasible` asks it to. A task with a `motions` list solves the motion of
/// `--motion`, or each in turn.
pub fn run(args: &Args) -> Result<(), Failure> {
    check_flags(args)?;
    let loaded = args.model.load()?;
    match &args.motion {
        Some(name) => solve_one(args, pick_motion(loaded, name)?),
        None if loaded.task.has_motions() => solve_each(args, loaded),
        None => solve_one(args, loaded),
    }
}

/// The task's motion with `--duration` and `--steps` applied.
pub(super) fn with_flags(args: &Args, mut task: Task) -> Task {
    if let Some(duration) = args.duration {
        task.motion.horizon = Horizon::Fixed(duration);
    }
    task.motion.steps = args.steps.unwrap_or(task.motion.steps);
    task
}

/// The problem of `task` on `robot` in the flags' space and modes, elastic with `--elastic`.
pub(super) fn formulate(
    args: &Args,
    task: &Task,
    robot: Robot,
    settings: &SolveSettings,
) -> Result<Formulation, Failure> {
    let modes = args.problem.modes(task);
    let hard = Formulation::new(task, robot, args.problem.space, modes)
        .map_err(|e| e.to_string())?
        .with_hold_tolerance(settings.constraint_tolerance());
    Ok(if args.elastic { hard.elastic() } else { hard })
}

/// A solve's error in words, naming the design by `source`, the task or its solver settings.
pub(super) fn solve_error(args: &Args, source: &str, error: SolveError) -> Failure {
    Failure::from(match error {
        SolveError::Design(_) => format!("{source}: {error}"),
        SolveError::Ipopt(_) => format!("{} solver: {error}", args.model.source()),
        SolveError::Formulation(_) | SolveError::Pose { .. } => {
            format!("{}: {error}", args.model.source())
        }
    })
}

/// Solves the one motion of `loaded`'s task, prints its summary, writes the requested files.
fn solve_one(args: &Args, loaded: Loaded) -> Result<(), Failure> {
    let Loaded {
        task,
        robot,
        mut settings,
        task_hash,
    } = loaded;
    args.problem.configure(&mut settings);
    settings.verbose = args.verbose;
    let task = with_flags(args, task);
    check_outputs(args, &task)?;
    let formulation = formulate(args, &task, robot, &settings)?;
    let (ratios, source) = design(args, &task);
    if args.check_derivatives {
        return Ok(check(&formulation, &settings, &ratios, &source)?);
    }
    let start = read_start_flag(args, &formulation, &task_hash)?;
    let warm = start.as_ref().map(|start| start.point.to_solution());
    let (result, solution) = solve_design_from(&formulation, &ratios, &settings, warm.as_ref())
        .map_err(|e| solve_error(args, &source, e))?;
    refuse_unwritable(&result, &source)?;
    print_summary(&formulation, &result);
    if let Some(start) = &start {
        say!("  {}", start_text(&start.record));
    }
    let verdict = (!result.feasible).then(|| result.reason.clone().unwrap_or_default());
    let point = StartPoint::from_solution(&solution, &formulation, &task_hash);
    write_outputs(
        args,
        &formulation,
        &settings,
        &task_hash,
        result,
        point,
        start,
    )?;
    match verdict {
        Some(reason) if args.fail_if_infeasible => Err(Failure::Infeasible(format!(
            "{source}: the design is infeasible ({reason}); --fail-if-infeasible makes that \
             exit {INFEASIBLE_EXIT}"
        ))),
        _ => Ok(()),
    }
}

/// `started from FILE (its design r = (..), payload .. kg)`: the start, for the summary.
fn start_text(record: &StartRecord) -> String {
    let ratios: Vec<String> = record.ratios.iter().map(|r| r.to_string()).collect();
    format!(
        "started from {} (its design r = ({}), payload {} kg)",
        record.file,
        ratios.join(", "),
        number(record.payload_kg)
    )
}

/// Writes the plots of `--plot`, the export of `--export` and the result of `--out`, with `point` (the raw solution, to
/// start another solve from) and the record of `start`.
fn write_outputs(
    args: &Args,
    formulation: &Formulation,
    settings: &SolveSettings,
    task_hash: &str,
    result: TrajectoryResult,
    point: StartPoint,
    start: Option<StartFile>,
) -> Result<(), Failure> {
    if let Some(folder) = &args.plot {
        write_plots(folder, formulation, &result).map_err(|e| e.to_string())?;
        say!("plots written to {}", folder.display());
    }
    args.export.write(formulation, &result)?;
    if let Some(path) = &args.out {
        let label = args.model.source().label();
        let mut document = SolveDocument::new(&label, task_hash, formulation, settings, result);
        // Only a point that could start this very problem again is kept.
        if point.check_fits(formulation, task_hash).is_ok() {
            document = document.with_start_point(point);
        }
        if let Some(start) = start {
            document = document.started_from(start.record);
        }
        write_document(path, &document).map_err(|e| e.to_string())?;
        say!("result written to {}", path.display());
    }
    Ok(())
}

/// Runs IPOPT's second-order derivative checker at the initial guess of design `ratios`.
fn check(
    formulation: &Formulation,
    settings: &SolveSettings,
    ratios: &[f64],
    source: &str,
) -> Result<(), String> {
    let mut problem = formulation
        .problem(ratios)
        .map_err(|e| format!("{source}: invalid design: {e}"))?;
    let options = settings
        .ipopt_options()
        .num("point_perturbation_radius", 0.0);
    say!(
        "running IPOPT's derivative checker on {} steps: IPOPT 3.11's second-order check \
         scans the whole Hessian for every constraint and variable, so its time grows as the \
         fourth power of the steps (about 13 minutes at 50, 0.1 s at --steps 5, which checks \
         the same formulas at every node)",
        formulation.task().motion.steps
    );
    let started = std::time::Instant::now();
    let report = check_derivatives(&mut problem, &options, DerivativeOrder::Second)
        .map_err(|e| e.to_string())?;
    say!(
        "IPOPT derivative checker ({} space, first and second order, at the initial guess): {} error(s) in {:.1} s",
        formulation.space(),
        report.errors,
        started.elapsed().as_secs_f64()
    );
    for line in &report.flagged {
        say!("  {line}");
    }
    if report.errors > 0 {
        return Err(format!(
            "the derivative checker flagged {} entries",
            report.errors
        ));
    }
    Ok(())
}
