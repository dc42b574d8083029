//! `codesign reproduce`: the task's experiment, by default the paper's (docs/model.md, section
//! 13), end to end.

mod commands;
mod words;

use super::failure::Failure;
use super::store_hints::{check_output, hint};
use crate::cli::choice::choice;
use crate::cli::run_flags::{case_error, RunArgs};
use crate::design::run::task_source;
use crate::design::run::{Method, RunSettings};
use crate::experiment::{run_experiment, ExperimentTask, Section};
use crate::experiment::{Plan, PlanError, PlanRequest};
use crate::store::files::create_folder;
use crate::store::lock::lock_folder;
use crate::store::log::Start;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::Ends;
use std::path::{Path, PathBuf};
use std::time::Instant;
use words::experiment_error;

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
    #[arg(long, value_parser = choice::<LinearSolver>(), value_name = "SOLVER")]
    linear_solver: Option<LinearSolver>,
    /// The CMA-ES runs' bound handling and warm starts, and their workers (as `optimize`'s).
    #[command(flatten)]
    run: RunArgs,
    /// What the motion asks at its ends in every run (see `solve --ends`); default: the task's
    /// `motion.ends` (the built-in task's: paper). Under `paper`, Table II's cases are solved
    /// under `hold` as well, in OUT_DIR/hold/, for the table's section on holding the load.
    #[arg(long, value_parser = choice::<Ends>(), value_name = "ENDS")]
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
    let task = ExperimentTask::load(&plan, file.clone()).map_err(experiment_error)?;
    let hold = match plan.hold_section() {
        Some(hold) => Some((
            ExperimentTask::load(&hold, file).map_err(experiment_error)?,
            hold,
        )),
        None => None,
    };
    if args.plan {
        return print_plan(&plan, hold.as_ref());
    }
    create_folder(plan.out_dir()).map_err(|e| e.to_string())?;
    // Held until the reproduction ends: a second one on the same folder fails at once.
    let _lock = lock_folder(plan.out_dir()).map_err(|e| hint(e, "--out-dir"))?;
    let merged = args.from_runs.is_some();
    check_outputs(&plan, &task, hold.as_ref(), merged)?;
    let main = Section {
        plan: &plan,
        task: &task,
    };
    let hold = hold.as_ref().map(|(task, plan)| Section { plan, task });
    run_experiment(main, hold, merged, started, &mut words::Printer).map_err(experiment_error)?;
    Ok(())
}

/// Creates the folders the plan's commands write into, on whichever machine runs them, and
/// prints the commands.
fn print_plan(plan: &Plan, hold: Option<&(ExperimentTask, Plan)>) -> Result<(), Failure> {
    let program = std::env::current_exe()
        .map_err(|e| format!("cannot locate the codesign executable: {e}"))?;
    for section in sections(plan, hold) {
        create_folder(section.out_dir()).map_err(|e| e.to_string())?;
        for folder in section.layout.folders() {
            create_folder(&folder).map_err(|e| e.to_string())?;
        }
    }
    for line in commands::commands(plan, &program.to_string_lossy()) {
        say!("{line}");
    }
    Ok(())
}

/// Checks, before any work, that every output can take a result and is none of the inputs:
/// the task file, its robot, and under --from-runs the results the plan's commands wrote
/// (through a symbolic link either).
fn check_outputs(
    plan: &Plan,
    task: &ExperimentTask,
    hold: Option<&(ExperimentTask, Plan)>,
    merged: bool,
) -> Result<(), Failure> {
    let task_file = plan.task.iter().map(|path| ("--task", path.as_path()));
    let robot = task.task.robot.iter().map(|path| ("robot", path.as_path()));
    let read: Vec<PathBuf> = match merged {
        true => sections(plan, hold).flat_map(Plan::merged_inputs).collect(),
        false => Vec::new(),
    };
    let results = read.iter().map(|path| ("--from-runs", path.as_path()));
    let inputs: Vec<(&str, &Path)> = task_file.chain(robot).chain(results).collect();
    let flag = if merged { "--from-runs" } else { "--out-dir" };
    let motors = task.task.transmission.matrix.len();
    for output in sections(plan, hold).flat_map(|plan| plan.outputs(motors)) {
        if !read.contains(&output) {
            check_output(flag, &output, &inputs)?;
        }
    }
    Ok(())
}

/// The experiment's sections: `plan`, then its hold section when it has one.
fn sections<'a>(
    plan: &'a Plan,
    hold: Option<&'a (ExperimentTask, Plan)>,
) -> impl Iterator<Item = &'a Plan> {
    std::iter::once(plan).chain(hold.map(|(_, plan)| plan))
}
