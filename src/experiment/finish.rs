//! The stages that need every run of a section: the best designs' plots and capacities, the
//! radar chart, the table with its notes, and the index page; and the whole experiment, its
//! sections in order.

use super::index::write_index;
use super::stages::{capacity_documents, run_section, CapacityJob};
use super::{merge, CapacityOf, Event, ExperimentError, ExperimentTask, Observer, Outcomes};
use super::{Plan, SPACES};
use crate::design::run::OptimizeDocument;
use crate::report::codesign::{cost_evolution_chart, ratio_chart, CapacityDocument};
use crate::report::plots::Figure;
use crate::report::table::{build_table, PaperTable, ResultFile};
use crate::report::trajectory::write_plots;
use crate::store::document::write_document;
use crate::store::files::{create_folder, remove_stale, write_atomic};
use codesign_core::model::experiment::Budget;
use codesign_core::problem::Space;
use codesign_core::solve::TrajectoryResult;
use std::path::Path;
use std::time::Instant;

/// One section of an experiment: its plan and its task.
pub struct Section<'a> {
    /// The plan.
    pub plan: &'a Plan,
    /// Its task.
    pub task: &'a ExperimentTask,
}

/// Runs an experiment's `main` section and its `hold` section (when the plan has one) here,
/// or, when `merged`, reads their stages' results back from the plan's commands; then writes
/// each section's table, the hold section's first. `started` is when the reproduction began
/// (its wall time is noted in the table).
pub fn run_experiment(
    main: Section<'_>,
    hold: Option<Section<'_>>,
    merged: bool,
    started: Instant,
    observer: &mut dyn Observer,
) -> Result<PaperTable, ExperimentError> {
    let outcomes = section_outcomes(&main, merged, observer)?;
    let hold_table = match hold {
        Some(hold) => {
            let outcomes = section_outcomes(&hold, merged, observer)?;
            let seconds = started.elapsed().as_secs_f64();
            Some(finish(&hold, outcomes, merged, seconds, None, observer)?)
        }
        None => None,
    };
    let seconds = started.elapsed().as_secs_f64();
    finish(
        &main,
        outcomes,
        merged,
        seconds,
        hold_table.as_ref(),
        observer,
    )
}

/// The independent stages of one section: read back from the plan's commands' results
/// (`merged`), or run here.
fn section_outcomes(
    section: &Section<'_>,
    merged: bool,
    observer: &mut dyn Observer,
) -> Result<Outcomes, ExperimentError> {
    match merged {
        true => Ok(merge::read_all(section.plan, &section.task.hash)?),
        false => run_section(section.plan, section.task, observer),
    }
}

/// The stages that need every run: the best designs' plots and capacities, the radar chart, and
/// the table, with `hold`, the table of the same cases under `hold`, as a section of it.
fn finish(
    section: &Section<'_>,
    outcomes: Outcomes,
    merged: bool,
    seconds: f64,
    hold: Option<&PaperTable>,
    observer: &mut dyn Observer,
) -> Result<PaperTable, ExperimentError> {
    let plan = section.plan;
    create_folder(&plan.layout.capacities())?;
    write_case_plots(section, &outcomes.runs, observer)?;
    let mut capacities = outcomes.original_capacities;
    capacities.extend(best_capacities(section, &outcomes.runs, observer)?);
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
    let mut notes = plan_notes(plan);
    notes.push(time_note);
    let mut table = build_table(&files, notes);
    if let Some(hold) = hold {
        table.add_hold_section(hold);
    }
    write_atomic(
        &plan.layout.table_markdown(),
        table.to_markdown().as_bytes(),
    )?;
    write_document(&plan.layout.table_json(), &table)?;
    write_index(&plan.layout, &table)?;
    observer.event(Event::Table {
        table: &table,
        folder: plan.out_dir(),
    });
    Ok(table)
}

/// The table's notes on the experiment itself: which one it is, when not the paper's, and
/// whether its budget is reduced.
fn plan_notes(plan: &Plan) -> Vec<String> {
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
    notes
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
    section: &Section<'_>,
    runs: &[OptimizeDocument],
    observer: &mut dyn Observer,
) -> Result<Vec<CapacityDocument>, ExperimentError> {
    let (plan, task) = (section.plan, section.task);
    let mut jobs = Vec::new();
    for &payload in &plan.experiment.codesign_payloads_kg {
        for space in SPACES {
            let of = CapacityOf::Best(space, payload);
            if let Some(best) = best_of(runs, payload, space) {
                let ratios = best.ratios.clone();
                jobs.push(CapacityJob { of, ratios });
            } else {
                remove_stale_output(&plan.layout.capacity(of), observer)?;
            }
        }
    }
    capacity_documents(plan, task, &jobs, observer)
}

/// Removes an output an earlier reproduction wrote for a case that has no feasible design now
/// (its best design's plots or capacity), so that no file describes a design the table does not
/// name; tells so.
fn remove_stale_output(path: &Path, observer: &mut dyn Observer) -> Result<(), ExperimentError> {
    if remove_stale(path)? {
        observer.event(Event::Removed { path });
    }
    Ok(())
}

/// Per case: the cost evolution of its seeds and the plots of its best design; and the radar
/// (or bar) chart of every case's best ratios.
fn write_case_plots(
    section: &Section<'_>,
    runs: &[OptimizeDocument],
    observer: &mut dyn Observer,
) -> Result<(), ExperimentError> {
    let (plan, task) = (section.plan, section.task);
    create_folder(&plan.layout.plots())?;
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
                let formulation = task.formulation_at(payload, space)?;
                write_plots(&folder, &formulation, best)?;
                radar_cases.push((format!("{space}, {payload} kg"), best.ratios.clone()));
            } else {
                remove_stale_output(&folder, observer)?;
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
    use super::wall_time_note;

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
}
