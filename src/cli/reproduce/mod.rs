//! `codesign reproduce`: the task's experiment, by default the paper's (docs/model.md, section
//! 13), end to end.

mod commands;
mod merge;
mod stages;

use super::failure::Failure;
use super::store_hints::{check_output, hint};
use crate::cli::run_flags::{case_error, RunArgs};
use crate::design::run::{task_source, OptimizeDocument};
use crate::design::run::{Method, RunSettings};
use crate::experiment::CapacityOf;
use crate::experiment::{Plan, PlanError, PlanRequest, SPACES};
use crate::ipopt::LinearSolver;
use crate::model::experiment::Budget;
use crate::model::identity::task_hash;
use crate::model::task::{Ends, Task, TaskFile};
use crate::model::Robot;
use crate::problem::Space;
use crate::report::codesign::{cost_evolution_chart, ratio_chart, CapacityDocument};
use crate::report::index::write_index;
use crate::report::plots::Figure;
use crate::report::table::{build_table, PaperTable, ResultFile};
use crate::report::trajectory::write_plots;
use crate::solve::{SolveSettings, TrajectoryResult};
use crate::store::document::write_document;
use crate::store::files::{create_folder, remove_stale, write_atomic};
use crate::store::lock::lock_folder;
use crate::store::log::{Start, LOG_EXTENSION};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Flags of `codesign reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A reduced run that ends in minutes, on the task's `experiment.quick_budget` (the
    /// paper's task: population 16, 8 generations, 2 seeds), written to results/quick/ unless
    /// --out-dir is given; labelled as reduced in the table.
    #[arg(long)]
    quick: bool,
    /// Seeds of CMA-ES per case (0..N); default: the task's experiment's (the paper's 5, 2 with
    /// --quick).
    #[arg(long, value_name = "N")]
    seeds: Option<u64>,
    /// CMA-ES population; default: the task's experiment's (the paper's 100, 16 with --quick).
    #[arg(long)]
    population: Option<usize>,
    /// CMA-ES generations; default: the task's experiment's (the paper's 30, 8 with --quick).
    #[arg(long)]
    generations: Option<usize>,
    /// Output folder; default results/ (results/quick/ with --quick). Locked while the
    /// reproduction runs: a second one on the same folder fails at once.
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
    /// Task file, its optional `experiment` section saying which payloads, seeds and budgets
    /// to run [default: the built-in task, which `codesign task` prints, and the paper's
    /// experiment].
    #[arg(long, value_name = "FILE")]
    task: Option<PathBuf>,
    /// Linear solver inside IPOPT; default: the task's `solver.linear_solver`, else ldl.
    #[arg(long, value_enum, value_name = "SOLVER")]
    linear_solver: Option<LinearSolver>,
    /// The CMA-ES runs' bound handling and warm starts, and their workers (as `optimize`'s).
    #[command(flatten)]
    run: RunArgs,
    /// What the motion asks at its ends in every run (see `solve --ends`); default: the task's
    /// `motion.ends` (the built-in task's: paper). Under `paper`, Table II's cases are solved
    /// under `hold` as well, in OUT_DIR/hold/, for the table's section on holding the load.
    #[arg(long, value_enum, value_name = "ENDS")]
    ends: Option<Ends>,
    /// Continue an interrupted reproduction from its evaluation logs.
    #[arg(long)]
    resume: bool,
    /// Start afresh even if the output folder holds an earlier reproduction's evaluation logs
    /// (they are replaced case by case as the new runs start).
    #[arg(long, conflicts_with = "resume")]
    overwrite: bool,
    /// Print the experiment's independent commands, one a line, instead of running them (each
    /// co-design run an `optimize` with its own --out, one worker unless --workers is given,
    /// resuming its log when run again), after creating the output folder they write into; run
    /// them with GNU parallel or a Slurm job array, then `reproduce --from-runs DIR` with the
    /// same flags.
    #[arg(long, conflicts_with_all = ["from_runs", "resume", "overwrite"])]
    plan: bool,
    /// Finish an experiment whose planned commands have run: read their results in DIR, search
    /// the capacities of the best designs, and write the table and plots as `reproduce` does.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["out_dir", "resume", "overwrite"])]
    from_runs: Option<PathBuf>,
}

impl Args {
    /// What these flags ask of the task's experiment.
    fn request(&self) -> PlanRequest {
        let mut cmaes = RunSettings::new(Method::Cmaes);
        self.run.apply(&mut cmaes);
        PlanRequest {
            quick: self.quick,
            seeds: self.seeds,
            population: self.population,
            generations: self.generations,
            folder: self.from_runs.clone().or_else(|| self.out_dir.clone()),
            task: self.task.clone(),
            linear_solver: self.linear_solver,
            cmaes,
            execution: self
                .run
                .execution(Start::from_flags(self.resume, self.overwrite)),
            ends: self.ends,
        }
    }
}

/// A plan's error: a usage error naming the flag, or the task file's.
fn plan_error(error: PlanError) -> Failure {
    match error {
        PlanError::Request(error) => case_error(error),
        PlanError::Task(message) => Failure::Work(message),
    }
}

/// What the experiment's independent stages produced, in this process or by the plan's
/// commands elsewhere.
pub struct Outcomes {
    /// The original designs' solves, per payload and space.
    originals: Vec<ResultFile>,
    /// The paper's co-design runs, per payload, space and seed.
    runs: Vec<OptimizeDocument>,
    /// The gradient method's runs that found a feasible start.
    gradient_runs: Vec<OptimizeDocument>,
    /// The CMA-ES runs beyond the paper: the capacity designs per space, the payload range.
    beyond_runs: Vec<OptimizeDocument>,
    /// The original design's capacity, per space.
    original_capacities: Vec<CapacityDocument>,
}

/// Runs the experiment (or prints its plan, or merges its results) and writes results, table
/// and plots.
pub fn run(args: &Args) -> Result<(), Failure> {
    let started = Instant::now();
    // The task and its solver and experiment sections are checked before anything is planned or
    // written.
    let file = task_source(args.task.as_ref())
        .load()
        .map_err(|e| e.to_string())?;
    let plan = Plan::new(
        &args.request(),
        file.experiment.clone(),
        file.task.motion.ends,
    )
    .map_err(plan_error)?;
    if let Some(folder) = &args.from_runs {
        if !folder.is_dir() {
            return Err(Failure::Work(format!(
                "--from-runs {}: not a folder; give the --out-dir that the plan's commands wrote \
                 into",
                folder.display()
            )));
        }
    }
    let task = load_task(&plan, file.clone())?;
    let hold = match plan.hold_section() {
        Some(hold) => Some((load_task(&hold, file)?, hold)),
        None => None,
    };
    if args.plan {
        let program = std::env::current_exe()
            .map_err(|e| format!("cannot locate the codesign executable: {e}"))?;
        // The commands write into these folders, on whichever machine runs them.
        for section in sections(&plan, hold.as_ref()) {
            create_folder(section.out_dir()).map_err(|e| e.to_string())?;
            for folder in section.layout.folders() {
                create_folder(&folder).map_err(|e| e.to_string())?;
            }
        }
        for line in commands::commands(&plan, &program.to_string_lossy()) {
            say!("{line}");
        }
        return Ok(());
    }
    create_folder(plan.out_dir()).map_err(|e| e.to_string())?;
    // Held until the reproduction ends: a second one on the same folder fails at once.
    let _lock = lock_folder(plan.out_dir()).map_err(|e| hint(e, "--out-dir"))?;
    let task_file = plan.task.iter().map(|path| ("--task", path.as_path()));
    let robot = task.task.robot.iter().map(|path| ("robot", path.as_path()));
    let merged = args.from_runs.is_some();
    // Under --from-runs the results the plan's commands wrote are inputs: no output may be one,
    // through a symbolic link either.
    let read: Vec<PathBuf> = match merged {
        true => sections(&plan, hold.as_ref())
            .flat_map(Plan::merged_inputs)
            .collect(),
        false => Vec::new(),
    };
    let results = read.iter().map(|path| ("--from-runs", path.as_path()));
    let inputs: Vec<(&str, &Path)> = task_file.chain(robot).chain(results).collect();
    let flag = if merged { "--from-runs" } else { "--out-dir" };
    for output in sections(&plan, hold.as_ref()).flat_map(Plan::outputs) {
        if !read.contains(&output) {
            check_output(flag, &output, &inputs)?;
        }
    }
    let outcomes = section_outcomes(&plan, &task, merged)?;
    let hold_table = match &hold {
        Some((hold_task, hold)) => {
            let outcomes = section_outcomes(hold, hold_task, merged)?;
            let seconds = started.elapsed().as_secs_f64();
            Some(finish(hold, hold_task, outcomes, merged, seconds, None)?)
        }
        None => None,
    };
    let seconds = started.elapsed().as_secs_f64();
    finish(&plan, &task, outcomes, merged, seconds, hold_table.as_ref())?;
    Ok(())
}

/// The experiment's sections: `plan`, then its hold section when it has one.
fn sections<'a>(
    plan: &'a Plan,
    hold: Option<&'a (ExperimentTask, Plan)>,
) -> impl Iterator<Item = &'a Plan> {
    std::iter::once(plan).chain(hold.map(|(_, plan)| plan))
}

/// The independent stages of one section of the experiment (Table II and beyond, or Table II
/// under `hold`): read back from the plan's commands' results (`merged`), or run here.
fn section_outcomes(plan: &Plan, task: &ExperimentTask, merged: bool) -> Result<Outcomes, String> {
    if merged {
        return merge::read_all(plan, &task.hash);
    }
    if plan.execution.start == Start::Fresh {
        refuse_earlier_logs(&plan.layout.runs())?;
    }
    create_folder(plan.out_dir()).map_err(|e| e.to_string())?;
    for folder in plan.layout.folders() {
        create_folder(&folder).map_err(|e| e.to_string())?;
    }
    stages::run_all(plan, task)
}

/// The experiment's task, checked with its robot.
pub struct ExperimentTask {
    /// The task as read.
    pub task: Task,
    /// Its solve settings, the plan's linear solver applied.
    pub solver: SolveSettings,
    /// Its task hash on its robot (`model::identity::task_hash`).
    pub hash: String,
}

/// The plan's task from its `file` (the plan's ends applied), its solve settings (the plan's
/// linear solver applied) and its task hash, checked with its robot.
fn load_task(plan: &Plan, mut file: TaskFile) -> Result<ExperimentTask, String> {
    file.task.motion.ends = plan.ends;
    let source = task_source(plan.task.as_ref());
    let mut solver =
        SolveSettings::from_section(file.solver.as_ref()).map_err(|e| format!("{source}: {e}"))?;
    solver.override_linear_solver(plan.linear_solver);
    let robot = Robot::load(&file.task).map_err(|e| e.to_string())?;
    Ok(ExperimentTask {
        hash: task_hash(&file.task, robot.urdf_hash()),
        task: file.task,
        solver,
    })
}

/// The stages that need every run: the best designs' plots and capacities, the radar chart, and
/// the table, with `hold`, the table of the same cases under `hold`, as a section of it.
fn finish(
    plan: &Plan,
    task: &ExperimentTask,
    outcomes: Outcomes,
    merged: bool,
    seconds: f64,
    hold: Option<&PaperTable>,
) -> Result<PaperTable, String> {
    create_folder(&plan.layout.capacities()).map_err(|e| e.to_string())?;
    write_case_plots(plan, task, &outcomes.runs)?;
    let mut capacities = outcomes.original_capacities;
    capacities.extend(best_capacities(plan, task, &outcomes.runs)?);
    let runs = outcomes.runs;
    let beyond: Vec<&OptimizeDocument> = outcomes
        .gradient_runs
        .iter()
        .chain(&outcomes.beyond_runs)
        .collect();
    let time_note = if merged {
        merged_note(plan.out_dir(), runs.iter().chain(beyond.iter().copied()))
    } else {
        // Resumed runs' earlier invocations, from their logs (the capacity co-design runs too).
        let earlier: Option<f64> = runs
            .iter()
            .chain(outcomes.beyond_runs.iter())
            .map(|d| d.earlier_seconds)
            .sum();
        let replayed: usize = runs.iter().map(|d| d.replayed).sum();
        wall_time_note(seconds, replayed, earlier)
    };
    let mut files = outcomes.originals;
    files.extend(
        beyond
            .into_iter()
            .map(|d| ResultFile::Optimize(Box::new(d.clone()))),
    );
    files.extend(
        capacities
            .into_iter()
            .map(|d| ResultFile::Capacity(Box::new(d))),
    );
    files.extend(runs.into_iter().map(|d| ResultFile::Optimize(Box::new(d))));
    let mut notes = Vec::new();
    if !plan.experiment.is_paper() {
        notes.push(format!(
            "The experiment of the task's `experiment` section: {}.",
            plan.experiment.describe()
        ));
    }
    if plan.is_reduced() {
        let (b, full) = (&plan.budget, &plan.experiment.budget);
        let whose = if *full == Budget::PAPER {
            "the paper's"
        } else {
            "the experiment's full budget's"
        };
        notes.push(format!(
            "REDUCED RUN: population {}, {} generations, {} seed(s), against {whose} {}, {} and {}. \
             Run `codesign reproduce` without --quick for the full experiment.",
            b.population, b.generations, b.seeds, full.population, full.generations, full.seeds
        ));
    }
    notes.push(time_note);
    let mut table = build_table(&files, notes);
    if let Some(hold) = hold {
        table.add_hold_section(hold);
    }
    write_atomic(
        &plan.layout.table_markdown(),
        table.to_markdown().as_bytes(),
    )
    .map_err(|e| e.to_string())?;
    write_document(&plan.layout.table_json(), &table).map_err(|e| e.to_string())?;
    write_index(&plan.layout, &table).map_err(|e| e.to_string())?;
    say_raw!("{}", table.to_markdown());
    say!("results written to {}", plan.out_dir().display());
    Ok(table)
}

/// The time note of a merged reproduction: the co-design runs' working time, summed.
fn merged_note<'a>(folder: &Path, runs: impl Iterator<Item = &'a OptimizeDocument>) -> String {
    let seconds: f64 = runs
        .map(|d| d.wall_seconds + d.earlier_seconds.unwrap_or(0.0))
        .sum();
    format!(
        "Merged by `reproduce --from-runs` from the results in {} that the commands of \
         `reproduce --plan` wrote; the co-design runs' working time sums to {:.1} min.",
        folder.display(),
        seconds / 60.0
    )
}

/// The best feasible solve of the co-design runs at `payload` in `space`.
fn best_of(runs: &[OptimizeDocument], payload: f64, space: Space) -> Option<&TrajectoryResult> {
    runs.iter()
        .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
        .filter_map(|d| d.best_result.as_ref().filter(|r| r.feasible))
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
}

/// The payload capacity of each co-designed case's best design; a case without a feasible
/// design has none, and an earlier reproduction's file for it is removed.
fn best_capacities(
    plan: &Plan,
    task: &ExperimentTask,
    runs: &[OptimizeDocument],
) -> Result<Vec<CapacityDocument>, String> {
    let mut capacities = Vec::new();
    for &payload in &plan.experiment.codesign_payloads_kg {
        for space in SPACES {
            let of = CapacityOf::Best(space, payload);
            if let Some(best) = best_of(runs, payload, space) {
                let ratios = best.ratios.clone();
                capacities.push(stages::capacity_document(plan, task, space, ratios, of)?);
            } else {
                remove_stale_output(&plan.layout.capacity(of))?;
            }
        }
    }
    Ok(capacities)
}

/// Removes an output an earlier reproduction wrote for a case that has no feasible design now
/// (its best design's plots or capacity), so that no file describes a design the table does not
/// name; says so.
fn remove_stale_output(path: &Path) -> Result<(), String> {
    if remove_stale(path).map_err(|e| e.to_string())? {
        say!(
            "removed {}: its case has no feasible design in this reproduction",
            path.display()
        );
    }
    Ok(())
}

/// Per case: the cost evolution of its seeds and the plots of its best design; and the radar
/// (or bar) chart of every case's best ratios.
fn write_case_plots(
    plan: &Plan,
    task: &ExperimentTask,
    runs: &[OptimizeDocument],
) -> Result<(), String> {
    create_folder(&plan.layout.plots()).map_err(|e| e.to_string())?;
    let mut radar_cases = Vec::new();
    for &payload in &plan.experiment.codesign_payloads_kg {
        for space in SPACES {
            let case: Vec<&OptimizeDocument> = runs
                .iter()
                .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
                .collect();
            let title = format!("CMA-ES cost per evaluation: {space} space, {payload} kg");
            cost_evolution_chart(&title, &case)
                .write(&plan.layout.cost_evolution(space, payload))?;
            let folder = plan.layout.best_plots(space, payload);
            if let Some(best) = best_of(runs, payload, space) {
                let formulation = stages::formulation_at(task, payload, space)?;
                write_plots(&folder, &formulation, best)?;
                radar_cases.push((format!("{space}, {payload} kg"), best.ratios.clone()));
            } else {
                remove_stale_output(&folder)?;
            }
        }
    }
    let upper: Vec<f64> = task.task.transmission.bounds.iter().map(|b| b[1]).collect();
    let ratios = ratio_chart(
        "Optimal gear ratios (r_i / upper bound)",
        &radar_cases,
        &upper,
    );
    Ok(ratios.write(&plan.layout.optimal_ratios())?)
}

/// Fails, naming a log and the two ways on, when `runs` holds evaluation logs of an earlier
/// reproduction (a missing folder holds none).
fn refuse_earlier_logs(runs: &Path) -> Result<(), String> {
    let Ok(entries) = std::fs::read_dir(runs) else {
        return Ok(());
    };
    let suffix = format!(".{LOG_EXTENSION}");
    let mut logs: Vec<PathBuf> = entries
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.to_string_lossy().ends_with(&suffix))
        .collect();
    logs.sort();
    match logs.first() {
        None => Ok(()),
        Some(first) => Err(format!(
            "{} holds the evaluation logs of an earlier reproduction ({} and {} more): pass \
             --resume to continue it (finished evaluations are replayed) or --overwrite to start \
             afresh",
            runs.display(),
            first.display(),
            logs.len() - 1
        )),
    }
}

/// How long the reproduction took, s: this invocation's `seconds`, plus, when it resumed an
/// interrupted reproduction (`replayed` evaluations), the `earlier` working time of the resumed
/// runs where their logs record it.
fn wall_time_note(seconds: f64, replayed: usize, earlier: Option<f64>) -> String {
    let minutes = seconds / 60.0;
    match earlier {
        _ if replayed == 0 => format!("Wall time of this reproduction: {minutes:.1} min."),
        Some(earlier) => format!(
            "Wall time of this reproduction: {:.1} min over its invocations ({minutes:.1} min in \
             the last, which resumed it and replayed {replayed} CMA-ES evaluations from their \
             logs; idle time between invocations not counted).",
            minutes + earlier / 60.0
        ),
        None => format!(
            "Wall time of this invocation: {minutes:.1} min. It resumed an interrupted \
             reproduction and replayed {replayed} CMA-ES evaluations from their logs, some of \
             which predate the record of working time, so the earlier invocations' time is not \
             included."
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{refuse_earlier_logs, wall_time_note};

    #[test]
    fn wall_time_counts_earlier_invocations_where_logged() {
        assert_eq!(
            wall_time_note(90.0, 0, Some(0.0)),
            "Wall time of this reproduction: 1.5 min."
        );
        let resumed = wall_time_note(60.0, 40, Some(3540.0));
        assert!(resumed.starts_with("Wall time of this reproduction: 60.0 min over"));
        assert!(resumed.contains("1.0 min in the last"));
        let unknown = wall_time_note(60.0, 40, None);
        assert!(unknown.starts_with("Wall time of this invocation: 1.0 min."));
    }

    #[test]
    fn earlier_logs_are_not_overwritten_unasked() {
        let runs =
            std::env::temp_dir().join(format!("codesign-reproduce-{}-runs", std::process::id()));
        let _ = std::fs::remove_dir_all(&runs);
        assert!(refuse_earlier_logs(&runs).is_ok(), "no folder, no logs");
        std::fs::create_dir_all(&runs).unwrap();
        std::fs::write(runs.join("joint-1kg-seed0.json"), "{}").unwrap();
        assert!(
            refuse_earlier_logs(&runs).is_ok(),
            "result files alone are no run to lose"
        );
        std::fs::write(runs.join("joint-1kg-seed0.log.jsonl"), "").unwrap();
        let error = refuse_earlier_logs(&runs).unwrap_err();
        assert!(error.contains("joint-1kg-seed0.log.jsonl"), "{error}");
        assert!(
            error.contains("--resume") && error.contains("--overwrite"),
            "{error}"
        );
        std::fs::remove_dir_all(&runs).unwrap();
    }
}
