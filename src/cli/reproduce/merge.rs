//! `reproduce --from-runs`: the results that the plan's commands wrote (on other machines, by
//! GNU parallel or a Slurm job array), read back from the output folder.

use super::plan::{Plan, PAYLOADS, SPACES};
use super::Outcomes;
use crate::design::run::OptimizeDocument;
use crate::report::codesign::CapacityDocument;
use crate::report::table::{read_result_file, ResultFile};
use std::path::Path;

/// Reads every result the plan's commands write; fails naming the first that is missing or of
/// the wrong kind. A gradient run may be missing: the gradient method fails where it finds no
/// feasible start, and `reproduce` leaves that case out too.
pub fn read_all(plan: &Plan) -> Result<Outcomes, String> {
    let mut originals = Vec::new();
    for payload in PAYLOADS {
        for space in SPACES {
            let path = plan.original_file(space, payload);
            match read(&path)? {
                file @ ResultFile::Solve(_) => originals.push(file),
                _ => return Err(wrong_kind(&path, "a `solve` result")),
            }
        }
    }
    let optimize = |path: &Path| match read(path)? {
        ResultFile::Optimize(document) => Ok(*document),
        _ => Err(wrong_kind(path, "an `optimize` result")),
    };
    let runs = plan
        .cost_runs()
        .iter()
        .map(|run| optimize(&plan.run_file(run)))
        .collect::<Result<Vec<OptimizeDocument>, String>>()?;
    let gradient_runs = plan
        .gradient_runs()
        .iter()
        .map(|run| plan.run_file(run))
        .filter(|path| path.exists())
        .map(|path| optimize(&path))
        .collect::<Result<_, _>>()?;
    let beyond_runs = plan
        .beyond_runs()
        .iter()
        .map(|run| optimize(&plan.run_file(run)))
        .collect::<Result<_, _>>()?;
    let original_capacities = SPACES
        .iter()
        .map(|space| {
            let path = plan.capacity_file(&format!("{space}-original"));
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

/// Reads one result file, saying which command of the plan writes it when it is missing.
fn read(path: &Path) -> Result<ResultFile, String> {
    if !path.exists() {
        return Err(format!(
            "--from-runs: {} is missing; run every command of `codesign reproduce --plan` (with \
             the same flags) before merging",
            path.display()
        ));
    }
    read_result_file(path)
}

fn wrong_kind(path: &Path, expected: &str) -> String {
    format!("--from-runs: {} is not {expected}", path.display())
}
