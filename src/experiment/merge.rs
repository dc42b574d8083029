//! The merge of an experiment run elsewhere: the results that the plan's commands wrote (on
//! other machines, by GNU parallel or a Slurm job array), read back from the output folder.

use super::{CapacityOf, MergeError, Outcomes, Plan, PlannedRun, SPACES};
use crate::design::run::OptimizeDocument;
use crate::report::codesign::CapacityDocument;
use crate::report::table::{check_results, read_result_file, ResultFile};
use std::path::{Path, PathBuf};

/// Reads every result the plan's commands write; fails naming the first that is missing, of
/// the wrong kind, or of another task than the plan's (task hash `task_hash`). A gradient run
/// may be missing: the gradient method fails where it finds no feasible start, and a run here
/// leaves that case out too.
pub fn read_all(plan: &Plan, task_hash: &str) -> Result<Outcomes, MergeError> {
    let read = |path: &Path| read_of_task(path, task_hash);
    let mut originals = Vec::new();
    let payloads = &plan.experiment.original_payloads_kg;
    for &payload in payloads {
        for space in SPACES {
            let path = plan.layout.original(space, payload);
            match read(&path)? {
                file @ ResultFile::Solve(_) => originals.push(file),
                _ => return Err(wrong_kind(&path, "a `solve` result")),
            }
        }
    }
    // A gradient run may be missing: the gradient method fails where it finds no feasible
    // start.
    let present = |run: &PlannedRun| plan.layout.run(&run.name).exists();
    let runs = planned_all(plan, task_hash, plan.cost_runs())?;
    let gradient_runs = planned_all(
        plan,
        task_hash,
        plan.gradient_runs().into_iter().filter(present),
    )?;
    let beyond_runs = planned_all(plan, task_hash, plan.beyond_runs())?;
    let mut paths: Vec<PathBuf> = payloads
        .iter()
        .flat_map(|&payload| SPACES.map(|space| plan.layout.original(space, payload)))
        .collect();
    let mut files = originals.clone();
    for (path, document) in runs.iter().chain(&gradient_runs).chain(&beyond_runs) {
        paths.push(path.clone());
        files.push(ResultFile::Optimize(Box::new(document.clone())));
    }
    check_results(&paths, &files).map_err(MergeError::Check)?;
    let documents =
        |runs: Vec<(PathBuf, OptimizeDocument)>| runs.into_iter().map(|(_, d)| d).collect();
    let original_capacities = SPACES
        .iter()
        .map(|space| {
            let path = plan.layout.capacity(CapacityOf::Original(*space));
            match read(&path)? {
                ResultFile::Capacity(document) => Ok(*document),
                _ => Err(wrong_kind(&path, "a `capacity` result")),
            }
        })
        .collect::<Result<Vec<CapacityDocument>, MergeError>>()?;
    Ok(Outcomes {
        originals,
        runs: documents(runs),
        gradient_runs: documents(gradient_runs),
        beyond_runs: documents(beyond_runs),
        original_capacities,
    })
}

/// Reads the result of the planned `run` at `path`; fails naming the settings in which it
/// differs from the plan (a run made with other flags is never merged as the plan's), its task
/// included (`task_hash`).
fn planned(path: &Path, run: &PlannedRun, task_hash: &str) -> Result<OptimizeDocument, MergeError> {
    let ResultFile::Optimize(document) = read_of_task(path, task_hash)? else {
        return Err(wrong_kind(path, "an `optimize` result"));
    };
    let differences = run.case.differences(&document.inputs);
    if !differences.is_empty() {
        return Err(MergeError::NotPlanned {
            path: path.to_owned(),
            differences,
        });
    }
    Ok(*document)
}

/// The results of the planned `runs` of the task of `task_hash`, each with its path.
fn planned_all(
    plan: &Plan,
    task_hash: &str,
    runs: impl IntoIterator<Item = PlannedRun>,
) -> Result<Vec<(PathBuf, OptimizeDocument)>, MergeError> {
    runs.into_iter()
        .map(|run| {
            let path = plan.layout.run(&run.name);
            planned(&path, &run, task_hash).map(|document| (path, document))
        })
        .collect()
}

/// Reads one result file ([`read`]); fails naming it when it records another task hash than
/// `task_hash`, the plan's (a file written before the hash was recorded is not checked).
fn read_of_task(path: &Path, task_hash: &str) -> Result<ResultFile, MergeError> {
    let file = read(path)?;
    match file.task() {
        Some(recorded) if recorded != task_hash => Err(MergeError::OtherTask {
            path: path.to_owned(),
            recorded,
            task_file: file.task_file().to_string(),
            expected: task_hash.to_owned(),
        }),
        _ => Ok(file),
    }
}

/// Reads one result file; a missing one is named as such.
fn read(path: &Path) -> Result<ResultFile, MergeError> {
    if !path.exists() {
        return Err(MergeError::Missing(path.to_owned()));
    }
    read_result_file(path).map_err(MergeError::Read)
}

/// A file of another kind than `expected` at `path`.
fn wrong_kind(path: &Path, expected: &'static str) -> MergeError {
    MergeError::WrongKind {
        path: path.to_owned(),
        expected,
    }
}
