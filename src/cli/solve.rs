//! `codesign solve`: one trajectory problem for one design (each motion's, for a task with
//! several: `solve_motions`).

use super::failure::{Failure, INFEASIBLE_EXIT};
use super::solve_args::{
    configure, design, formulate, refuse_unwritable, solve_error, with_flags, Args,
};
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
use codesign_core::model::task::{check_horizon, check_steps, Task};
use codesign_core::problem::Formulation;
use codesign_core::solve::{solve_design_from, SolveSettings, StartPoint, TrajectoryResult};
use codesign_core::text::number;

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

/// Solves the one motion of `loaded`'s task, prints its summary, writes the requested files.
fn solve_one(args: &Args, loaded: Loaded) -> Result<(), Failure> {
    let Loaded {
        task,
        robot,
        mut settings,
        task_hash,
    } = loaded;
    configure(args, &mut settings);
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
