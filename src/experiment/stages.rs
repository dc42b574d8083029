//! The stages of an experiment run in this process: the original designs, the co-design runs
//! and the capacities, each written to its file in the output folder as it finishes, and told
//! to an [`Observer`] (the command line prints them).

use super::{CapacityOf, ExperimentError, ExperimentTask, Plan, PlannedRun, SPACES};
use crate::design::capacity::{payload_capacity, Capacity, CapacitySettings};
use crate::design::optimize::Progress;
use crate::design::run::{run_case, task_source, OptimizeDocument, RecordedHash, RunError};
use crate::parallel::{in_order, solve_threads};
use crate::report::codesign::{CapacityDocument, CapacityInputs};
use crate::report::solve_document::SolveDocument;
use crate::report::table::{PaperTable, ResultFile};
use crate::report::trajectory::write_plots;
use crate::store::document::write_document;
use crate::store::files::create_folder;
use crate::store::log::{Start, LOG_EXTENSION};
use codesign_core::problem::Space;
use codesign_core::solve::{solve_design, ToolInfo, TrajectoryResult};
use std::convert::Infallible;
use std::path::{Path, PathBuf};

/// What the experiment's independent stages produced, in this process or by the plan's
/// commands elsewhere.
pub struct Outcomes {
    /// The original designs' solves, per payload and space.
    pub originals: Vec<ResultFile>,
    /// The paper's co-design runs, per payload, space and seed.
    pub runs: Vec<OptimizeDocument>,
    /// The gradient method's runs that found a feasible start.
    pub gradient_runs: Vec<OptimizeDocument>,
    /// The CMA-ES runs beyond the paper: the capacity designs per space, the payload range.
    pub beyond_runs: Vec<OptimizeDocument>,
    /// The original design's capacity, per space.
    pub original_capacities: Vec<CapacityDocument>,
}

/// What an experiment tells as it goes.
pub enum Event<'a> {
    /// The original design was solved at `payload_kg` in `space`.
    Original {
        /// Joint or actuation space.
        space: Space,
        /// The payload, kg.
        payload_kg: f64,
        /// The solve.
        result: &'a TrajectoryResult,
    },
    /// A co-design run of the paper (CMA-ES on the cost) finished.
    CostRun {
        /// The run.
        run: &'a PlannedRun,
        /// Its document.
        document: &'a OptimizeDocument,
    },
    /// A gradient run finished, or failed; a failed one is left out of the table.
    GradientRun {
        /// The run.
        run: &'a PlannedRun,
        /// Its document, or why it failed.
        result: Result<&'a OptimizeDocument, RunError>,
    },
    /// A CMA-ES run beyond the paper (capacity, range, graded penalty) finished.
    BeyondRun {
        /// The run.
        run: &'a PlannedRun,
        /// Its document.
        document: &'a OptimizeDocument,
    },
    /// A payload capacity was searched: the capacity, kg (None: infeasible even unloaded).
    Capacity {
        /// Of which design.
        of: CapacityOf,
        /// Its capacity, kg.
        capacity_kg: Option<f64>,
    },
    /// An output of an earlier reproduction was removed: its case has no feasible design now.
    Removed {
        /// The file or folder removed.
        path: &'a Path,
    },
    /// A section's table (and index page) was written into `folder`.
    Table {
        /// The table.
        table: &'a PaperTable,
        /// The section's output folder.
        folder: &'a Path,
    },
}

/// Who hears what an experiment does: the progress of each co-design run, and each finished
/// stage.
pub trait Observer {
    /// The progress display of a co-design run of `total` evaluations, labelled.
    fn progress(&self, total: u64, label: String) -> Box<dyn Progress>;
    /// A stage finished.
    fn event(&mut self, event: Event<'_>);
}

/// Runs the independent stages of one section of `plan` here, after creating its folders (and
/// refusing an earlier reproduction's logs when starting afresh): what its printed commands do
/// elsewhere.
pub fn run_section(
    plan: &Plan,
    task: &ExperimentTask,
    observer: &mut dyn Observer,
) -> Result<Outcomes, ExperimentError> {
    if plan.execution.start == Start::Fresh {
        refuse_earlier_logs(&plan.layout.runs())?;
    }
    create_folder(plan.out_dir())?;
    for folder in plan.layout.folders() {
        create_folder(&folder)?;
    }
    Ok(Outcomes {
        originals: solve_originals(plan, task, observer)?,
        runs: cost_runs(plan, observer)?,
        gradient_runs: gradient_runs(plan, observer),
        beyond_runs: beyond_runs(plan, observer)?,
        original_capacities: {
            let original = |space| CapacityJob {
                of: CapacityOf::Original(space),
                ratios: task.task.transmission.original.clone(),
            };
            let jobs: Vec<CapacityJob> = SPACES.into_iter().map(original).collect();
            capacity_documents(plan, task, &jobs, observer)?
        },
    })
}

/// Solves the original design at every payload in both spaces; writes each result and its
/// plots.
fn solve_originals(
    plan: &Plan,
    task: &ExperimentTask,
    observer: &mut dyn Observer,
) -> Result<Vec<ResultFile>, ExperimentError> {
    let source = task_source(plan.task.as_ref());
    let mut files = Vec::new();
    for &payload in &plan.experiment.original_payloads_kg {
        for space in SPACES {
            let formulation = task.formulation_at(payload, space)?;
            let ratios = task.task.transmission.original.clone();
            let result = solve_design(&formulation, &ratios, &task.solver).map_err(|error| {
                ExperimentError::Original {
                    source: source.clone(),
                    error,
                }
            })?;
            observer.event(Event::Original {
                space,
                payload_kg: payload,
                result: &result,
            });
            let plots = plan.layout.original_plots(space, payload);
            write_plots(&plots, &formulation, &result)?;
            let label = source.label();
            let document =
                SolveDocument::new(&label, &task.hash, &formulation, &task.solver, result);
            write_document(&plan.layout.original(space, payload), &document)?;
            files.push(ResultFile::Solve(Box::new(document)));
        }
    }
    Ok(files)
}

/// Runs one planned co-design run, its progress shown by `observer`, labelled with which of
/// the section's runs it is.
fn run(
    plan: &Plan,
    run: &PlannedRun,
    observer: &dyn Observer,
) -> Result<OptimizeDocument, RunError> {
    let (number, count) = run_number(plan, run);
    let section = if plan.is_hold_section { "hold " } else { "" };
    let display =
        |total, label| observer.progress(total, format!("{section}run {number}/{count}, {label}"));
    run_case(&run.case, &plan.layout.run(&run.name), &display)
}

/// Which of the section's co-design runs, in the order they run, `run` is (from 1), and how
/// many there are.
fn run_number(plan: &Plan, run: &PlannedRun) -> (usize, usize) {
    let mut runs = plan.cost_runs();
    runs.extend(plan.gradient_runs());
    runs.extend(plan.beyond_runs());
    let position = runs.iter().position(|planned| planned.name == run.name);
    (position.map_or(0, |index| index + 1), runs.len())
}

/// The paper's co-design runs (CMA-ES on the cost), in order.
fn cost_runs(
    plan: &Plan,
    observer: &mut dyn Observer,
) -> Result<Vec<OptimizeDocument>, ExperimentError> {
    let mut documents = Vec::new();
    for planned in plan.cost_runs() {
        let document = run(plan, &planned, observer)?;
        observer.event(Event::CostRun {
            run: &planned,
            document: &document,
        });
        documents.push(document);
    }
    Ok(documents)
}

/// Co-design by the gradient method for every co-designed case, and with the graded penalty at
/// the edge of feasibility; a case where it finds no feasible start is told and left out.
fn gradient_runs(plan: &Plan, observer: &mut dyn Observer) -> Vec<OptimizeDocument> {
    let mut documents = Vec::new();
    for planned in plan.gradient_runs() {
        match run(plan, &planned, observer) {
            Ok(document) => {
                observer.event(Event::GradientRun {
                    run: &planned,
                    result: Ok(&document),
                });
                documents.push(document);
            }
            Err(error) => observer.event(Event::GradientRun {
                run: &planned,
                result: Err(error),
            }),
        }
    }
    documents
}

/// The CMA-ES runs beyond the paper: the design of largest payload capacity per space, and one
/// design for the payload range.
fn beyond_runs(
    plan: &Plan,
    observer: &mut dyn Observer,
) -> Result<Vec<OptimizeDocument>, ExperimentError> {
    let mut documents = Vec::new();
    for planned in plan.beyond_runs() {
        let document = run(plan, &planned, observer)?;
        observer.event(Event::BeyondRun {
            run: &planned,
            document: &document,
        });
        documents.push(document);
    }
    Ok(documents)
}

/// A payload capacity the experiment searches: of which design (in which space), its ratios.
pub struct CapacityJob {
    /// Of which design.
    pub of: CapacityOf,
    /// The design r.
    pub ratios: Vec<f64>,
}

/// Searches the payload capacity of every job, side by side on the plan's workers' count of
/// threads (default one per core; one with MUMPS, which is not thread-safe: each search is one
/// design's sequence of solves), then tells each and writes it as `capacity/NAME.json`, in the
/// order given. A search's numbers do not depend on the threads.
pub fn capacity_documents(
    plan: &Plan,
    task: &ExperimentTask,
    jobs: &[CapacityJob],
    observer: &mut dyn Observer,
) -> Result<Vec<CapacityDocument>, ExperimentError> {
    let settings = CapacitySettings::default();
    let search = |index: usize| -> Result<Capacity, ExperimentError> {
        let job = &jobs[index];
        let formulation = task.formulation_at(task.task.payload.mass_kg, job.of.space())?;
        Ok(payload_capacity(
            &formulation,
            &task.solver,
            &job.ratios,
            &settings,
        )?)
    };
    let threads = solve_threads(plan.execution.workers, task.solver.linear_solver());
    let heard = |_: usize, _: &_| Ok::<(), Infallible>(());
    let Ok(searched) = in_order(jobs.len(), threads, || false, search, heard);
    let mut documents = Vec::new();
    for (job, capacity) in jobs.iter().zip(searched) {
        // Nothing stops the threads early: every job was searched.
        let Some(capacity) = capacity else { continue };
        let capacity = capacity?;
        observer.event(Event::Capacity {
            of: job.of,
            capacity_kg: capacity.capacity_kg,
        });
        let document = CapacityDocument {
            tool: ToolInfo::current(task.solver.linear_solver()),
            inputs: CapacityInputs {
                task_file: task_source(plan.task.as_ref()).label(),
                task_hash: RecordedHash(Some(task.hash.clone())),
                space: job.of.space(),
                ratios: job.ratios.clone(),
                limit_modes: task.task.limit_modes,
                ends: task.task.motion.ends,
                settings,
                duration_s: None,
            },
            capacity,
        };
        write_document(&plan.layout.capacity(job.of), &document)?;
        documents.push(document);
    }
    Ok(documents)
}

/// Fails, naming a log, when `runs` holds evaluation logs of an earlier reproduction (a
/// missing folder holds none).
fn refuse_earlier_logs(runs: &Path) -> Result<(), ExperimentError> {
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
        Some(first) => Err(ExperimentError::EarlierLogs {
            folder: runs.to_owned(),
            first: first.clone(),
            more: logs.len() - 1,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::refuse_earlier_logs;
    use crate::experiment::ExperimentError;

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
        assert!(
            matches!(&error, ExperimentError::EarlierLogs { first, more: 0, .. }
                if first.ends_with("joint-1kg-seed0.log.jsonl")),
            "{error}"
        );
        std::fs::remove_dir_all(&runs).unwrap();
    }
}
