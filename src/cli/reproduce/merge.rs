//! `reproduce --from-runs`: the results that the plan's commands wrote (on other machines, by
//! GNU parallel or a Slurm job array), read back from the output folder.

use super::Outcomes;
use crate::design::run::OptimizeDocument;
use crate::experiment::CapacityOf;
use crate::experiment::{Plan, PlannedRun, SPACES};
use crate::report::codesign::CapacityDocument;
use crate::report::table::{check_results, read_result_file, ResultFile};
use std::path::{Path, PathBuf};

/// Reads every result the plan's commands write; fails naming the first that is missing, of
/// the wrong kind, or of another task than the plan's (task hash `task_hash`). A gradient run
/// may be missing: the gradient method fails where it finds no feasible start, and `reproduce`
/// leaves that case out too.
pub fn read_all(plan: &Plan, task_hash: &str) -> Result<Outcomes, String> {
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
    check_results(&paths, &files).map_err(|why| format!("--from-runs: {why}"))?;
    let documents =
        |runs: Vec<(PathBuf, OptimizeDocument)>| runs.into_iter().map(|(_, d)| d).collect();
    let (runs, gradient_runs, beyond_runs) = (
        documents(runs),
        documents(gradient_runs),
        documents(beyond_runs),
    );
    let original_capacities = SPACES
        .iter()
        .map(|space| {
            let path = plan.layout.capacity(CapacityOf::Original(*space));
            match read(&path)? {
                ResultFile::Capacity(document) => Ok(*document),
                _ => Err(wrong_kind(&path, "a `capacity` result")),
            }
        })
        .collect::<Result<Vec<CapacityDocument>, String>>()?;
    Ok(Outcomes {
        originals,
        runs,
        gradient_runs,
        beyond_runs,
        original_capacities,
    })
}

/// Reads the result of the planned `run` at `path`; fails naming the settings in which it
/// differs from the plan (a run made with other flags is never merged as the plan's), its task
/// included (`task_hash`).
fn planned(path: &Path, run: &PlannedRun, task_hash: &str) -> Result<OptimizeDocument, String> {
    let ResultFile::Optimize(document) = read_of_task(path, task_hash)? else {
        return Err(wrong_kind(path, "an `optimize` result"));
    };
    let differences = run.case.differences(&document.inputs);
    if !differences.is_empty() {
        return Err(format!(
            "--from-runs: {} is not the plan's run ({}); run the plan's command for it again",
            path.display(),
            differences.join("; ")
        ));
    }
    Ok(*document)
}

/// The results of the planned `runs` of the task of `task_hash`, each with its path.
fn planned_all(
    plan: &Plan,
    task_hash: &str,
    runs: impl IntoIterator<Item = PlannedRun>,
) -> Result<Vec<(PathBuf, OptimizeDocument)>, String> {
    runs.into_iter()
        .map(|run| {
            let path = plan.layout.run(&run.name);
            planned(&path, &run, task_hash).map(|document| (path, document))
        })
        .collect()
}

/// Reads one result file ([`read`]); fails naming it when it records another task hash than
/// `task_hash`, the plan's (a file written before the hash was recorded is not checked).
fn read_of_task(path: &Path, task_hash: &str) -> Result<ResultFile, String> {
    let file = read(path)?;
    match file.task(None) {
        Some(recorded) if recorded != task_hash => Err(format!(
            "--from-runs: {} is a result of another task (task hash {recorded}, task file {}) \
             than the plan's (task hash {task_hash}); run the plan's command for it again",
            path.display(),
            file.task_file()
        )),
        _ => Ok(file),
    }
}

/// Reads one result file, saying which command of the plan writes it when it is missing.
fn read(path: &Path) -> Result<ResultFile, String> {
    if !path.exists() {
        return Err(format!(
            "--from-runs: {} is missing; run every command of `codesign reproduce --plan` (with \
             the same flags) before merging",
            path.display()
        ));
    }
    Ok(read_result_file(path)?)
}

fn wrong_kind(path: &Path, expected: &str) -> String {
    format!("--from-runs: {} is not {expected}", path.display())
}
