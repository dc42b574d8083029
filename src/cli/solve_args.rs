//! The flags of `codesign solve` and what they make of a task: the design they name, the task's
//! motion with `--duration` and `--steps`, its problem, and a solve's errors in their words.

use super::choice::choice;
use super::common::{finite_ratio, ModelArgs, ProblemArgs};
use super::export::ExportArgs;
use super::failure::Failure;
use codesign_core::model::task::{Horizon, Task};
use codesign_core::model::Robot;
use codesign_core::problem::Formulation;
use codesign_core::solve::{FreeHorizonSearch, SolveError, SolveSettings, TrajectoryResult};
use codesign_core::text::listed;
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
    pub(super) ratios: Option<Vec<f64>>,
    /// Duration of the motion, s; default: the task's horizon.
    #[arg(long, value_name = "S")]
    pub(super) duration: Option<f64>,
    /// Number of intervals N; default: the task's steps.
    #[arg(long, value_name = "N")]
    pub(super) steps: Option<usize>,
    /// Solve the task's pure minimum-time problem instead, as `optimize --objective time` does
    /// for each design: its horizon freed (a fixed T to [0.3 T, 1.5 T]), J = T, no box; where
    /// the horizon is shortened (`--free-horizon descend`), through fixed-horizon problems
    /// with the task's own weights and box.
    #[arg(long, conflicts_with = "duration")]
    pub(super) minimum_time: bool,
    /// How a free horizon's duration is searched: `local`, the optimum the rule's first
    /// feasible start reaches; `descend`, that optimum shortened by the fixed-horizon rule
    /// (docs/model.md, section 6); default: the task's `solver.free_horizon`, else local.
    #[arg(long, value_parser = choice::<FreeHorizonSearch>(), value_name = "SEARCH")]
    pub(super) free_horizon: Option<FreeHorizonSearch>,
    /// Solve only this motion of the task's `motions` list, by its name, with every other flag;
    /// without it a task with a `motions` list solves each motion in turn, and takes none of
    /// `--out`, `--plot`, `--export`, `--start`, `--check-derivatives` (each is of one motion).
    #[arg(long, value_name = "NAME")]
    pub(super) motion: Option<String>,
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
    pub(super) elastic: bool,
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

/// The solve settings with the flags applied: `--linear-solver`, `--free-horizon`, `--verbose`.
pub(super) fn configure(args: &Args, settings: &mut SolveSettings) {
    args.problem.configure(settings);
    if let Some(search) = args.free_horizon {
        settings.free_horizon = search;
    }
    settings.verbose = args.verbose;
}

/// The task's motion with `--duration` and `--steps` applied.
pub(super) fn with_flags(args: &Args, mut task: Task) -> Task {
    if let Some(duration) = args.duration {
        task.motion.horizon = Horizon::Fixed(duration);
    }
    task.motion.steps = args.steps.unwrap_or(task.motion.steps);
    task
}

/// The problem of `task` on `robot` in the flags' space and modes, elastic with `--elastic`:
/// its pure minimum-time problem with `--minimum-time`.
pub(super) fn formulate(
    args: &Args,
    task: &Task,
    robot: Robot,
    settings: &SolveSettings,
) -> Result<Formulation, Failure> {
    let modes = args.problem.modes(task);
    let hard = if args.minimum_time {
        Formulation::minimum_time_of(task, robot, args.problem.space, modes)
    } else {
        Formulation::new(task, robot, args.problem.space, modes)
    };
    let hard =
        (hard.map_err(|e| e.to_string())?).with_hold_tolerance(settings.constraint_tolerance());
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
