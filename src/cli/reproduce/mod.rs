//! `codesign reproduce`: the paper's experiment (docs/model.md, section 13) end to end.

mod plan;

use super::common::task_source;
use super::optimize::{run_case, LOG_EXTENSION};
use crate::design::capacity::{payload_capacity, CapacitySettings};
use crate::design::log::Start;
use crate::ipopt::LinearSolver;
use crate::model::task::Task;
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::report::codesign::{
    cost_evolution_chart, radar_chart, CapacityDocument, OptimizeDocument,
};
use crate::report::files::{
    check_output, create_folder, lock_or_name_holder, write_atomic, write_json,
};
use crate::report::plots::Figure;
use crate::report::table::{build_table, ResultFile};
use crate::report::trajectory::{write_plots, SolveDocument, ToolInfo};
use crate::solver::{solve_design, SolveError, SolveSettings, TrajectoryResult};
use plan::{Plan, PlannedRun, CODESIGNED, FULL, PAYLOADS, SPACES};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Flags of `codesign reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A reduced run that ends in minutes (population 16, 8 generations, 2 seeds unless given),
    /// written to results/quick/ unless --out-dir is given; labelled as reduced in the table.
    #[arg(long)]
    quick: bool,
    /// Seeds of CMA-ES per case (0..N); default 5 (2 with --quick).
    #[arg(long, value_name = "N")]
    seeds: Option<u64>,
    /// CMA-ES population; default 100 (16 with --quick).
    #[arg(long)]
    population: Option<usize>,
    /// CMA-ES generations; default 30 (8 with --quick).
    #[arg(long)]
    generations: Option<usize>,
    /// Output folder; default results/ (results/quick/ with --quick). Locked while the
    /// reproduction runs: a second one on the same folder fails at once.
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
    /// Task file [default: the built-in task, which `codesign task` prints].
    #[arg(long, value_name = "FILE")]
    task: Option<PathBuf>,
    /// Worker processes (default: one per core).
    #[arg(long, value_name = "N")]
    workers: Option<usize>,
    /// Linear solver inside IPOPT; default: the task's `solver.linear_solver`, else ldl.
    #[arg(long, value_enum, value_name = "SOLVER")]
    linear_solver: Option<LinearSolver>,
    /// Continue an interrupted reproduction from its evaluation logs.
    #[arg(long)]
    resume: bool,
    /// Start afresh even if the output folder holds an earlier reproduction's evaluation logs
    /// (they are replaced case by case as the new runs start).
    #[arg(long, conflicts_with = "resume")]
    overwrite: bool,
}

/// Runs the experiment matrix and writes results, table and plots.
pub fn run(args: &Args) -> Result<(), String> {
    let started = Instant::now();
    let plan = Plan::new(args)?;
    let source = task_source(plan.task.as_ref());
    let mut task = source.load().map_err(|e| e.to_string())?;
    task.solver
        .override_linear_solver(plan.problem.linear_solver);
    create_folder(&plan.out_dir)?;
    // Held until the reproduction ends: a second one on the same folder fails at once.
    let _lock = lock_folder(&plan.out_dir)?;
    let inputs: Vec<(&str, &Path)> = plan
        .task
        .iter()
        .map(|path| ("--task", path.as_path()))
        .collect();
    check_output("--out-dir", &plan.out_dir.join("paper_table.md"), &inputs)?;
    if plan.start == Start::Fresh {
        refuse_earlier_logs(&plan.out_dir.join("runs"))?;
    }
    for folder in ["original", "runs", "plots", "capacity"] {
        create_folder(&plan.out_dir.join(folder))?;
    }
    let mut files = solve_originals(&plan, &task)?;
    let runs = cost_runs(&plan)?;
    write_case_plots(&plan, &task, &runs)?;
    let beyond = beyond_the_paper(&plan, &task, &runs)?;
    // Resumed runs' earlier invocations, from their logs (the capacity co-design runs too).
    let earlier: Option<f64> = runs
        .iter()
        .chain(beyond.iter().filter_map(|file| match file {
            ResultFile::Optimize(document) => Some(document.as_ref()),
            _ => None,
        }))
        .map(|d| d.earlier_seconds)
        .sum();
    let replayed: usize = runs.iter().map(|d| d.replayed).sum();
    files.extend(beyond);
    files.extend(runs.into_iter().map(|d| ResultFile::Optimize(Box::new(d))));
    let mut notes = Vec::new();
    if plan.is_reduced() {
        let b = &plan.budget;
        notes.push(format!(
            "REDUCED RUN: population {}, {} generations, {} seed(s), against the paper's {}, {} and {}. \
             Run `codesign reproduce` without --quick for the full experiment.",
            b.population, b.generations, b.seeds, FULL.population, FULL.generations, FULL.seeds
        ));
    }
    notes.push(wall_time_note(
        started.elapsed().as_secs_f64(),
        replayed,
        earlier,
    ));
    let table = build_table(&files, notes);
    write_atomic(
        &plan.out_dir.join("paper_table.md"),
        table.to_markdown().as_bytes(),
    )?;
    write_json(&plan.out_dir.join("paper_table.json"), &table)?;
    say_raw!("{}", table.to_markdown());
    say!("results written to {}", plan.out_dir.display());
    Ok(())
}

/// The formulation of `task` with `payload_kg` in `space`, with the task's limit modes.
fn formulation_at(task: &Task, payload_kg: f64, space: Space) -> Result<Formulation, String> {
    let mut loaded = task.clone();
    loaded.payload.mass_kg = payload_kg;
    let robot = Robot::load(&loaded).map_err(|e| e.to_string())?;
    Formulation::new(&loaded, robot, space, loaded.limit_modes).map_err(|e| e.to_string())
}

/// Solves the original design at every payload in both spaces; writes each result and its
/// plots.
fn solve_originals(plan: &Plan, task: &Task) -> Result<Vec<ResultFile>, String> {
    let source = task_source(plan.task.as_ref());
    let mut files = Vec::new();
    for payload in PAYLOADS {
        for space in SPACES {
            let formulation = formulation_at(task, payload, space)?;
            let ratios = task.transmission.original.clone();
            let result = solve_design(&formulation, &ratios, &SolveSettings::default()).map_err(
                |e| match e {
                    SolveError::Design(_) => format!("{source} transmission.original: {e}"),
                    SolveError::Ipopt(_) => format!("{source} solver: {e}"),
                },
            )?;
            say!(
                "original design, {space} space, {payload} kg: {} J = {:.4} ({} iterations)",
                result.status,
                result.cost,
                result.iterations
            );
            let name = format!("{space}-{payload}kg");
            let plots = plan.out_dir.join("plots").join(format!("original-{name}"));
            write_plots(&plots, &formulation, &result)?;
            let document = SolveDocument::new(&source.label(), &formulation, result);
            write_json(
                &plan.out_dir.join("original").join(format!("{name}.json")),
                &document,
            )?;
            files.push(ResultFile::Solve(Box::new(document)));
        }
    }
    Ok(files)
}

/// The result file of a planned run.
fn run_file(plan: &Plan, run: &PlannedRun) -> PathBuf {
    plan.out_dir.join("runs").join(format!("{}.json", run.name))
}

/// The paper's co-design runs (CMA-ES on the cost), in order.
fn cost_runs(plan: &Plan) -> Result<Vec<OptimizeDocument>, String> {
    let mut documents = Vec::new();
    for run in plan.cost_runs() {
        let document = run_case(&run.case, &run_file(plan, &run))?;
        say!(
            "co-design, {} space, {} kg, seed {}: best r = {:?}, J = {:.4} ({} evaluations)",
            run.case.problem.space,
            document.inputs.payload_kg,
            run.case.cmaes.seed,
            document.best_ratios,
            document.best_cost,
            document.evaluations
        );
        documents.push(document);
    }
    Ok(documents)
}

/// The best feasible solve of the co-design runs at `payload` in `space`.
fn best_of(runs: &[OptimizeDocument], payload: f64, space: Space) -> Option<&TrajectoryResult> {
    runs.iter()
        .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
        .filter_map(|d| d.best_result.as_ref().filter(|r| r.feasible))
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
}

/// Per case: the cost evolution of its seeds and the plots of its best design; and the radar
/// chart of every case's best ratios.
fn write_case_plots(plan: &Plan, task: &Task, runs: &[OptimizeDocument]) -> Result<(), String> {
    let plots = plan.out_dir.join("plots");
    let mut radar_cases = Vec::new();
    for payload in CODESIGNED {
        for space in SPACES {
            let case: Vec<&OptimizeDocument> = runs
                .iter()
                .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
                .collect();
            let name = format!("{space}-{payload}kg");
            let title = format!("CMA-ES cost per evaluation: {space} space, {payload} kg");
            cost_evolution_chart(&title, &case)
                .write(&plots.join(format!("cost_evolution-{name}.svg")))?;
            if let Some(best) = best_of(runs, payload, space) {
                let formulation = formulation_at(task, payload, space)?;
                write_plots(&plots.join(format!("best-{name}")), &formulation, best)?;
                radar_cases.push((format!("{space}, {payload} kg"), best.ratios.clone()));
            }
        }
    }
    let upper: Vec<f64> = task.transmission.bounds.iter().map(|b| b[1]).collect();
    radar_chart(
        "Optimal gear ratios (r_i / upper bound)",
        &radar_cases,
        &upper,
    )
    .write(&plots.join("optimal_ratios.svg"))
}

/// Opens the output folder and takes its advisory lock (`flock`), so that two reproductions
/// never write one folder at once.
fn lock_folder(folder: &Path) -> Result<std::fs::File, String> {
    let handle = std::fs::File::open(folder)
        .map_err(|e| format!("cannot open --out-dir {}: {e}", folder.display()))?;
    let what = format!("the output folder {}", folder.display());
    lock_or_name_holder(&handle, &what, "--out-dir")?;
    Ok(handle)
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

/// Co-design by the gradient method for every co-designed case, the design of largest payload
/// capacity per space, and the payload capacity of the original design (per space) and of each
/// case's best CMA-ES design.
fn beyond_the_paper(
    plan: &Plan,
    task: &Task,
    runs: &[OptimizeDocument],
) -> Result<Vec<ResultFile>, String> {
    let mut files = Vec::new();
    for run in plan.gradient_runs() {
        let (space, payload) = (
            run.case.problem.space,
            run.case.model.payload.unwrap_or_default(),
        );
        match run_case(&run.case, &run_file(plan, &run)) {
            Ok(document) => {
                say!(
                    "gradient co-design, {space} space, {payload} kg: best r = {:?}, J = {:.4} ({} solves)",
                    document.best_ratios, document.best_cost, document.evaluations
                );
                files.push(ResultFile::Optimize(Box::new(document)));
            }
            Err(error) => say!("gradient co-design, {space} space, {payload} kg: {error}"),
        }
    }
    for run in plan.capacity_runs() {
        let document = run_case(&run.case, &run_file(plan, &run))?;
        say!(
            "capacity co-design, {} space: r = {:?} lifts {:.3} kg ({} evaluations)",
            run.case.problem.space,
            document.best_ratios,
            -document.best_cost,
            document.evaluations
        );
        files.push(ResultFile::Optimize(Box::new(document)));
    }
    files.extend(capacities(plan, task, runs)?);
    Ok(files)
}

/// The payload capacity of the original design per space and of each case's best design.
fn capacities(
    plan: &Plan,
    task: &Task,
    runs: &[OptimizeDocument],
) -> Result<Vec<ResultFile>, String> {
    let mut designs: Vec<(Space, Vec<f64>, String)> = SPACES
        .iter()
        .map(|&space| {
            (
                space,
                task.transmission.original.clone(),
                format!("{space}-original"),
            )
        })
        .collect();
    for payload in CODESIGNED {
        for space in SPACES {
            if let Some(best) = best_of(runs, payload, space) {
                designs.push((
                    space,
                    best.ratios.clone(),
                    format!("{space}-{payload}kg-best"),
                ));
            }
        }
    }
    let settings = CapacitySettings::default();
    let robot = Robot::load(task).map_err(|e| e.to_string())?;
    let mut files = Vec::new();
    for (space, ratios, name) in designs {
        let capacity = payload_capacity(task, &robot, space, task.limit_modes, &ratios, &settings)?;
        say!("payload capacity, {name}: {:?} kg", capacity.capacity_kg);
        let document = CapacityDocument {
            tool: ToolInfo::current(task.solver.linear_solver()),
            task_file: task_source(plan.task.as_ref()).label(),
            space,
            ratios,
            limit_modes: task.limit_modes,
            settings,
            capacity,
        };
        write_json(
            &plan.out_dir.join("capacity").join(format!("{name}.json")),
            &document,
        )?;
        files.push(ResultFile::Capacity(Box::new(document)));
    }
    Ok(files)
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
