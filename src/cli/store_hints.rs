//! The store's errors in the command line's words: each with the flags that lead on from it.

use crate::design::run::{Output, RunError};
use crate::store::files;
use crate::store::{Action, StoreError, Thing};
use std::path::Path;

/// The message of `error` from the store, for an output given by `flag` (e.g. `--out`): an
/// output refused is prefixed by its flag, and a log in the way or locked names the flags that
/// resolve it.
pub fn hint(error: StoreError, flag: &str) -> String {
    match &error {
        StoreError::Refused { .. } => format!("{flag} {error}"),
        StoreError::Locked { .. } => format!("{error}, or pass another {flag}"),
        StoreError::LogExists { .. } => {
            format!("{error}: pass --resume to continue that run, or --overwrite to start afresh")
        }
        StoreError::DifferentRun { .. } => {
            format!("{error}; use another {flag}, or --overwrite to replace it")
        }
        StoreError::NotALog { .. } => format!(
            "{error}; codesign leaves it untouched: move it away, use another {flag}, or pass \
             --overwrite to replace it"
        ),
        StoreError::DamagedLine { .. } => format!(
            "{error} (remove that line to resume without it, or pass --overwrite to start afresh)"
        ),
        StoreError::Io {
            action: Action::Open(Thing::OutputFolder),
            path,
            why,
        } => format!("cannot open {flag} {}: {why}", path.display()),
        _ => error.to_string(),
    }
}

/// The message of a failed co-design run: a store error about its result file or evaluation
/// log with the hints of `--out`.
pub fn run_error(error: RunError) -> String {
    match error {
        RunError::Store {
            output: Output::Log,
            error: error @ StoreError::Refused { .. },
        } => hint(error, "--out (its evaluation log)"),
        RunError::Store { error, .. } => hint(error, "--out"),
        RunError::Case(error) => super::run_flags::case_message(&error),
        other => other.to_string(),
    }
}

/// Checks, before any work, that `path`, given by `flag`, can take a result, is none of
/// `inputs` and is no evaluation log, by name or content (see [`files::check_result`]).
pub fn check_output(flag: &str, path: &Path, inputs: &[(&str, &Path)]) -> Result<(), String> {
    files::check_result(path, inputs).map_err(|error| hint(error, flag))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn the_store_messages_gain_the_flags_that_lead_on() {
        let path = PathBuf::from("runs/x.log.jsonl");
        let exists = StoreError::LogExists { path: path.clone() };
        assert_eq!(
            hint(exists, "--out"),
            "the evaluation log runs/x.log.jsonl exists already: pass --resume to continue that \
             run, or --overwrite to start afresh"
        );
        let other = StoreError::DifferentRun {
            path: path.clone(),
            differences: vec!["seed: log 3, this command 4".to_owned()],
        };
        assert_eq!(
            hint(other, "--out"),
            "runs/x.log.jsonl belongs to a different run (seed: log 3, this command 4); use \
             another --out, or --overwrite to replace it"
        );
        let damaged = StoreError::DamagedLine {
            path: path.clone(),
            line: 3,
            why: crate::store::Damage::ChecksumMismatch,
        };
        assert_eq!(
            hint(damaged, "--out"),
            "runs/x.log.jsonl line 3: its checksum does not match its content; the log was \
             edited or damaged (remove that line to resume without it, or pass --overwrite to \
             start afresh)"
        );
        let locked = StoreError::Locked {
            thing: Thing::OutputFolder,
            path: PathBuf::from("results"),
            pid: Some(42),
        };
        assert_eq!(
            hint(locked, "--out-dir"),
            "the output folder results is in use by another run (pid 42): wait for it to end or \
             stop it, or pass another --out-dir"
        );
        let error = check_output("--out", Path::new("/dev/null"), &[]).unwrap_err();
        assert!(error.starts_with("--out /dev/null: is a device"), "{error}");
    }
}
