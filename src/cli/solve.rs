//! `codesign solve`: one trajectory problem for one design.

use super::common::{finite_ratio, ModelArgs, ProblemArgs};
use super::export::ExportArgs;
use super::failure::{Failure, INFEASIBLE_EXIT};
use super::store_hints::check_output;
use crate::design::run::Loaded;
use crate::report::solve_document::{SolveDocument, StartRecord};
use crate::report::start::{read_start, StartFile};
use crate::report::trajectory::{every_plot_file, write_plots};
use crate::store::document::write_document;
use crate::store::files::check_folder;
use codesign_core::ipopt::{check_derivatives, DerivativeOrder};
use codesign_core::model::task::{check_horizon, check_steps, Horizon, PerMotor, Task};
use codesign_core::problem::{EndHold, Formulation, Space, StaticHold};
use codesign_core::solve::{
    least_envelope_margin, solve_design_from, CostTerms, ElasticMeasures, SolveError,
    SolveSettings, StartPoint, TrajectoryResult,
};
use codesign_core::text::{listed, number, rounded};
use std::path::PathBuf;

/// Flags of `codesign solve`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    problem: ProblemArgs,
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
    duration: Option<f64>,
    /// Number of intervals N; default: the task's steps.
    #[arg(long, value_name = "N")]
    steps: Option<usize>,
    /// Write the result as JSON to this file (checked before the solve; a symbolic link is
    /// followed, an input file, a folder, a special file or a file the user may not write
    /// refused; a file replaced keeps its permissions).
    #[arg(long, value_name = "FILE.json")]
    out: Option<PathBuf>,
    /// Draw SVG plots of the trajectory into this folder.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
    #[command(flatten)]
    export: ExportArgs,
    /// Show IPOPT's iteration log.
    #[arg(long)]
    verbose: bool,
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
    check_derivatives: bool,
    /// Start from the trajectory and multipliers of an earlier `solve --out` result of the same
    /// task, space, steps and kind (hard or `--elastic`): another design or payload converges
    /// in fewer iterations. A start that does not fit is refused, naming why; where the start
    /// finds no feasible trajectory, the cold starts follow as without it.
    #[arg(long, value_name = "FILE.json")]
    start: Option<PathBuf>,
    /// Exit with code 3 (after writing the result and plots) when the design is infeasible;
    /// without it an infeasible verdict, like a feasible one, exits 0.
    #[arg(long)]
    fail_if_infeasible: bool,
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
fn refuse_unwritable(result: &TrajectoryResult, source: &str) -> Result<(), Failure> {
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
fn design(args: &Args, task: &Task) -> (Vec<f64>, String) {
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
/// `--fail-if-infeasible` asks it to.
pub fn run(args: &Args) -> Result<(), Failure> {
    check_flags(args)?;
    let Loaded {
        mut task,
        robot,
        mut settings,
        task_hash,
    } = args.model.load()?;
    args.problem.configure(&mut settings);
    settings.verbose = args.verbose;
    if let Some(duration) = args.duration {
        task.motion.horizon = Horizon::Fixed(duration);
    }
    task.motion.steps = args.steps.unwrap_or(task.motion.steps);
    check_outputs(args, &task)?;
    let modes = args.problem.modes(&task);
    let hard = Formulation::new(&task, robot, args.problem.space, modes)
        .map_err(|e| e.to_string())?
        .with_hold_tolerance(settings.constraint_tolerance());
    let formulation = if args.elastic { hard.elastic() } else { hard };
    let (ratios, source) = design(args, &task);
    if args.check_derivatives {
        return Ok(check(&formulation, &settings, &ratios, &source)?);
    }
    let start = read_start_flag(args, &formulation, &task_hash)?;
    let warm = start.as_ref().map(|start| start.point.to_solution());
    let (result, solution) = solve_design_from(&formulation, &ratios, &settings, warm.as_ref())
        .map_err(|e| match e {
            SolveError::Design(_) => format!("{source}: {e}"),
            SolveError::Ipopt(_) => format!("{} solver: {e}", args.model.source()),
            SolveError::Formulation(_) | SolveError::Pose { .. } => {
                format!("{}: {e}", args.model.source())
            }
        })?;
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

/// `max motor torque 1.234 N m (limit 1.7)` where every motor has one limit, else each
/// motor's peak beside the motors' limits: `max motor torques (1.234, 0.5) N m (limits [1.7,
/// 0.9])`; (largest, peaks, decimals) of the trajectory.
fn peak_text(name: &str, unit: &str, peaks: (f64, &[f64], usize), limits: &PerMotor) -> String {
    let (largest, each, decimals) = peaks;
    match limits {
        PerMotor::All(_) => {
            format!("max motor {name} {largest:.decimals$} {unit} (limit {limits})")
        }
        PerMotor::Each(_) => {
            let texts: Vec<String> = each.iter().map(|p| format!("{p:.decimals$}")).collect();
            format!(
                "max motor {name}s ({}) {unit} (limits {limits})",
                texts.join(", ")
            )
        }
    }
}

/// A margin within this of 0, N m, is the envelope reached: IPOPT holds rows to about its `tol`.
const REACHED_NM: f64 = 1e-6;

/// The torque-speed envelope, for the summary (None without one): where the trajectory comes
/// closest to it, reaches it or exceeds it most.
fn envelope_text(formulation: &Formulation, result: &TrajectoryResult) -> Option<String> {
    let no_load = formulation.task().motors.no_load_speed_rad_s.as_ref()?;
    let least = least_envelope_margin(formulation, &result.trajectory)?;
    let margin = least.margin_nm;
    let state = if margin >= REACHED_NM {
        format!("least margin {margin:.3} N m")
    } else if margin > -REACHED_NM {
        format!("reached (margin {margin:.1e} N m)")
    } else {
        format!("EXCEEDED by {:.3e} N m", -margin)
    };
    Some(format!(
        "torque-speed envelope (no-load speed {no_load} rad/s): {state}, motor {} at t = {:.3} s",
        least.motor + 1,
        result.trajectory.time[least.node]
    ))
}

/// The load held at rest, for the summary: each end's least margin, or what it lacks.
fn hold_text(hold: &StaticHold) -> String {
    let judged = if hold.judged {
        ""
    } else {
        " (reported, not required: ends paper)"
    };
    if let Some(reason) = hold.reason() {
        return format!("static hold{judged}: {reason}");
    }
    let least = |end: &EndHold| end.margins_nm.iter().copied().fold(f64::INFINITY, f64::min);
    format!(
        "static hold: the load is held at rest at the start and the goal (least {} margin {:.3} and {:.3} N m)",
        hold.rows.name(),
        least(&hold.start),
        least(&hold.goal)
    )
}

/// Whether the motors can execute a joint-space trajectory, for the summary (None in the
/// actuation space, whose controls are the motors' own).
fn execute_text(formulation: &Formulation, result: &TrajectoryResult) -> Option<String> {
    let execute = result.motors_execute.as_ref()?;
    (formulation.space() == Space::Joint).then(|| {
        format!(
            "joint space, {} limits: {}",
            formulation.modes().torque.name(),
            execute.text()
        )
    })
}

/// `feasible (judged by solving the trajectory problem directly)`: the verdict and, in plain
/// words, the solve that gave it (docs/model.md, section 8); for a design infeasible by the
/// static hold alone, the hold, and the motion's own verdict after it.
fn verdict_text(result: &TrajectoryResult) -> String {
    if result.infeasible_by_hold_alone() {
        let motion =
            (result.verdict_by).map_or(String::new(), |by| format!(" ({})", by.describe(true)));
        return format!(
            "INFEASIBLE: the motors cannot hold the load at rest at an end (the static hold \
             below); the motion itself is feasible{motion}"
        );
    }
    let verdict = if result.feasible {
        "feasible"
    } else {
        "INFEASIBLE"
    };
    match result.verdict_by {
        Some(by) => format!("{verdict} ({})", by.describe(result.feasible)),
        None => verdict.to_owned(),
    }
}

/// What the relaxed (elastic) problem measured, in plain words with units.
fn elastic_text(elastic: &ElasticMeasures) -> String {
    format!(
        "relaxed problem (limits may give way, at a price added to J): over the motion the \
         motors lack {} N m s of torque and exceed their speed limits by {} rad, at one node by \
         at most {} N m or rad/s; J with the price {:.6}",
        rounded(elastic.torque_deficit),
        rounded(elastic.speed_excess),
        rounded(elastic.largest_slack),
        elastic.objective
    )
}

/// Each ratio of the design at a bound of the design space, with dJ*/dr_i there.
fn print_bounds(formulation: &Formulation, result: &TrajectoryResult) {
    let space = formulation.transmission().design_space();
    for bound in space.active_bounds(&result.ratios, result.cost_gradient.as_deref()) {
        say!("  at its bounds: {bound}");
    }
}

fn print_summary(formulation: &Formulation, result: &TrajectoryResult) {
    let task = formulation.task();
    say!(
        "{} space, r = ({}), payload {} kg: {} in {} iterations, J = {:.6}",
        formulation.space(),
        result
            .ratios
            .iter()
            .map(|r| format!("{r}"))
            .collect::<Vec<_>>()
            .join(", "),
        task.payload.mass_kg,
        result.status,
        result.iterations,
        result.cost
    );
    let t = &result.trajectory;
    say!(
        "  {}; {}, {}",
        verdict_text(result),
        peak_text(
            "torque",
            "N m",
            (result.max_motor_torque, &t.motor_torque_peaks(), 3),
            &task.motors.torque_limit_nm
        ),
        peak_text(
            "speed",
            "rad/s",
            (result.max_motor_speed, &t.motor_speed_peaks(), 1),
            &task.motors.speed_limit_rad_s
        )
    );
    if let Some(text) = envelope_text(formulation, result) {
        say!("  {text}");
    }
    print_bounds(formulation, result);
    if let Some(hold) = &result.static_hold {
        say!("  {}", hold_text(hold));
    }
    if let Some(text) = execute_text(formulation, result) {
        say!("  {text}");
    }
    if let Some(elastic) = &result.elastic {
        say!("  {}", elastic_text(elastic));
    }
    if let Some(horizon) = result.horizon_s {
        say!("  free horizon: T* = {horizon:.6} s");
    }
    if let Some(t) = &result.cost_terms {
        say!("  {}", cost_terms_text(t));
    }
    let s = &result.solve_seconds;
    say!(
        "  solve {:.1} ms (callbacks {:.1} ms, IPOPT {:.1} ms)",
        s.total * 1e3,
        s.callbacks * 1e3,
        s.ipopt * 1e3
    );
}

/// "J by term: ..." with the largest named; the duration's term only where it counts.
fn cost_terms_text(t: &CostTerms) -> String {
    let mut terms = vec![
        ("position", t.position),
        ("velocity", t.velocity),
        ("control", t.control),
        ("box", t.cartesian_box),
    ];
    if t.time != 0.0 {
        terms.push(("time", t.time));
    }
    let largest = terms
        .iter()
        .fold(terms[0], |m, &t| if t.1 > m.1 { t } else { m });
    let listed: Vec<String> = terms
        .iter()
        .map(|(name, value)| format!("{name} {value:.4}"))
        .collect();
    format!(
        "J by term: {} (the largest: {})",
        listed.join(", "),
        largest.0
    )
}
