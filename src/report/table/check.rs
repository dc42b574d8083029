//! The checks of a set of result files before they make one table: one motion, no result
//! twice, and numbers that a run can have written.

use super::ResultFile;
use crate::design::score::Objective;
use crate::report::codesign::CapacityDocument;
use crate::report::ReportError;
use codesign_core::model::task::{Horizon, MAX_PAYLOAD_KG};
use codesign_core::text::number;
use std::path::PathBuf;

/// Fails, naming the files, when two results are of different tasks (their task hashes differ;
/// a file without one, written before it was recorded, is of an unknown task that merges with
/// any: see [`ResultFile::task`]), when two describe
/// different motions (horizon or number of intervals), when one result is given twice (the same
/// file, or the same run under another name), or when a result holds a cost no run writes
/// (edited or damaged), or a solve of another design than the original one, which has no cell:
/// one table compares the results of one task, each once.
pub fn check_results(paths: &[PathBuf], files: &[ResultFile]) -> Result<(), ReportError> {
    for (path, file) in paths.iter().zip(files) {
        if let Some(why) = odd_value(file) {
            return Err(ReportError::Table(format!("{}: {why}", path.display())));
        }
    }
    let tasks: Vec<Option<String>> = files.iter().map(ResultFile::task).collect();
    for (i, a) in files.iter().enumerate() {
        for (j, b) in files.iter().enumerate().skip(i + 1) {
            let (first, second) = (paths[i].display(), paths[j].display());
            if let (Some(ta), Some(tb)) = (&tasks[i], &tasks[j]) {
                if ta != tb {
                    return Err(ReportError::Table(format!(
                        "{first} (task hash {ta}, task file {}) and {second} (task hash {tb}, \
                         task file {}) are results of different tasks; a table compares the \
                         results of one task",
                        a.task_file(),
                        b.task_file()
                    )));
                }
            }
            if let (Some((ha, na)), Some((hb, nb))) = (motion(a), motion(b)) {
                if (ha, na) != (hb, nb) {
                    return Err(ReportError::Table(format!("{first} (horizon {ha} s, {na} intervals) and {second} (horizon {hb} s, {nb} intervals) describe different motions; a table compares the results of one task")));
                }
            }
            if let (Some((payload, space)), true) = (row(a), row(a) == row(b)) {
                return Err(ReportError::Table(format!("{first} and {second} both solve the original design at {payload} kg in {space} space; pass one of them")));
            }
            if same_result(a, b) {
                return Err(ReportError::Table(format!(
                    "{first} and {second} hold the same result (the same run's settings, or one \
                     file under two names); pass one of them"
                )));
            }
        }
    }
    Ok(())
}

/// The horizon (s) and intervals of a result's motion, where it records them.
pub(super) fn motion(file: &ResultFile) -> Option<(Horizon, usize)> {
    let motion = match file {
        ResultFile::Solve(d) => &d.inputs.task.task.motion,
        ResultFile::Optimize(d) => &d.inputs.task.task.motion,
        ResultFile::Capacity(_) => return None,
    };
    Some((motion.horizon, motion.steps))
}

/// The table row of a solve of the original design: (payload kg, space).
fn row(file: &ResultFile) -> Option<(f64, codesign_core::problem::Space)> {
    match file {
        ResultFile::Solve(d) if d.result.ratios == d.inputs.task.task.transmission.original => {
            Some((d.inputs.payload_kg, d.inputs.space))
        }
        _ => None,
    }
}

/// Whether two results are one: runs with the same settings, solves of the same design and
/// inputs, capacity searches of the same design.
fn same_result(a: &ResultFile, b: &ResultFile) -> bool {
    match (a, b) {
        (ResultFile::Optimize(a), ResultFile::Optimize(b)) => a.inputs == b.inputs,
        (ResultFile::Solve(a), ResultFile::Solve(b)) => {
            a.inputs == b.inputs && a.result.ratios == b.result.ratios
        }
        (ResultFile::Capacity(a), ResultFile::Capacity(b)) => {
            let (a, b) = (&a.inputs, &b.inputs);
            (&a.task_file, a.space, &a.ratios, a.limit_modes, a.settings)
                == (&b.task_file, b.space, &b.ratios, b.limit_modes, b.settings)
        }
        _ => false,
    }
}

/// What is wrong when a result holds a cost or mass no run writes: a trajectory cost J (a sum
/// of squares) below zero or not a number, a capacity below zero (a capacity run's best cost is
/// minus a capacity; none without a feasible design).
fn odd_value(file: &ResultFile) -> Option<String> {
    let cost = |name: &str, value: f64| {
        (!(value.is_finite() && value >= 0.0)).then(|| {
            format!(
                "{name} = {value} is not a trajectory cost (J is a sum of squares, >= 0); the \
                 file was edited or damaged"
            )
        })
    };
    match file {
        ResultFile::Optimize(d) => match d.inputs.settings.objective {
            // The capacity objective minimises minus the payload: its best cost is <= 0, or
            // the penalty (at least its base) when every design was infeasible, as every one
            // is whose motors cannot hold the arm at rest.
            // Files written before a best design had to be feasible hold an infeasible one at
            // the penalty (at least its base), as every design is whose motors cannot hold the
            // arm at rest.
            Objective::Capacity(_) => match d.best_cost {
                Some(best) if !(best.is_finite() && best >= d.inputs.settings.penalty) => {
                    cost("best_cost", -best)
                }
                _ => None,
            },
            Objective::Cost | Objective::Range(_) | Objective::Energy | Objective::Time => (d
                .best_cost)
                .and_then(|best| cost("best_cost", best))
                .or_else(|| cost("original_cost", d.original_cost)),
        },
        // The table places the original design's solves; any other design has no cell.
        ResultFile::Solve(d) if d.result.ratios != d.inputs.task.task.transmission.original => {
            Some(format!(
                "a solve of r = {:?}, not of the task's original design {:?}: the table places \
                 only the original design's solves (a co-design run's result places its best)",
                d.result.ratios, d.inputs.task.task.transmission.original
            ))
        }
        ResultFile::Solve(d) => cost("cost", d.result.cost),
        ResultFile::Capacity(d) => odd_capacity(d),
    }
    .or_else(|| odd_count(file))
}

/// What is wrong when a capacity search's result holds a mass no search writes: a capacity
/// that is no payload, or above the search's own `max_kg` or the largest payload a task may
/// carry.
fn odd_capacity(d: &CapacityDocument) -> Option<String> {
    let max = d.inputs.settings.max_kg;
    let edited = "the file was edited or damaged";
    if !(max.is_finite() && max > 0.0 && max <= MAX_PAYLOAD_KG) {
        return Some(format!(
            "settings.max_kg = {} is not a search's range (0 to {MAX_PAYLOAD_KG} kg); {edited}",
            number(max)
        ));
    }
    let kg = d.capacity.capacity_kg?;
    if !(kg.is_finite() && kg >= 0.0) {
        return Some(format!("capacity_kg = {kg} is not a payload; {edited}"));
    }
    (kg > max).then(|| {
        format!(
            "capacity_kg = {} is above the search's max_kg = {}; {edited}",
            number(kg),
            number(max)
        )
    })
}

/// What is wrong when a co-design run's counts disagree: one cost per evaluation, and no more
/// evaluations replayed, solved or invalid than there were.
fn odd_count(file: &ResultFile) -> Option<String> {
    let ResultFile::Optimize(d) = file else {
        return None;
    };
    let edited = "the file was edited or damaged";
    if d.costs.len() != d.evaluations {
        return Some(format!(
            "evaluations = {} but costs holds {}; {edited}",
            d.evaluations,
            d.costs.len()
        ));
    }
    let most = |name: &str, count: usize| {
        (count > d.evaluations).then(|| {
            format!(
                "{name} = {count} is more than evaluations = {}; {edited}",
                d.evaluations
            )
        })
    };
    most("replayed", d.replayed)
        .or_else(|| most("solves", d.solves))
        .or_else(|| {
            let verdicts = d.verdicts.as_ref();
            most("verdicts", verdicts.map_or(0, |v| v.evaluations()))
        })
}
