//! The committed evaluation logs (results/quick/runs, results/hold/runs and their kin) still resume, and the store
//! writes their header and entry lines byte for byte as they are on disk.

use crate::support;

use codesign::design::optimize::EvaluationLog;
use codesign::design::penalty::Penalty;
use codesign::design::run::OptimizeInputs;
use codesign::design::score::{Evaluation, Objective};
use codesign::store::log::{LogEntry, LogHeader, Start};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use support::{root, scratch};

/// The committed evaluation logs, sorted.
fn committed_logs() -> Vec<PathBuf> {
    // results/runs holds the full reproduction's logs while it runs (it may not exist yet).
    let folders = [
        "results/quick/runs",
        "results/quick/hold/runs",
        "results/hold/runs",
        "results/runs",
    ];
    let mut logs: Vec<PathBuf> = folders
        .iter()
        .filter_map(|folder| std::fs::read_dir(root().join(folder)).ok())
        .flatten()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.to_string_lossy().ends_with(".log.jsonl"))
        // A finished run's: a run still writing its log (the full reproduction's) has no result.
        .filter(|path| {
            let name = path.to_string_lossy();
            Path::new(&name.replace(".log.jsonl", ".json")).exists()
        })
        .collect();
    logs.sort();
    logs
}

#[test]
fn committed_logs_resume_and_their_lines_are_written_as_they_are() {
    let logs = committed_logs();
    assert!(logs.len() >= 40, "{} logs", logs.len());
    let dir = scratch("committed");
    for original in logs {
        let text = std::fs::read_to_string(&original).unwrap();
        let mut lines = text.lines();
        let first = lines.next().unwrap();
        let header: LogHeader = serde_json::from_str(first).unwrap();
        assert_eq!(serde_json::to_string(&header).unwrap(), first);
        let mut keys = HashSet::new();
        // Every entry is one the scoring writes, so that a resumption believes it.
        let inputs: OptimizeInputs = serde_json::from_value(header.run.clone()).unwrap();
        let penalty = Penalty {
            base: inputs.settings.penalty,
            grading: inputs.settings.grading,
        };
        let negative = matches!(inputs.settings.objective, Objective::Capacity(_));
        for line in lines {
            let entry = LogEntry::<Evaluation>::from_line(line)
                .unwrap_or_else(|why| panic!("{}: {why:?}", original.display()));
            assert_eq!(entry.to_line().unwrap(), line, "{}", original.display());
            let implausible = entry.evaluation.implausible(&penalty, negative);
            assert_eq!(implausible, None, "{}: {line}", original.display());
            keys.insert((entry.generation, entry.index));
        }
        let copy = dir.join(original.file_name().unwrap());
        std::fs::copy(&original, &copy).unwrap();
        let (log, finished) = EvaluationLog::open(&copy, &header.run, Start::Resume)
            .unwrap_or_else(|error| panic!("{error}"));
        assert_eq!(log.dropped_line(), None);
        assert_eq!(finished.len(), keys.len(), "{}", original.display());
        drop(log);
        assert!(
            std::fs::read(&copy).unwrap() == std::fs::read(&original).unwrap(),
            "{} changed on resuming",
            original.display()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An entry edited to make an invalid design feasible and the best, its checksum recomputed,
/// is refused on resuming, naming the log and the entry (issue 38, item 3).
#[test]
fn an_edited_entry_the_scoring_never_writes_is_refused() {
    let dir = scratch("edited");
    let committed = root().join("results/quick/runs/actuation-1kg-seed0.log.jsonl");
    let text = std::fs::read_to_string(&committed).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let header: LogHeader = serde_json::from_str(&lines[0]).unwrap();
    let (number, mut entry) = lines
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, line)| (k, LogEntry::<Evaluation>::from_line(line).unwrap()))
        .find(|(_, entry)| entry.evaluation.status.to_string() == "Invalid_Design")
        .expect("the committed run logs an invalid design");
    entry.evaluation.feasible = true;
    entry.evaluation.cost = 1e-9;
    lines[number] = entry.to_line().unwrap();
    let log = dir.join("o.log.jsonl");
    std::fs::write(&log, lines.join("\n") + "\n").unwrap();
    assert!(EvaluationLog::open(&log, &header.run, Start::Resume).is_ok());
    let output = support::codesign(&[
        "optimize",
        "--space",
        "actuation",
        "--payload",
        "1",
        "--seed",
        "0",
        "--population",
        "16",
        "--generations",
        "8",
        "--workers",
        "1",
        "--resume",
        "--out",
        dir.join("o.json").to_str().unwrap(),
    ]);
    let error = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{error}");
    assert!(
        error.contains("holds a feasible design with the status Invalid_Design"),
        "{error}"
    );
    assert!(error.contains("the log was edited"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}
