//! An evaluation log of an older format brought to this build's (`codesign migrate`): its
//! header's run with the settings the caller fills in, and a checksum on every entry where the
//! log was written before checksums. Entries that carry one are checked, never recomputed: a
//! damaged line stays an error naming it.

use super::log::{LogEntry, LogHeader};
use super::{Damage, StoreError};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;
use std::path::Path;

/// A log upgraded: what changed, one line each, and its new text (None: it was current).
#[derive(Clone, Debug, PartialEq)]
pub struct UpgradedLog {
    /// What changed.
    pub changes: Vec<String>,
    /// The log's new text, when anything changed.
    pub text: Option<String>,
}

/// Brings the log `text` read from `path`, whose entries hold `E`, to this build's format:
/// `fill_run` fills its header's run (returning what it changed), and entries without a
/// checksum get one. A torn last line (an interrupted append, which resuming drops too) is
/// dropped when the log is rewritten. Errors name the line.
pub fn upgrade_log<E: Serialize + DeserializeOwned>(
    path: &Path,
    text: &str,
    fill_run: impl FnOnce(&mut Value) -> Vec<String>,
) -> Result<UpgradedLog, StoreError> {
    let damaged = |line: usize, why: Damage| StoreError::DamagedLine {
        path: path.to_owned(),
        line,
        why,
    };
    let mut lines = text.split_inclusive('\n');
    let first = lines.next().unwrap_or_default();
    let mut header: Value = serde_json::from_str(first).map_err(|e| StoreError::NotALog {
        path: path.to_owned(),
        why: Some(e.to_string()),
    })?;
    let format = header.get("format").and_then(Value::as_str).unwrap_or("");
    if format != super::LOG_FORMAT {
        return Err(StoreError::NotALog {
            path: path.to_owned(),
            why: None,
        });
    }
    let checksums = header.get("checksums") == Some(&Value::Bool(true));
    let mut changes = match header.get_mut("run") {
        Some(run) => fill_run(run),
        None => return Err(damaged(1, Damage::NotARecord("no run".to_owned()))),
    };
    let mut entries = Vec::new();
    let mut unchecked = 0;
    for (number, line) in (2..).zip(lines) {
        let Some(line) = line.strip_suffix('\n') else {
            changes.push(format!("torn last line {number} dropped"));
            break;
        };
        let mut entry: Value = serde_json::from_str(line)
            .map_err(|e| damaged(number, Damage::NotARecord(e.to_string())))?;
        let entry = match entry.get("check") {
            Some(_) => LogEntry::<E>::from_line(line).map_err(|why| damaged(number, why))?,
            None => {
                unchecked += 1;
                entry.as_object_mut().map(|e| e.remove("check"));
                serde_json::from_value(entry)
                    .map_err(|e| damaged(number, Damage::NotARecord(e.to_string())))?
            }
        };
        entries.push(entry);
    }
    if unchecked > 0 {
        changes.push(format!("checksums added to {unchecked} entries"));
    }
    if !checksums {
        changes.push("checksums = true (absent)".to_owned());
    }
    if changes.is_empty() {
        return Ok(UpgradedLog {
            changes,
            text: None,
        });
    }
    let serialise = |e: serde_json::Error| StoreError::Serialise {
        path: path.to_owned(),
        why: e.to_string(),
    };
    let header = LogHeader {
        format: super::LOG_FORMAT.to_owned(),
        run: header.get("run").cloned().unwrap_or(Value::Null),
        checksums: true,
    };
    let mut text = serde_json::to_string(&header).map_err(serialise)? + "\n";
    for entry in &entries {
        text += &(entry.to_line().map_err(serialise)? + "\n");
    }
    Ok(UpgradedLog {
        changes,
        text: Some(text),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Design {
        cost: f64,
    }

    fn upgrade(text: &str) -> Result<UpgradedLog, StoreError> {
        upgrade_log::<Design>(Path::new("x.log.jsonl"), text, |run| {
            let object = run.as_object_mut().unwrap();
            match object.contains_key("seed") {
                true => Vec::new(),
                false => {
                    object.insert("seed".to_owned(), Value::from(0));
                    vec!["run.seed = 0 (absent)".to_owned()]
                }
            }
        })
    }

    /// A log written before checksums gets one on each entry, each of which then reads; a
    /// current log is left as it is; an edited line stays an error naming it.
    #[test]
    fn a_log_without_checksums_gets_them() {
        let old = "{\"format\":\"codesign-evaluation-log\",\"run\":{}}\n\
                   {\"generation\":0,\"index\":0,\"cost\":1.5}\n\
                   {\"generation\":0,\"index\":1,\"cost\":2.5}\n{\"gener";
        let upgraded = upgrade(old).unwrap();
        assert_eq!(
            upgraded.changes,
            [
                "run.seed = 0 (absent)",
                "torn last line 4 dropped",
                "checksums added to 2 entries",
                "checksums = true (absent)"
            ]
        );
        let text = upgraded.text.unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "{\"format\":\"codesign-evaluation-log\",\"run\":{\"seed\":0},\"checksums\":true}"
        );
        let entry = LogEntry::<Design>::from_line(lines[2]).unwrap();
        assert_eq!((entry.index, entry.evaluation.cost), (1, 2.5));
        assert_eq!(upgrade(&text).unwrap().text, None);
        let edited = text.replacen("1.5", "0.5", 1);
        let error = upgrade(&edited).unwrap_err();
        assert!(
            error.to_string().contains("line 2: its checksum"),
            "{error}"
        );
    }
}
