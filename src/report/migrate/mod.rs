//! Result documents and evaluation logs of older versions brought to the version this build
//! writes (`codesign migrate`): the upgrade steps on their JSON ([`steps`]), then the document
//! read as this build's type and written as this build writes it, so that a migrated file is
//! one this build could have written and reads. A current file is left as it is, byte for byte.

mod ordered;
pub mod steps;

use super::codesign::CapacityDocument;
use super::solve_document::SolveDocument;
use super::table::PaperTable;
use super::time_curve::TimeCurveDocument;
use super::tradeoff::TradeoffDocument;
use super::{ReadFailure, ReportError};
use crate::design::run::OptimizeDocument;
use crate::design::score::Evaluation;
use crate::store::document::{self, document_json, Document, Schema, Tagged};
use crate::store::files::{keep_original, rewrite_log, write_atomic};
use crate::store::log_upgrade::upgrade_log;
use crate::store::{Action, StoreError};
use codesign_core::hash::fnv1a;
use codesign_core::input::{read_text, MAX_RESULT_BYTES};
use codesign_core::json_keys::check_unique_keys;
use codesign_core::model::catalogue;
use codesign_core::model::identity::built_in_task_hash;
use ordered::Ordered;
use serde::de::DeserializeOwned;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// What a file is, as `codesign migrate` reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A result document or table of this kind, at this version.
    Document(Schema, u32),
    /// An evaluation log.
    Log,
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Kind::Document(schema, version) => write!(f, "{} version {version}", schema.tag()),
            Kind::Log => f.write_str("evaluation log"),
        }
    }
}

/// One file's migration, planned: what it is, what changes, and its new text.
#[derive(Clone, Debug, PartialEq)]
pub struct Migration {
    /// The file.
    pub path: PathBuf,
    /// What it is.
    pub kind: Kind,
    /// What changes, one line each; empty for a current file.
    pub changes: Vec<String>,
    /// The FNV-1a hash of the text read, to check that the file still holds it when it is
    /// replaced.
    read: String,
    /// The new text, when anything changes.
    after: Option<String>,
}

impl Migration {
    /// Whether the file is of an older version.
    pub fn is_old(&self) -> bool {
        self.after.is_some()
    }

    /// Writes the migrated file in place of the old one, whole (a reader never sees half of
    /// it), keeping the original as `NAME.orig` beside it when `keep`; returns the name the
    /// original is kept under. A current file is not touched.
    pub fn apply(&self, keep: bool) -> Result<Option<PathBuf>, ReportError> {
        let Some(after) = &self.after else {
            return Ok(None);
        };
        if self.kind == Kind::Log {
            let kept = rewrite_log(&self.path, &self.read, after.as_bytes(), keep)?;
            return Ok(kept);
        }
        let now = std::fs::read(&self.path).map_err(|e| StoreError::Io {
            action: Action::Read,
            path: self.path.clone(),
            why: e.to_string(),
        })?;
        if fnv1a(&now) != self.read {
            return Err(ReportError::Read {
                path: self.path.clone(),
                why: ReadFailure::Changed,
            });
        }
        let kept = keep.then(|| keep_original(&self.path)).transpose()?;
        write_atomic(&self.path, after.as_bytes()).inspect_err(|_| {
            kept.as_ref().map(std::fs::remove_file);
        })?;
        Ok(kept)
    }
}

/// Plans the migration of the file at `path`: a result document, a table or an evaluation log
/// of any version this build knows. None for a file that is none of them (JSON of another
/// program, or a catalogue of parts). Errors name the file: unreadable, damaged, of a newer version, or not read as
/// this build's type once upgraded.
pub fn plan(path: &Path) -> Result<Option<Migration>, ReportError> {
    let failed = |why| ReportError::Read {
        path: path.to_owned(),
        why,
    };
    let before = read_text(path, MAX_RESULT_BYTES).map_err(|e| failed(ReadFailure::Input(e)))?;
    if before.starts_with(crate::store::LOG_HEADER_PREFIX) {
        let upgraded = upgrade_log::<Evaluation>(path, &before, |run| match run.as_object_mut() {
            Some(run) => {
                let mut changes = Vec::new();
                steps::run_inputs_fill(run, "run.", &mut changes);
                changes
            }
            None => Vec::new(),
        })?;
        return Ok(Some(Migration {
            path: path.to_owned(),
            kind: Kind::Log,
            changes: upgraded.changes,
            read: fnv1a(before.as_bytes()),
            after: upgraded.text,
        }));
    }
    let mut value: Value =
        serde_json::from_str(&before).map_err(|e| failed(ReadFailure::NotJson(e.to_string())))?;
    check_unique_keys(&before).map_err(|e| failed(ReadFailure::RepeatedKey(e)))?;
    if value.get("schema").and_then(Value::as_str) == Some(catalogue::SCHEMA) {
        // A catalogue of parts is an input, read by its own strict reader, and has no older
        // version to upgrade.
        return Ok(None);
    }
    let (schema, version) = match document::open(&mut value) {
        Ok(Tagged::Kind(schema, version)) => (schema, version),
        Ok(Tagged::Untagged) => match steps::untagged_kind(&value) {
            Some(schema) => (schema, 0),
            None => return Ok(None),
        },
        Err(e) => return Err(failed(ReadFailure::Envelope(e))),
    };
    let built_in = built_in_task_hash().ok();
    let changes = steps::upgrade(schema, version, &mut value, built_in.as_deref());
    let after = match changes.is_empty() {
        true => None,
        false => Some(rewritten(schema, value, &before).map_err(|why| {
            failed(ReadFailure::NotAResult {
                kind: schema.name(),
                why: format!("once brought to version {}: {why}", schema.version()),
            })
        })?),
    };
    Ok(Some(Migration {
        path: path.to_owned(),
        kind: Kind::Document(schema, version),
        changes,
        read: fnv1a(before.as_bytes()),
        after,
    }))
}

/// The text this build writes for the document `value` of `schema` (envelope off, upgraded),
/// read from `before`: its objects in `before`'s order, then read as its type and written as
/// [`crate::store::document::write_document`] writes it.
fn rewritten(schema: Schema, value: Value, before: &str) -> Result<String, serde_json::Error> {
    let read: Ordered = serde_json::from_str(before)?;
    let text = serde_json::to_string(&Ordered::like(value, Some(&read)))?;
    match schema {
        Schema::Solve => text_of::<SolveDocument>(&text),
        Schema::Optimize => text_of::<OptimizeDocument>(&text),
        Schema::Capacity => text_of::<CapacityDocument>(&text),
        Schema::Table => text_of::<PaperTable>(&text),
        Schema::Tradeoff => text_of::<TradeoffDocument>(&text),
        Schema::TimeCurve => text_of::<TimeCurveDocument>(&text),
        Schema::Pareto => text_of::<crate::design::parts::ParetoDocument>(&text),
    }
}

/// `text` read as a `D` and written as this build writes it.
fn text_of<D: Document + DeserializeOwned>(text: &str) -> Result<String, serde_json::Error> {
    let document: D = serde_json::from_str(text)?;
    Ok(document_json(&document)? + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file written by another command between the plan and its writing is left as that
    /// command wrote it, and the migration fails naming it; a log the same.
    #[test]
    fn a_file_changed_meanwhile_is_left_alone() {
        let dir = std::env::temp_dir().join(format!("codesign-migrate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/migrate");
        for name in ["solve-v1.json", "unchecked.log.jsonl"] {
            let path = dir.join(name);
            std::fs::copy(fixtures.join(name), &path).unwrap();
            let migration = plan(&path).unwrap().unwrap();
            assert!(migration.is_old());
            std::fs::write(&path, "{}\n").unwrap();
            let error = migration.apply(true).unwrap_err();
            assert!(error.to_string().contains(name), "{error}");
            assert_eq!(std::fs::read_to_string(&path).unwrap(), "{}\n");
            assert!(!dir.join(format!("{name}.orig")).exists());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
