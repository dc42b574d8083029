//! The committed evaluation logs (results/quick/runs, results/hold/runs and their kin) still resume, and the store
//! writes their header and entry lines byte for byte as they are on disk.

mod support;

use codesign::design::optimize::EvaluationLog;
use codesign::design::score::Evaluation;
use codesign::store::log::{LogEntry, LogHeader, Start};
use std::collections::HashSet;
use std::path::PathBuf;
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
        for line in lines {
            let entry = LogEntry::<Evaluation>::from_line(line, header.checksums)
                .unwrap_or_else(|why| panic!("{}: {why:?}", original.display()));
            assert_eq!(entry.to_line().unwrap(), line, "{}", original.display());
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
