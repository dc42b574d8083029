//! The evaluation log of a co-design run: JSON lines, appended as each evaluation finishes.
//!
//! The first line is a [`LogHeader`] describing the run; every further line is a [`LogEntry`]
//! carrying a checksum of its content. A resumed run reads the log back, checks that the header
//! matches the run being resumed and every record its checksum, and replays finished evaluations
//! instead of solving them again. Only a last line cut short by an interruption is dropped (and
//! overwritten by the next append); a damaged line anywhere else is an error naming it.
//!
//! An open log holds an advisory lock (`flock`) for as long as it is open, so that two runs on
//! one log cannot both write it: the second fails at once, naming the first's process.
//!
//! Each entry also records the run's working time when it finished: wall time summed over the
//! invocations of the run, so a resumed run still knows how long it took in all.
//!
//! The log is generic over what an entry holds (`E`, serialised flattened into the entry's
//! object): the design level logs its evaluations.

use super::files::{resolved, same_file};
use super::lines::{next_line, Line};
use super::lock::lock_file;
use super::{Action, Damage, StoreError, Thing};
use codesign_core::hash::fnv1a;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{BufReader, Seek, SeekFrom, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The extension of an evaluation log, which sits beside its result file.
pub const LOG_EXTENSION: &str = "log.jsonl";

/// The evaluation log of the result file `output`, `x.json` -> `x.log.jsonl`, beside the file
/// that writing `output` replaces (the one a symbolic link points to): every name of one output
/// has one log, and so one lock.
pub fn log_beside(output: &Path) -> PathBuf {
    resolved(output).with_extension(LOG_EXTENSION)
}

/// What makes two runs the same run: any difference forbids resuming.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogHeader {
    /// Always `codesign-evaluation-log`.
    pub format: String,
    /// The run's settings (task, space, modes, payload, seed, population, ...), as JSON.
    pub run: Value,
    /// Whether every entry carries a checksum: true in every log this build reads (false or
    /// absent in logs written before checksums, which `codesign migrate` brings to this format).
    pub checksums: bool,
}

/// One finished evaluation, holding `E`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogEntry<E> {
    /// Generation (0 = the initial population).
    pub generation: usize,
    /// Index of the design in its generation.
    pub index: usize,
    /// The evaluation, its fields inline in the entry's object.
    #[serde(flatten)]
    pub evaluation: E,
    /// Wall time of the run when this evaluation finished, s, summed over its invocations (the
    /// time between an interruption and the last evaluation finished before it is not counted,
    /// as that work is done again). Absent in logs written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run_seconds: Option<f64>,
    /// FNV-1a hash (16 hex digits) of the entry's JSON without this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<String>,
}

/// A run as a log's header records it.
pub trait LoggedRun: Serialize + DeserializeOwned {
    /// Whether the logged run `self` is `run`, which may then resume it: equal, but for what
    /// only names an input whose content the run records otherwise (a path as it was spelled).
    fn same_run(&self, run: &Self) -> bool;
}

/// A run known only as its JSON (a log read back by a tool): the same run when equal.
impl LoggedRun for Value {
    fn same_run(&self, run: &Value) -> bool {
        self == run
    }
}

/// Finished evaluations of a log by (generation, index).
pub type Finished<E> = HashMap<(usize, usize), E>;

/// How a run treats a log already at its path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// Refuse it (the user decides between resuming and overwriting).
    Fresh,
    /// Continue it (or start a new one where there is none).
    Resume,
    /// Empty it and start afresh.
    Overwrite,
}

impl Start {
    /// The start asked for by a request to resume and one to overwrite (exclusive; resuming
    /// wins), neither being a fresh start.
    pub fn from_flags(resume: bool, overwrite: bool) -> Start {
        match (resume, overwrite) {
            (true, _) => Start::Resume,
            (false, true) => Start::Overwrite,
            (false, false) => Start::Fresh,
        }
    }
}

/// An open log of entries holding `E`, appended to line by line, locked against other runs while
/// open.
#[derive(Debug)]
pub struct EvaluationLog<E> {
    path: PathBuf,
    file: File,
    /// When this invocation opened the log.
    opened: Instant,
    /// The run's working time before this invocation, s; None when a resumed log has entries
    /// without it, so the run's total is unknown.
    earlier_seconds: Option<f64>,
    /// Whether this invocation created the file or emptied it.
    created: bool,
    /// Entries appended by this invocation.
    appended: usize,
    /// The number of a torn last line dropped on resuming, if any.
    dropped_line: Option<usize>,
    /// What the entries hold.
    entries: PhantomData<fn(&E)>,
}

const FORMAT: &str = super::LOG_FORMAT;

/// The checksum of a log line's text: FNV-1a, 64 bits, as 16 hex digits.
fn checksum(text: &str) -> String {
    fnv1a(text.as_bytes())
}

impl<E: Serialize> LogEntry<E> {
    /// The entry's line, without its end: its JSON, with the checksum of its JSON without one.
    pub fn to_line(&self) -> Result<String, serde_json::Error> {
        let unchecked = LogEntry {
            generation: self.generation,
            index: self.index,
            evaluation: &self.evaluation,
            run_seconds: self.run_seconds,
            check: None,
        };
        let check = checksum(&serde_json::to_string(&unchecked)?);
        serde_json::to_string(&LogEntry {
            check: Some(check),
            ..unchecked
        })
    }
}

impl<E: Serialize + DeserializeOwned> LogEntry<E> {
    /// Parses an entry line and checks its checksum, which it must carry; the entry returned
    /// has none.
    pub fn from_line(line: &str) -> Result<LogEntry<E>, Damage> {
        let mut entry: LogEntry<E> =
            serde_json::from_str(line).map_err(|e| Damage::NotARecord(e.to_string()))?;
        let logged = entry.check.take().ok_or(Damage::NoChecksum)?;
        let text = serde_json::to_string(&entry).map_err(|e| Damage::NotARecord(e.to_string()))?;
        match checksum(&text) == logged {
            true => Ok(entry),
            false => Err(Damage::ChecksumMismatch),
        }
    }
}

/// Opens (creating if absent) and locks the log at `path`; returns the file and whether this
/// call created it. Fails at once when another process holds the lock, naming it.
fn open_locked(path: &Path) -> Result<(File, bool), StoreError> {
    let thing = Thing::EvaluationLog;
    let options = || OpenOptions::new().read(true).write(true).clone();
    let (file, created) = match options().create_new(true).open(path) {
        Ok(file) => (file, true),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => (
            options()
                .open(path)
                .map_err(|e| StoreError::io(Action::Open(thing), path, &e))?,
            false,
        ),
        Err(e) => return Err(StoreError::io(Action::Create(thing), path, &e)),
    };
    lock_file(&file, thing, path)?;
    // Another run may have replaced the file between the open and the lock.
    match (std::fs::metadata(path), file.metadata()) {
        (Ok(a), Ok(b)) if same_file(&a, &b) => Ok((file, created)),
        _ => Err(StoreError::Replaced {
            path: path.to_owned(),
        }),
    }
}

/// The settings in which `logged` and `current` differ, as `path: log X, this command Y`.
fn differences(logged: &Value, current: &Value, path: &str, found: &mut Vec<String>) {
    if let (Value::Object(a), Value::Object(b)) = (logged, current) {
        let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
        keys.sort();
        keys.dedup();
        for key in keys {
            let inner = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            differences(
                a.get(key).unwrap_or(&Value::Null),
                b.get(key).unwrap_or(&Value::Null),
                &inner,
                found,
            );
        }
    } else if logged != current {
        let short = |value: &Value| {
            let text = value.to_string();
            match text.char_indices().nth(60) {
                Some((end, _)) => format!("{}...", &text[..end]),
                None => text,
            }
        };
        found.push(format!(
            "{path}: log {}, this command {}",
            short(logged),
            short(current)
        ));
    }
}

/// Why a first line is no header of a log this build reads.
enum NoHeader {
    /// The file is no log: the parser's reason, None for JSON of a header of another format.
    Foreign(Option<String>),
    /// A log of an older format (without checksums): the parser's reason, if any.
    Old(Option<String>),
}

/// The header of a log whose first line is `first`, and that line's length in bytes; else why
/// the file is no log of this build's.
fn header_of(first: Option<Line>) -> Result<(LogHeader, usize), NoHeader> {
    let text = (first.ok_or_else(|| "the file is empty".to_owned()))
        .and_then(Line::text)
        .map_err(|why| NoHeader::Foreign(Some(why)))?;
    match serde_json::from_str::<LogHeader>(&text) {
        Ok(header) if header.format != FORMAT => Err(NoHeader::Foreign(None)),
        Ok(header) if !header.checksums => Err(NoHeader::Old(None)),
        Ok(header) => Ok((header, text.len())),
        Err(e) if text.starts_with(super::LOG_HEADER_PREFIX) => {
            Err(NoHeader::Old(Some(e.to_string())))
        }
        Err(e) => match serde_json::from_str::<Value>(&text) {
            Ok(value) if value.get("format").is_some_and(|f| f != FORMAT) => {
                Err(NoHeader::Foreign(None))
            }
            _ => Err(NoHeader::Foreign(Some(e.to_string()))),
        },
    }
}

/// What a non-empty file where a log goes holds.
enum Contents {
    /// A log header and entries.
    Entries,
    /// A log header alone: a run that ended before its first evaluation.
    HeaderOnly,
    /// A log of an older format, to migrate before resuming.
    Old,
    /// No log: the parser's reason, when its first line is no JSON of a header.
    Foreign(Option<String>),
}

impl<E: Serialize + DeserializeOwned> EvaluationLog<E> {
    /// Opens the log at `path` for `run`, locked against any other run while it is open. A
    /// missing or empty log starts afresh; an existing one is refused, resumed (its finished
    /// evaluations are returned by (generation, index)) or emptied, as `start` says.
    pub fn open<T: LoggedRun>(
        path: &Path,
        run: &T,
        start: Start,
    ) -> Result<(EvaluationLog<E>, Finished<E>), StoreError> {
        let (file, created) = open_locked(path)?;
        let length = file
            .metadata()
            .map_err(|e| StoreError::io(Action::Read, path, &e))?
            .len();
        let mut log = EvaluationLog {
            path: path.to_owned(),
            file,
            opened: Instant::now(),
            earlier_seconds: Some(0.0),
            created,
            appended: 0,
            dropped_line: None,
            entries: PhantomData,
        };
        if length > 0 {
            let contents = log.contents()?;
            match (start, contents) {
                // An old log is refused in its reading, naming `codesign migrate`.
                (Start::Resume, Contents::Entries | Contents::Old) => return log.replay(run),
                (Start::Fresh, Contents::Entries | Contents::Old) => {
                    return Err(StoreError::LogExists {
                        path: path.to_owned(),
                    })
                }
                // Someone else's file where the log goes: only --overwrite replaces it.
                (Start::Fresh | Start::Resume, Contents::Foreign(why)) => {
                    return Err(StoreError::NotALog {
                        path: path.to_owned(),
                        why,
                    })
                }
                // Overwritten, or a header alone: nothing is lost.
                _ => {
                    log.file
                        .set_len(0)
                        .and_then(|()| log.file.seek(SeekFrom::Start(0)))
                        .map_err(|e| StoreError::io(Action::Empty, path, &e))?;
                    log.created = true;
                }
            }
        }
        let header = LogHeader {
            format: FORMAT.to_owned(),
            run: serde_json::to_value(run).map_err(|e| log.serialise_error(&e))?,
            checksums: true,
        };
        let line = serde_json::to_string(&header).map_err(|e| log.serialise_error(&e))?;
        log.write_line(&line)?;
        Ok((log, Finished::new()))
    }

    /// Reads a non-empty log back for `run`: checks its header and every entry, drops a torn
    /// last line, and leaves the file positioned for appending.
    fn replay<T: LoggedRun>(
        mut self,
        run: &T,
    ) -> Result<(EvaluationLog<E>, Finished<E>), StoreError> {
        let read_error = |e: std::io::Error| StoreError::io(Action::Read, &self.path, &e);
        let mut reader = BufReader::new(&self.file);
        let first = next_line(&mut reader).map_err(read_error)?;
        let (header, header_bytes) = header_of(first).map_err(|problem| match problem {
            NoHeader::Foreign(why) => StoreError::NotALog {
                path: self.path.clone(),
                why,
            },
            NoHeader::Old(why) => StoreError::OldLog {
                path: self.path.clone(),
                why,
            },
        })?;
        self.check_same_run(&header.run, run)?;
        let mut finished = HashMap::new();
        let mut valid_end = header_bytes;
        let mut dropped_line = None;
        let mut earlier_seconds = self.earlier_seconds;
        for number in 2.. {
            let damaged = |why| StoreError::DamagedLine {
                path: self.path.clone(),
                line: number,
                why,
            };
            let line = match next_line(&mut reader).map_err(read_error)? {
                None => break,
                Some(Line::Whole(text)) => text,
                // Only the last line can lack its end: an append cut short.
                Some(Line::Torn(_)) => {
                    dropped_line = Some(number);
                    break;
                }
                Some(other) => return Err(damaged(Damage::NotALine(other.text().unwrap_err()))),
            };
            let entry = LogEntry::<E>::from_line(&line).map_err(damaged)?;
            earlier_seconds = earlier_seconds
                .zip(entry.run_seconds)
                .map(|(latest, at)| latest.max(at));
            finished.insert((entry.generation, entry.index), entry.evaluation);
            valid_end += line.len();
        }
        drop(reader);
        self.dropped_line = dropped_line;
        self.earlier_seconds = earlier_seconds;
        self.file
            .set_len(valid_end as u64)
            .and_then(|()| self.file.seek(SeekFrom::End(0)))
            .map_err(|e| StoreError::io(Action::Truncate, &self.path, &e))?;
        Ok((self, finished))
    }

    /// Fails, naming the differing settings, unless the logged run is `run`, compared as the
    /// run's type; one that does not read as it (a setting missing) is of an older log.
    fn check_same_run<T: LoggedRun>(&self, logged: &Value, run: &T) -> Result<(), StoreError> {
        let logged =
            serde_json::from_value::<T>(logged.clone()).map_err(|e| StoreError::OldLog {
                path: self.path.clone(),
                why: Some(e.to_string()),
            })?;
        if logged.same_run(run) {
            return Ok(());
        }
        let logged = serde_json::to_value(logged).unwrap_or(Value::Null);
        let current = serde_json::to_value(run).map_err(|e| self.serialise_error(&e))?;
        let mut found = Vec::new();
        differences(&logged, &current, "", &mut found);
        let more = found.len().saturating_sub(3);
        found.truncate(3);
        if more > 0 {
            found.push(format!("{more} more"));
        }
        Err(StoreError::DifferentRun {
            path: self.path.clone(),
            differences: found,
        })
    }

    /// What the non-empty file at the log's path holds: a log with entries, a log header alone,
    /// or something else; leaves the file at its start.
    fn contents(&mut self) -> Result<Contents, StoreError> {
        let mut reader = BufReader::new(&self.file);
        let read = next_line(&mut reader)
            .and_then(|first| Ok((first, next_line(&mut reader)?.is_some())))
            .and_then(|read| self.file.seek(SeekFrom::Start(0)).map(|_| read));
        let (first, more) = read.map_err(|e| StoreError::io(Action::Read, &self.path, &e))?;
        Ok(match header_of(first) {
            Err(NoHeader::Foreign(why)) => Contents::Foreign(why),
            Err(NoHeader::Old(_)) => Contents::Old,
            Ok(_) if more => Contents::Entries,
            Ok(_) => Contents::HeaderOnly,
        })
    }

    /// The number of the torn last line dropped on resuming, if there was one.
    pub fn dropped_line(&self) -> Option<usize> {
        self.dropped_line
    }

    /// Removes the log when this invocation created (or emptied) it and appended nothing (a run
    /// that failed before its first evaluation leaves nothing behind); otherwise just closes it.
    pub fn discard_if_unused(self) -> Result<(), StoreError> {
        if self.created && self.appended == 0 {
            std::fs::remove_file(&self.path)
                .map_err(|e| StoreError::io(Action::Remove, &self.path, &e))?;
        }
        Ok(())
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
    /// time and checksummed, and flushes it to disk.
    pub fn append(
        &mut self,
        generation: usize,
        index: usize,
        evaluation: &E,
    ) -> Result<(), StoreError> {
        let entry = LogEntry {
            generation,
            index,
            evaluation,
            run_seconds: self.run_seconds(),
            check: None,
        };
        let line = entry.to_line().map_err(|e| self.serialise_error(&e))?;
        self.write_line(&line)?;
        self.appended += 1;
        Ok(())
    }

    /// Writes `line` and its end in one write and flushes it to disk.
    fn write_line(&mut self, line: &str) -> Result<(), StoreError> {
        let whole = format!("{line}\n");
        self.file
            .write_all(whole.as_bytes())
            .and_then(|()| self.file.sync_data())
            .map_err(|e| StoreError::io(Action::Write, &self.path, &e))
    }

    /// The failure to serialise a line of this log.
    fn serialise_error(&self, error: &serde_json::Error) -> StoreError {
        StoreError::Serialise {
            path: self.path.clone(),
            why: error.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    impl LoggedRun for Run {
        fn same_run(&self, run: &Run) -> bool {
            self == run
        }
    }

    impl LoggedRun for NewerRun {
        fn same_run(&self, run: &NewerRun) -> bool {
            self == run
        }
    }

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
        extra: u32,
    }

    /// What an entry holds in these tests: a design and its cost.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    struct Design {
        ratios: Vec<f64>,
        cost: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reason: Option<String>,
    }

    type Log = EvaluationLog<Design>;

    fn entry(generation: usize, index: usize, cost: f64) -> LogEntry<Design> {
        LogEntry {
            generation,
            index,
            evaluation: Design {
                ratios: vec![6.0, 3.0, 1.0, 0.1 + cost],
                cost,
                reason: None,
            },
            run_seconds: None,
            check: None,
        }
    }

    fn create(path: &Path, run: &Run) -> Log {
        Log::open(path, run, Start::Fresh).unwrap().0
    }

    fn scratch(name: &str) -> PathBuf {
        let path =
            std::env::temp_dir().join(format!("codesign-log-{name}-{}.jsonl", std::process::id()));
        let _ = std::fs::remove_file(&path);
        path
    }

    #[test]
    fn every_name_of_one_output_has_one_log() {
        let folder =
            std::env::temp_dir().join(format!("codesign-log-names-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let out = folder.join("a.json");
        assert_eq!(log_beside(&out), folder.join("a.log.jsonl"));
        std::fs::write(&out, "{}").unwrap();
        let alias = folder.join("alias.json");
        std::os::unix::fs::symlink(&out, &alias).unwrap();
        let real = std::fs::canonicalize(&folder).unwrap().join("a.log.jsonl");
        assert_eq!(log_beside(&alias), real);
        std::fs::remove_dir_all(&folder).unwrap();
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
            let line = original.to_line().unwrap();
            let back = LogEntry::<Design>::from_line(&line).unwrap();
            assert_eq!(
                back.evaluation.ratios[3].to_bits(),
                original.evaluation.ratios[3].to_bits()
            );
            assert_eq!(back.to_line().unwrap(), line);
        }
    }

    #[test]
    fn lines_keep_their_format() {
        let mut written = entry(0, 1, 2.5);
        written.run_seconds = Some(0.25);
        let line = written.to_line().unwrap();
        let text =
            r#"{"generation":0,"index":1,"ratios":[6.0,3.0,1.0,2.6],"cost":2.5,"run_seconds":0.25"#;
        assert_eq!(
            line,
            format!(r#"{text},"check":"{}"}}"#, checksum(&format!("{text}}}")))
        );
        let path = scratch("format");
        let run = Run {
            seed: 7,
            method: Some("cmaes".into()),
        };
        drop(create(&path, &run));
        let header = r#"{"format":"codesign-evaluation-log","run":{"method":"cmaes","seed":7},"checksums":true}"#;
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            format!("{header}\n")
        );
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn resumes_its_own_run_and_drops_a_torn_last_line() {
        let path = scratch("resume");
        let run = Run {
            seed: 3,
            method: None,
        };
        let append = |log: &mut Log, e: LogEntry<Design>| {
            log.append(e.generation, e.index, &e.evaluation).unwrap()
        };
        let mut log = create(&path, &run);
        append(&mut log, entry(0, 0, 1.5));
        append(&mut log, entry(0, 1, 2.5));
        drop(log);
        let error = Log::open(&path, &run, Start::Fresh).unwrap_err();
        assert_eq!(error, StoreError::LogExists { path: path.clone() });
        let mut file = OpenOptions::new().append(true).open(&path).unwrap();
        write!(file, "{{\"generation\": 0, \"ind").unwrap();
        drop(file);
        let (mut log, finished) = Log::open(&path, &run, Start::Resume).unwrap();
        assert_eq!(log.dropped_line(), Some(4));
        assert_eq!(finished.len(), 2);
        assert_eq!(finished[&(0, 1)], entry(0, 1, 2.5).evaluation);
        append(&mut log, entry(0, 2, 3.5));
        drop(log);
        let (_, finished) = Log::open(&path, &run, Start::Resume).unwrap();
        assert_eq!(finished.len(), 3);
        // A log written before a field of the run existed is an older log, to migrate.
        let newer = NewerRun {
            seed: 3,
            method: None,
            extra: 0,
        };
        let error = Log::open(&path, &newer, Start::Resume).unwrap_err();
        assert!(matches!(error, StoreError::OldLog { .. }), "{error:?}");
        let migrate = format!("run `codesign migrate {}`", path.display());
        assert!(error.to_string().contains(&migrate), "{error}");
        let other = Run {
            seed: 4,
            method: None,
        };
        let error = Log::open(&path, &other, Start::Resume).unwrap_err();
        assert_eq!(
            error,
            StoreError::DifferentRun {
                path: path.clone(),
                differences: vec!["seed: log 3, this command 4".to_owned()],
            }
        );
        assert!(
            error
                .to_string()
                .ends_with("belongs to a different run (seed: log 3, this command 4)"),
            "{error}"
        );
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn working_time_adds_up_over_invocations_and_is_unknown_for_old_logs() {
        let path = scratch("time");
        let run = Run {
            seed: 5,
            method: None,
        };
        let mut log = create(&path, &run);
        log.earlier_seconds = Some(100.0); // as if a first invocation had worked 100 s
        log.append(0, 0, &entry(0, 0, 1.0).evaluation).unwrap();
        drop(log);
        let (log, _) = Log::open(&path, &run, Start::Resume).unwrap();
        let total = log.run_seconds().unwrap();
        assert!((100.0..101.0).contains(&total), "{total}");
        drop(log);
        // An entry without the record (an older log): the run's total is unknown from then on.
        let mut file = OpenOptions::new().append(true).open(&path).unwrap();
        writeln!(file, "{}", entry(0, 1, 2.0).to_line().unwrap()).unwrap();
        drop(file);
        let (mut log, finished) = Log::open(&path, &run, Start::Resume).unwrap();
        assert_eq!(finished.len(), 2);
        assert_eq!(log.run_seconds(), None);
        log.append(0, 2, &entry(0, 2, 3.0).evaluation).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(!text.lines().last().unwrap().contains("run_seconds"));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn damaged_or_edited_lines_are_errors_naming_them() {
        let path = scratch("bad");
        let run = Run {
            seed: 1,
            method: None,
        };
        let mut log = create(&path, &run);
        for index in 0..3 {
            log.append(0, index, &entry(0, index, 1.0).evaluation)
                .unwrap();
        }
        drop(log);
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let rewrite = |third: &str| {
            let mut edited = lines.clone();
            edited[2] = third;
            std::fs::write(&path, edited.join("\n") + "\n").unwrap();
        };
        rewrite("garbage");
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert!(
            matches!(
                error,
                StoreError::DamagedLine {
                    line: 3,
                    why: Damage::NotARecord(_),
                    ..
                }
            ),
            "{error:?}"
        );
        assert!(
            error
                .to_string()
                .contains("line 3: not an evaluation record"),
            "{error}"
        );
        assert_eq!(
            std::fs::read_to_string(&path).unwrap().lines().count(),
            4,
            "nothing dropped"
        );
        let edited = lines[2].replacen("\"cost\":1.0", "\"cost\":0.5", 1);
        assert_ne!(edited, lines[2]);
        rewrite(&edited);
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert_eq!(
            error,
            StoreError::DamagedLine {
                path: path.clone(),
                line: 3,
                why: Damage::ChecksumMismatch,
            }
        );
        assert!(
            error
                .to_string()
                .contains("line 3: its checksum does not match"),
            "{error}"
        );
        std::fs::write(&path, "{\"format\":\"other\",\"run\":{}}\n{}\n").unwrap();
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert_eq!(
            error,
            StoreError::NotALog {
                path: path.clone(),
                why: None
            }
        );
        std::fs::remove_file(&path).unwrap();
    }

    /// A log written before checksums is one to migrate: resuming it names `codesign migrate`,
    /// a fresh run finds it in the way, and only `--overwrite` replaces it.
    #[test]
    fn a_log_without_checksums_is_refused_naming_migrate() {
        let path = scratch("unchecked");
        let run = Run {
            seed: 1,
            method: None,
        };
        let old = "{\"format\":\"codesign-evaluation-log\",\"run\":{\"seed\":1}}\n\
                   {\"generation\":0,\"index\":0,\"ratios\":[1.0],\"cost\":1.0}\n";
        std::fs::write(&path, old).unwrap();
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert!(matches!(error, StoreError::OldLog { .. }), "{error:?}");
        let migrate = format!("run `codesign migrate {}`", path.display());
        assert!(error.to_string().contains(&migrate), "{error}");
        let error = Log::open(&path, &run, Start::Fresh).unwrap_err();
        assert_eq!(error, StoreError::LogExists { path: path.clone() });
        assert_eq!(std::fs::read_to_string(&path).unwrap(), old);
        assert!(Log::open(&path, &run, Start::Overwrite).is_ok());
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn a_huge_file_at_the_log_path_is_refused_reading_one_bounded_line() {
        // Issue 38, item 11: 1 GiB at the log path was read whole (1.06 GB of memory).
        let path = scratch("huge");
        let run = Run {
            seed: 1,
            method: None,
        };
        std::fs::File::create(&path)
            .unwrap()
            .set_len(1 << 30)
            .unwrap();
        for start in [Start::Resume, Start::Fresh] {
            let error = Log::open(&path, &run, start).unwrap_err();
            assert!(
                matches!(&error, StoreError::NotALog { why: Some(why), .. }
                    if why.contains("a line longer than 4194304 bytes")),
                "{error:?}"
            );
        }
        // A log's header, then an endless second line: damage on line 2, nothing dropped.
        drop(create(&scratch("huge"), &run));
        let header = std::fs::read(&path).unwrap();
        std::fs::File::options()
            .append(true)
            .open(&path)
            .unwrap()
            .set_len(header.len() as u64 + (1 << 30))
            .unwrap();
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert!(
            matches!(
                &error,
                StoreError::DamagedLine {
                    line: 2,
                    why: Damage::NotALine(_),
                    ..
                }
            ),
            "{error:?}"
        );
        assert_eq!(
            std::fs::metadata(&path).unwrap().len(),
            header.len() as u64 + (1 << 30)
        );
        // Bytes that are not text on an entry's line are that line's damage.
        std::fs::write(&path, [&header[..], b"\xff\xfe\n"].concat()).unwrap();
        let error = Log::open(&path, &run, Start::Resume).unwrap_err();
        assert!(
            error
                .to_string()
                .contains("line 2: a line that is not UTF-8 text"),
            "{error}"
        );
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn one_run_at_a_time_and_no_empty_log_left_behind() {
        let path = scratch("lock");
        let run = Run {
            seed: 2,
            method: None,
        };
        let log = create(&path, &run);
        for start in [Start::Fresh, Start::Resume, Start::Overwrite] {
            let error = Log::open(&path, &run, start).unwrap_err();
            assert_eq!(
                error,
                StoreError::Locked {
                    thing: Thing::EvaluationLog,
                    path: path.clone(),
                    pid: Some(std::process::id()),
                }
            );
        }
        log.discard_if_unused().unwrap();
        assert!(!path.exists(), "a log without evaluations is removed");
        let mut log = create(&path, &run);
        log.append(0, 0, &entry(0, 0, 1.0).evaluation).unwrap();
        log.discard_if_unused().unwrap();
        let (log, finished) = Log::open(&path, &run, Start::Overwrite).unwrap();
        assert!(finished.is_empty());
        drop(log);
        // A header alone holds nothing to lose: a fresh or resumed run of any settings takes
        // its place.
        let other = Run {
            seed: 9,
            method: None,
        };
        let (log, finished) = Log::open(&path, &other, Start::Resume).unwrap();
        assert!(finished.is_empty());
        drop(log);
        create(&path, &run).discard_if_unused().unwrap();
        assert!(!path.exists());
    }
}
