//! `codesign reproduce`: the paper's experiment (docs/model.md, section 13) end to end.

use super::common::{task_source, ModelArgs, ProblemArgs};
use super::optimize::{run_case, Args as OptimizeArgs, ObjectiveKind, LOG_EXTENSION};
use super::preflight::{check_generations, check_population};
use crate::design::capacity::{payload_capacity, CapacitySettings};
use crate::ipopt::LinearSolver;
use crate::model::task::Task;
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::report::codesign::{
    cost_evolution_chart, radar_chart, CapacityDocument, Method, OptimizeDocument,
};
use crate::report::files::{
    check_output, create_folder, lock_or_name_holder, write_atomic, write_json,
};
use crate::report::plots::Figure;
use crate::report::table::{build_table, ResultFile};
use crate::report::trajectory::{write_plots, SolveDocument, ToolInfo};
use crate::solver::{solve_design, SolveError, SolveSettings};
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

/// Payloads of the experiment, kg, and those that are co-designed (docs/model.md, section 13).
const PAYLOADS: [f64; 3] = [0.0, 1.0, 3.0];
const CODESIGNED: [f64; 2] = [1.0, 3.0];
const SPACES: [Space; 2] = [Space::Joint, Space::Actuation];

/// The flags of one `optimize` run of the reproduction (the task's limit modes, the paper's
/// sigma and penalty).
fn case_args(
    args: &Args,
    payload: Option<f64>,
    space: Space,
    method: Method,
    objective: ObjectiveKind,
    (seed, population, generations): (u64, usize, usize),
) -> OptimizeArgs {
    OptimizeArgs {
        model: ModelArgs {
            task: args.task.clone(),
            robot: None,
            payload,
        },
        method,
        objective,
        capacity_resolution: 0.01,
        gradient_iterations: 50,
        problem: ProblemArgs {
            space,
            torque_mode: None,
            speed_mode: None,
            linear_solver: args.linear_solver,
        },
        seed,
        population,
        generations,
        sigma: 0.3,
        penalty: 1e6,
        workers: args.workers,
        solve_timeout: 600.0,
        out: None,
        resume: args.resume && method == Method::Cmaes,
        overwrite: args.overwrite,
    }
}

/// The formulation of `task` with `payload_kg` in `space`, with the task's limit modes.
fn formulation_at(task: &Task, payload_kg: f64, space: Space) -> Result<Formulation, String> {
    let mut loaded = task.clone();
    loaded.payload.mass_kg = payload_kg;
    let robot = Robot::load(&loaded).map_err(|e| e.to_string())?;
    Formulation::new(&loaded, robot, space, loaded.limit_modes).map_err(|e| e.to_string())
}

/// Runs the experiment matrix and writes results, table and plots.
pub fn run(args: &Args) -> Result<(), String> {
    let started = Instant::now();
    let seeds = args.seeds.unwrap_or(if args.quick { 2 } else { 5 });
    let population = args.population.unwrap_or(if args.quick { 16 } else { 100 });
    let generations = args.generations.unwrap_or(if args.quick { 8 } else { 30 });
    let out_dir = args.out_dir.clone().unwrap_or_else(|| {
        PathBuf::from(if args.quick {
            "results/quick"
        } else {
            "results"
        })
    });
    check_sizes(seeds, population, generations)?;
    let mut task = task_source(args.task.as_ref())
        .load()
        .map_err(|e| e.to_string())?;
    task.solver.override_linear_solver(args.linear_solver);
    create_folder(&out_dir)?;
    // Held until the reproduction ends: a second one on the same folder fails at once.
    let _lock = lock_folder(&out_dir)?;
    check_output(
        "--out-dir",
        &out_dir.join("paper_table.md"),
        &args
            .task
            .as_deref()
            .map(|path| ("--task", path))
            .into_iter()
            .collect::<Vec<_>>(),
    )?;
    if !args.resume && !args.overwrite {
        refuse_earlier_logs(&out_dir.join("runs"))?;
    }
    for folder in ["original", "runs", "plots", "capacity"] {
        create_folder(&out_dir.join(folder))?;
    }
    let mut files = Vec::new();

    for payload in PAYLOADS {
        for space in SPACES {
            let formulation = formulation_at(&task, payload, space)?;
            let ratios = task.transmission.original.clone();
            let result = solve_design(&formulation, &ratios, &SolveSettings::default()).map_err(
                |e| match e {
                    SolveError::Design(_) => {
                        format!(
                            "{} transmission.original: {e}",
                            task_source(args.task.as_ref())
                        )
                    }
                    SolveError::Ipopt(_) => {
                        format!("{} solver: {e}", task_source(args.task.as_ref()))
                    }
                },
            )?;
            say!(
                "original design, {space} space, {payload} kg: {} J = {:.4} ({} iterations)",
                result.status,
                result.cost,
                result.iterations
            );
            let name = format!("{space}-{payload}kg");
            write_plots(
                &out_dir.join("plots").join(format!("original-{name}")),
                &formulation,
                &result,
            )?;
            let document = SolveDocument::new(
                &task_source(args.task.as_ref()).label(),
                &formulation,
                result,
            );
            write_json(
                &out_dir.join("original").join(format!("{name}.json")),
                &document,
            )?;
            files.push(ResultFile::Solve(Box::new(document)));
        }
    }

    let mut runs: Vec<OptimizeDocument> = Vec::new();
    for payload in CODESIGNED {
        for space in SPACES {
            for seed in 0..seeds {
                let case = case_args(
                    args,
                    Some(payload),
                    space,
                    Method::Cmaes,
                    ObjectiveKind::Cost,
                    (seed, population, generations),
                );
                let out = out_dir
                    .join("runs")
                    .join(format!("{space}-{payload}kg-seed{seed}.json"));
                let document = run_case(&case, &out)?;
                say!(
                    "co-design, {space} space, {payload} kg, seed {seed}: best r = {:?}, J = {:.4} ({} evaluations)",
                    document.best_ratios, document.best_cost, document.evaluations
                );
                runs.push(document);
            }
        }
    }

    let mut radar_cases = Vec::new();
    for payload in CODESIGNED {
        for space in SPACES {
            let case: Vec<&OptimizeDocument> = runs
                .iter()
                .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
                .collect();
            let name = format!("{space}-{payload}kg");
            cost_evolution_chart(
                &format!("CMA-ES cost per evaluation: {space} space, {payload} kg"),
                &case,
            )
            .write(
                &out_dir
                    .join("plots")
                    .join(format!("cost_evolution-{name}.svg")),
            )?;
            let best = case
                .iter()
                .filter_map(|d| d.best_result.as_ref().filter(|r| r.feasible))
                .min_by(|a, b| a.cost.total_cmp(&b.cost));
            if let Some(best) = best {
                let formulation = formulation_at(&task, payload, space)?;
                write_plots(
                    &out_dir.join("plots").join(format!("best-{name}")),
                    &formulation,
                    best,
                )?;
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
    .write(&out_dir.join("plots").join("optimal_ratios.svg"))?;

    let replayed: usize = runs.iter().map(|d| d.replayed).sum();
    let beyond = beyond_the_paper(args, &task, &out_dir, &runs)?;
    // Resumed runs' earlier invocations, from their logs (the capacity co-design runs too).
    let earlier: Option<f64> = runs
        .iter()
        .chain(beyond.iter().filter_map(|file| match file {
            ResultFile::Optimize(document) => Some(document.as_ref()),
            _ => None,
        }))
        .map(|d| d.earlier_seconds)
        .sum();
    files.extend(beyond);
    files.extend(runs.into_iter().map(|d| ResultFile::Optimize(Box::new(d))));
    let mut notes = Vec::new();
    if args.quick || population < 100 || generations < 30 || seeds < 5 {
        notes.push(format!(
            "REDUCED RUN: population {population}, {generations} generations, {seeds} seed(s), against the paper's 100, 30 and 5. \
             Run `codesign reproduce` without --quick for the full experiment."
        ));
    }
    notes.push(wall_time_note(
        started.elapsed().as_secs_f64(),
        replayed,
        earlier,
    ));
    let table = build_table(&files, notes);
    write_atomic(
        &out_dir.join("paper_table.md"),
        table.to_markdown().as_bytes(),
    )?;
    write_json(&out_dir.join("paper_table.json"), &table)?;
    say_raw!("{}", table.to_markdown());
    say!("results written to {}", out_dir.display());
    Ok(())
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

/// Most CMA-ES seeds per case: 20 times the paper's 5.
const MAX_SEEDS: u64 = 100;

/// Checks the sizes of the experiment before anything is created; errors name the flag, the
/// limit and its reason.
fn check_sizes(seeds: u64, population: usize, generations: usize) -> Result<(), String> {
    if !(1..=MAX_SEEDS).contains(&seeds) {
        return Err(format!(
            "--seeds {seeds}: must be 1 to {MAX_SEEDS} (20 times the paper's 5)"
        ));
    }
    check_population(population)?;
    check_generations(generations)
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

/// Co-design by the gradient method for every co-designed case, and the payload capacity of
/// the original design (per space) and of each case's best CMA-ES design.
fn beyond_the_paper(
    args: &Args,
    task: &Task,
    out_dir: &Path,
    runs: &[OptimizeDocument],
) -> Result<Vec<ResultFile>, String> {
    let mut files = Vec::new();
    for payload in CODESIGNED {
        for space in SPACES {
            let case = case_args(
                args,
                Some(payload),
                space,
                Method::Gradient,
                ObjectiveKind::Cost,
                (0, 0, 0),
            );
            let out = out_dir
                .join("runs")
                .join(format!("{space}-{payload}kg-gradient.json"));
            match run_case(&case, &out) {
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
    }
    // The design that lifts the most, per space: CMA-ES on minus the capacity, on a smaller
    // budget than the cost runs (each evaluation is a capacity search of about 10 solves).
    let budget = if args.quick { (0, 6, 2) } else { (0, 20, 10) };
    for space in SPACES {
        let case = case_args(
            args,
            None,
            space,
            Method::Cmaes,
            ObjectiveKind::Capacity,
            budget,
        );
        let out = out_dir
            .join("runs")
            .join(format!("{space}-capacity-seed0.json"));
        let document = run_case(&case, &out)?;
        say!(
            "capacity co-design, {space} space: r = {:?} lifts {:.3} kg ({} evaluations)",
            document.best_ratios,
            -document.best_cost,
            document.evaluations
        );
        files.push(ResultFile::Optimize(Box::new(document)));
    }
    let settings = CapacitySettings {
        resolution_kg: 0.01,
        first_step_kg: 1.0,
        max_kg: 64.0,
    };
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
            let best = runs
                .iter()
                .filter(|d| d.inputs.payload_kg == payload && d.inputs.space == space)
                .filter_map(|d| d.best_result.as_ref().filter(|r| r.feasible))
                .min_by(|a, b| a.cost.total_cmp(&b.cost));
            if let Some(best) = best {
                designs.push((
                    space,
                    best.ratios.clone(),
                    format!("{space}-{payload}kg-best"),
                ));
            }
        }
    }
    let robot = Robot::load(task).map_err(|e| e.to_string())?;
    for (space, ratios, name) in designs {
        let capacity = payload_capacity(task, &robot, space, task.limit_modes, &ratios, &settings)?;
        say!("payload capacity, {name}: {:?} kg", capacity.capacity_kg);
        let document = CapacityDocument {
            tool: ToolInfo::current(task.solver.linear_solver()),
            task_file: task_source(args.task.as_ref()).label(),
            space,
            ratios,
            limit_modes: task.limit_modes,
            settings,
            capacity,
        };
        write_json(
            &out_dir.join("capacity").join(format!("{name}.json")),
            &document,
        )?;
        files.push(ResultFile::Capacity(Box::new(document)));
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::{check_sizes, refuse_earlier_logs, wall_time_note};

    #[test]
    fn sizes_are_checked_with_their_limits() {
        assert!(check_sizes(5, 100, 30).is_ok());
        assert!(check_sizes(0, 100, 30)
            .unwrap_err()
            .starts_with("--seeds 0: must be 1 to"));
        assert!(check_sizes(5, 0, 30)
            .unwrap_err()
            .starts_with("--population 0:"));
        assert!(check_sizes(5, 100, 1 << 40)
            .unwrap_err()
            .starts_with("--generations"));
    }

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
