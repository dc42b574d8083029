//! The evaluation log of a co-design run: JSON lines, appended as each evaluation finishes.
//!
//! The first line is a [`LogHeader`] describing the run; every further line is a [`LogEntry`].
//! `--resume` reads the log back, checks that the header matches the run being resumed, and
//! replays finished evaluations instead of solving them again. A last line cut short by an
//! interruption is ignored (and overwritten by the next append).
//!
//! Each entry also records the run's working time when it finished: wall time summed over the
//! invocations of the run, so a resumed run still knows how long it took in all.

use super::evaluate::Evaluation;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What makes two runs the same run: any difference forbids resuming.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogHeader {
    /// Always `codesign-evaluation-log`.
    pub format: String,
    /// The run's settings (task, space, modes, payload, seed, population, ...), as JSON.
    pub run: serde_json::Value,
}

/// One finished evaluation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogEntry {
    /// Generation (0 = the initial population).
    pub generation: usize,
    /// Index of the design in its generation.
    pub index: usize,
    /// The evaluation.
    #[serde(flatten)]
    pub evaluation: Evaluation,
    /// Wall time of the run when this evaluation finished, s, summed over its invocations (the
    /// time between an interruption and the last evaluation finished before it is not counted,
    /// as that work is done again). Absent in logs written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run_seconds: Option<f64>,
}

/// Finished evaluations of a log by (generation, index).
pub type Finished = HashMap<(usize, usize), Evaluation>;

/// An open log, appended to line by line.
#[derive(Debug)]
pub struct EvaluationLog {
    path: PathBuf,
    file: File,
    /// When this invocation opened the log.
    opened: Instant,
    /// The run's working time before this invocation, s; None when a resumed log has entries
    /// without it, so the run's total is unknown.
    earlier_seconds: Option<f64>,
}

const FORMAT: &str = "codesign-evaluation-log";

impl EvaluationLog {
    /// Starts a new log at `path`; refuses to overwrite an existing one (resume it instead).
    pub fn create<T: Serialize>(path: &Path, run: &T) -> Result<EvaluationLog, String> {
        let run = serde_json::to_value(run).map_err(|e| e.to_string())?;
        let mut file = OpenOptions::new().write(true).create_new(true).open(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                format!("the evaluation log {} exists already: pass --resume to continue that run, or --overwrite to start afresh", path.display())
            } else {
                format!("cannot create the evaluation log {}: {e}", path.display())
            }
        })?;
        let header = LogHeader {
            format: FORMAT.to_owned(),
            run,
        };
        let line = serde_json::to_string(&header).map_err(|e| e.to_string())?;
        writeln!(file, "{line}")
            .and_then(|()| file.sync_data())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        Ok(EvaluationLog {
            path: path.to_owned(),
            file,
            opened: Instant::now(),
            earlier_seconds: Some(0.0),
        })
    }

    /// Reopens the log at `path` of the same `run`, returning its finished evaluations by
    /// (generation, index). Fails when the file is missing or belongs to another run.
    pub fn resume<T: DeserializeOwned + PartialEq>(
        path: &Path,
        run: &T,
    ) -> Result<(EvaluationLog, Finished), String> {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| format!("cannot resume from {}: {e}", path.display()))?;
        let mut reader = BufReader::new(&mut file);
        let mut header_line = String::new();
        reader
            .read_line(&mut header_line)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let header: LogHeader = serde_json::from_str(&header_line).map_err(|e| {
            format!(
                "{} is not an evaluation log (first line: {e})",
                path.display()
            )
        })?;
        if header.format != FORMAT {
            return Err(format!("{} is not an evaluation log", path.display()));
        }
        // Compared as the run's type, so that a field added later with a default still matches
        // the logs written before it existed.
        let same = serde_json::from_value::<T>(header.run).is_ok_and(|logged| logged == *run);
        if !same {
            return Err(format!(
                "{} belongs to a different run (its settings differ from this command's); use another --out or remove it",
                path.display()
            ));
        }
        let mut finished = HashMap::new();
        let mut earlier_seconds = Some(0.0_f64);
        let mut valid_end = header_line.len() as u64;
        let mut line = String::new();
        loop {
            line.clear();
            let read = reader
                .read_line(&mut line)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            if read == 0 || !line.ends_with('\n') {
                break;
            }
            match serde_json::from_str::<LogEntry>(&line) {
                Ok(entry) => {
                    earlier_seconds = earlier_seconds
                        .zip(entry.run_seconds)
                        .map(|(latest, at)| latest.max(at));
                    finished.insert((entry.generation, entry.index), entry.evaluation);
                    valid_end += read as u64;
                }
                Err(_) => break,
            }
        }
        file.set_len(valid_end)
            .and_then(|()| file.seek(SeekFrom::End(0)))
            .map_err(|e| format!("cannot truncate {}: {e}", path.display()))?;
        Ok((
            EvaluationLog {
                path: path.to_owned(),
                file,
                opened: Instant::now(),
                earlier_seconds,
            },
            finished,
        ))
    }

    /// The run's working time before this invocation, s (None when the log predates that
    /// record).
    pub fn earlier_seconds(&self) -> Option<f64> {
        self.earlier_seconds
    }

    /// The run's working time so far, s: this invocation's since the log was opened plus the
    /// earlier invocations' as logged (None when the log predates that record).
    pub fn run_seconds(&self) -> Option<f64> {
        self.earlier_seconds
            .map(|earlier| earlier + self.opened.elapsed().as_secs_f64())
    }

    /// Appends the evaluation of design `index` of `generation`, stamped with the run's working
    /// time, and flushes it to disk.
    pub fn append(
        &mut self,
        generation: usize,
        index: usize,
        evaluation: &Evaluation,
    ) -> Result<(), String> {
        let entry = LogEntry {
            generation,
            index,
            evaluation: evaluation.clone(),
            run_seconds: self.run_seconds(),
        };
        let line = serde_json::to_string(&entry).map_err(|e| e.to_string())?;
        writeln!(self.file, "{line}")
            .and_then(|()| self.file.sync_data())
            .map_err(|e| format!("cannot append to {}: {e}", self.path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Run {
        seed: u64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        method: Option<String>,
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct NewerRun {
        seed: u64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        method: Option<String>,
        #[serde(default)]
        extra: u32,
    }

    fn entry(generation: usize, index: usize, cost: f64) -> LogEntry {
        LogEntry {
            generation,
            index,
            evaluation: Evaluation {
                ratios: vec![6.0, 3.0, 1.0, 0.1 + cost],
                cost,
                feasible: true,
                status: "Solve_Succeeded".into(),
                iterations: 30,
                seconds: 0.02,
                reason: None,
            },
            run_seconds: None,
        }
    }

    #[test]
    fn designs_read_back_equal_bit_for_bit() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..1000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let value = 1.0 + 8.0 * (state >> 11) as f64 / (1u64 << 53) as f64;
            let original = entry(1, 2, value);
            let text = serde_json::to_string(&original).unwrap();
            let back: LogEntry = serde_json::from_str(&text).unwrap();
            assert_eq!(
                back.evaluation.ratios[3].to_bits(),
                original.evaluation.ratios[3].to_bits()
            );
        }
    }

    #[test]
    fn resumes_its_own_run_and_drops_a_torn_last_line() {
        let path = std::env::temp_dir().join(format!("codesign-log-{}.jsonl", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let run = Run {
            seed: 3,
            method: None,
        };
        let append = |log: &mut EvaluationLog, e: LogEntry| {
            log.append(e.generation, e.index, &e.evaluation).unwrap()
        };
        let mut log = EvaluationLog::create(&path, &run).unwrap();
        append(&mut log, entry(0, 0, 1.5));
        append(&mut log, entry(0, 1, 2.5));
        drop(log);
        assert!(EvaluationLog::create(&path, &run)
            .unwrap_err()
            .contains("--resume"));
        let mut file = OpenOptions::new().append(true).open(&path).unwrap();
        write!(file, "{{\"generation\": 0, \"ind").unwrap();
        drop(file);
        let (mut log, finished) = EvaluationLog::resume(&path, &run).unwrap();
        assert_eq!(finished.len(), 2);
        assert_eq!(finished[&(0, 1)], entry(0, 1, 2.5).evaluation);
        append(&mut log, entry(0, 2, 3.5));
        drop(log);
        let (_, finished) = EvaluationLog::resume(&path, &run).unwrap();
        assert_eq!(finished.len(), 3);
        // A log written before a defaulted field existed still belongs to the run.
        let newer = NewerRun {
            seed: 3,
            method: None,
            extra: 0,
        };
        assert!(EvaluationLog::resume(&path, &newer).is_ok());
        let other = EvaluationLog::resume(
            &path,
            &Run {
                seed: 4,
                method: None,
            },
        );
        assert!(other.err().unwrap().contains("different run"));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn working_time_adds_up_over_invocations_and_is_unknown_for_old_logs() {
        let path =
            std::env::temp_dir().join(format!("codesign-log-time-{}.jsonl", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let run = Run {
            seed: 5,
            method: None,
        };
        let mut log = EvaluationLog::create(&path, &run).unwrap();
        log.earlier_seconds = Some(100.0); // as if a first invocation had worked 100 s
        log.append(0, 0, &entry(0, 0, 1.0).evaluation).unwrap();
        drop(log);
        let (log, _) = EvaluationLog::resume(&path, &run).unwrap();
        let total = log.run_seconds().unwrap();
        assert!((100.0..101.0).contains(&total), "{total}");
        drop(log);
        // An entry without the record (an older log): the run's total is unknown from then on.
        let mut file = OpenOptions::new().append(true).open(&path).unwrap();
        writeln!(
            file,
            "{}",
            serde_json::to_string(&entry(0, 1, 2.0)).unwrap()
        )
        .unwrap();
        drop(file);
        let (mut log, finished) = EvaluationLog::resume(&path, &run).unwrap();
        assert_eq!(finished.len(), 2);
        assert_eq!(log.run_seconds(), None);
        log.append(0, 2, &entry(0, 2, 3.0).evaluation).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(!text.lines().last().unwrap().contains("run_seconds"));
        std::fs::remove_file(&path).unwrap();
    }
}
