//! What `reproduce` prints as the experiment goes, and its errors in the command line's words.

use super::Failure;
use crate::cli::optimize::{ceiling_text, work_text};
use crate::cli::progress::progress_line;
use crate::cli::store_hints::run_error;
use crate::design::optimize::Progress;
use crate::design::run::OptimizeDocument;
use crate::design::score::Objective;
use crate::experiment::{Event, ExperimentError, MergeError, Observer, PlannedRun};

/// Prints each stage of the experiment on stdout as it finishes, and shows each co-design
/// run's progress line.
pub struct Printer;

impl Observer for Printer {
    fn progress(&self, total: u64, label: String) -> Box<dyn Progress> {
        progress_line(total, label)
    }

    fn event(&mut self, event: Event<'_>) {
        match event {
            Event::Original {
                space,
                payload_kg,
                result,
            } => {
                let verdict = match (&result.reason, result.feasible) {
                    (Some(reason), false) => format!("; infeasible: {reason}"),
                    _ => String::new(),
                };
                say!(
                    "original design, {space} space, {payload_kg} kg: {} J = {:.4} ({} \
                     iterations){verdict}",
                    result.status,
                    result.cost,
                    result.iterations
                );
            }
            Event::CostRun { run, document } => say!(
                "co-design, {} space, {} kg, seed {}: {} ({})",
                run.case.problem.space,
                document.inputs.payload_kg,
                run.case.settings.cmaes.seed,
                best_text(document),
                evaluations_text(document, "evaluations")
            ),
            Event::GradientRun { run, result } => gradient_run(run, result),
            Event::BeyondRun { run, document } => beyond_run(run, document),
            Event::Capacity { of, capacity_kg } => match capacity_kg {
                Some(kg) => say!("payload capacity, {of}: {kg} kg"),
                None => say!("payload capacity, {of}: infeasible even without payload"),
            },
            Event::Removed { path } => say!(
                "removed {}: its case has no feasible design in this reproduction",
                path.display()
            ),
            Event::Table { table, folder } => {
                say_raw!("{}", table.to_markdown());
                say!("results written to {}", folder.display());
            }
        }
    }
}

/// A CMA-ES run's best design and cost, or that it found no feasible design (a penalty is no
/// cost of a design).
fn best_text(document: &OptimizeDocument) -> String {
    match document.best_cost {
        None => "no feasible design found".to_owned(),
        Some(cost) => format!("best r = {:?}, J = {cost:.4}", document.best_ratios),
    }
}

/// A run's evaluations (called `what`) and where its solver time went, e.g. `144 evaluations;
/// median solve 12.0 ms, total solver time 3.1 s; invalid 3 of 144 (2.1%), ...`.
fn evaluations_text(document: &OptimizeDocument, what: &str) -> String {
    format!("{} {what}; {}", document.evaluations, work_text(document))
}

/// A gradient run's line: its best design, that it found none, or why it failed.
fn gradient_run(run: &PlannedRun, result: Result<&OptimizeDocument, crate::design::run::RunError>) {
    let space = run.case.problem.space;
    let payload = run.case.model.payload.unwrap_or_default();
    let penalty = run.case.settings.penalty();
    let label = format!("gradient co-design, {space} space, {payload} kg, {penalty} penalty");
    match result {
        Ok(document) => say!(
            "{label}: {} ({})",
            best_text(document),
            evaluations_text(document, "solves")
        ),
        Err(error) => say!("{label}: {}", run_error(error)),
    }
}

/// The line of a CMA-ES run beyond the paper, by its objective.
fn beyond_run(run: &PlannedRun, document: &OptimizeDocument) {
    let space = run.case.problem.space;
    match &run.case.settings.objective {
        Objective::Range(range) => say!(
            "range co-design, {space} space, {:?} kg: {} ({})",
            range.payloads_kg,
            best_text(document),
            evaluations_text(document, "evaluations")
        ),
        Objective::Capacity(_) => match document.best_cost {
            None => say!(
                "capacity co-design, {space} space: no design lifts any payload ({})",
                evaluations_text(document, "evaluations")
            ),
            Some(cost) => say!(
                "capacity co-design, {space} space: r = {:?} lifts {:.3} kg{} ({})",
                document.best_ratios,
                -cost,
                ceiling_text(document).map_or_else(String::new, |text| format!(", {text}")),
                evaluations_text(document, "evaluations")
            ),
        },
        // The experiment plans no energy or time run.
        Objective::Cost | Objective::Energy | Objective::Time => say!(
            "co-design, {space} space, {} kg, seed {}, penalty {}: {} ({})",
            document.inputs.payload_kg,
            run.case.settings.cmaes.seed,
            run.case.settings.penalty(),
            best_text(document),
            evaluations_text(document, "evaluations")
        ),
    }
}

/// An experiment's error with the flags that lead on from it.
pub fn experiment_error(error: ExperimentError) -> Failure {
    Failure::Work(match error {
        ExperimentError::Run(error) => run_error(error),
        error @ ExperimentError::EarlierLogs { .. } => format!(
            "{error}: pass --resume to continue it (finished evaluations are replayed) or \
             --overwrite to start afresh"
        ),
        ExperimentError::Merge(error) => merge_message(&error),
        error => error.to_string(),
    })
}

/// A merge's error, as `--from-runs` met it, with the command that mends it.
fn merge_message(error: &MergeError) -> String {
    match error {
        MergeError::Read(_) => error.to_string(),
        MergeError::Missing(_) => format!(
            "--from-runs: {error}; run every command of `codesign reproduce --plan` (with the \
             same flags) before merging"
        ),
        MergeError::OtherTask { .. } | MergeError::NotPlanned { .. } => {
            format!("--from-runs: {error}; run the plan's command for it again")
        }
        MergeError::WrongKind { .. } | MergeError::Check(_) => format!("--from-runs: {error}"),
    }
}

#[cfg(test)]
mod tests {
    use super::experiment_error;
    use crate::experiment::ExperimentError;
    use std::path::PathBuf;

    #[test]
    fn earlier_logs_name_the_two_ways_on() {
        let error = ExperimentError::EarlierLogs {
            folder: PathBuf::from("out/runs"),
            first: PathBuf::from("out/runs/joint-1kg-seed0.log.jsonl"),
            more: 2,
        };
        let message = experiment_error(error).to_string();
        assert_eq!(
            message,
            "out/runs holds the evaluation logs of an earlier reproduction \
             (out/runs/joint-1kg-seed0.log.jsonl and 2 more): pass --resume to continue it \
             (finished evaluations are replayed) or --overwrite to start afresh"
        );
    }
}
