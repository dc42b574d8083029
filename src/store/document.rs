//! The envelope every result document is written in: its `schema` (which kind of document) and
//! its `version` before its own fields, so that a reader tells a file's kind by its tag, reads
//! an older version knowingly and refuses a newer one. Files written before the envelope carry
//! neither key: version 0, whose kind only its fields tell.

use super::files::write_json;
use super::StoreError;
use codesign_core::input::{read_text, MAX_RESULT_BYTES};
use codesign_core::json_keys::check_unique_keys;
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;
use std::fmt;
use std::path::Path;

/// The kinds of result documents, each with its tag and the version this build writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schema {
    /// One trajectory solve (`codesign solve --out`).
    Solve,
    /// One co-design run (`codesign optimize --out`).
    Optimize,
    /// One payload capacity search (`codesign capacity --out`).
    Capacity,
    /// The experiment's table (`paper_table.json`, `codesign table --out`).
    Table,
    /// A design's payload capacity against cycle time (`codesign tradeoff`).
    Tradeoff,
    /// Designs' least duration T* against payload (`codesign tradeoff --payloads`).
    TimeCurve,
    /// The front of actuator mass against an objective over combinations of parts
    /// (`codesign parts`, `pareto.json`).
    Pareto,
}

impl Schema {
    /// Every kind.
    pub const ALL: [Schema; 7] = [
        Schema::Solve,
        Schema::Optimize,
        Schema::Capacity,
        Schema::Table,
        Schema::Tradeoff,
        Schema::TimeCurve,
        Schema::Pareto,
    ];

    /// The tag a document of this kind carries as `schema`, e.g. `codesign/solve`.
    pub fn tag(self) -> &'static str {
        match self {
            Schema::Solve => "codesign/solve",
            Schema::Optimize => "codesign/optimize",
            Schema::Capacity => "codesign/capacity",
            Schema::Table => "codesign/table",
            Schema::Tradeoff => "codesign/tradeoff",
            Schema::TimeCurve => "codesign/time_curve",
            Schema::Pareto => "codesign/pareto",
        }
    }

    /// The kind's name, as the command that writes it: `solve`, `optimize`, `capacity`, `table`,
    /// `tradeoff`; `time_curve` for `tradeoff --payloads`; `pareto` for `parts`.
    pub fn name(self) -> &'static str {
        &self.tag()["codesign/".len()..]
    }

    /// The version of this kind that this build writes (0: written before the envelope). The
    /// results are at 2: `reason` always written (null when feasible), each motor's peaks and
    /// margins in `motors_execute`, and a capacity search's inputs under `inputs`; a co-design
    /// run's at 3: `best_cost` null without a best design, and a table at 2: a seed's cost null
    /// then. A trade-off, a time curve and a front of parts, which came later, are at 1.
    pub fn version(self) -> u32 {
        match self {
            Schema::Solve | Schema::Capacity => 2,
            Schema::Optimize => 3,
            Schema::Table => 2,
            Schema::Tradeoff | Schema::TimeCurve | Schema::Pareto => 1,
        }
    }

    /// The kind of tag `tag`, if any.
    pub fn of_tag(tag: &str) -> Option<Schema> {
        Schema::ALL.into_iter().find(|schema| schema.tag() == tag)
    }
}

/// A result document, written in the envelope by [`write_document`].
pub trait Document: Serialize {
    /// Its kind.
    const SCHEMA: Schema;
}

/// Reads the document of kind `D` at `path`, of the version this build writes: a file of at
/// most [`MAX_RESULT_BYTES`], no key given twice, its envelope `D`'s. The error says why, not
/// naming the file.
pub fn read_document<D: Document + DeserializeOwned>(path: &Path) -> Result<D, String> {
    let text = read_text(path, MAX_RESULT_BYTES).map_err(|e| e.to_string())?;
    check_unique_keys(&text)?;
    let mut value: Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let schema = D::SCHEMA;
    match open(&mut value) {
        Ok(Tagged::Kind(kind, version)) if kind == schema && version == schema.version() => {
            serde_json::from_value(value).map_err(|e| e.to_string())
        }
        Ok(_) => Err(format!(
            "no {} document of version {}",
            schema.tag(),
            schema.version()
        )),
        Err(error) => Err(error.to_string()),
    }
}

/// `schema` and `version`, then the document's own fields.
#[derive(Serialize)]
struct Envelope<'d, D: Serialize> {
    schema: &'static str,
    version: u32,
    #[serde(flatten)]
    document: &'d D,
}

/// `document` in its envelope.
fn envelope<D: Document>(document: &D) -> Envelope<'_, D> {
    Envelope {
        schema: D::SCHEMA.tag(),
        version: D::SCHEMA.version(),
        document,
    }
}

/// Writes `document` to `path` whole, in its envelope (see [`super::files::write_json`]).
pub fn write_document<D: Document>(path: &Path, document: &D) -> Result<(), StoreError> {
    write_json(path, &envelope(document))
}

/// The JSON text [`write_document`] writes for `document`, without the final newline (what the
/// Python package's `to_json` gives).
pub fn document_json<D: Document>(document: &D) -> Result<String, serde_json::Error> {
    serde_json::to_string_pretty(&envelope(document))
}

/// What a document's envelope says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tagged {
    /// A document of this kind and version.
    Kind(Schema, u32),
    /// No envelope: a file written before it (version 0).
    Untagged,
}

/// Why a document's envelope cannot be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EnvelopeError {
    /// `schema` is no tag of this build's.
    UnknownSchema(String),
    /// `version` is not a whole number.
    BadVersion(String),
    /// A newer version than this build reads.
    Newer {
        /// Its kind.
        schema: Schema,
        /// Its version.
        version: u32,
    },
}

impl fmt::Display for EnvelopeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EnvelopeError::UnknownSchema(tag) => {
                let known: Vec<&str> = Schema::ALL.iter().map(|s| s.tag()).collect();
                write!(f, "schema {tag:?} is none of {}", known.join(", "))
            }
            EnvelopeError::BadVersion(version) => {
                write!(f, "version {version} is not a whole number")
            }
            EnvelopeError::Newer { schema, version } => write!(
                f,
                "{} version {version} was written by a newer codesign (this one reads up to \
                 version {})",
                schema.tag(),
                schema.version()
            ),
        }
    }
}

impl std::error::Error for EnvelopeError {}

/// Takes the envelope off `value` (a document's JSON object): its kind and version, the keys
/// removed, or [`Tagged::Untagged`] where it has none.
pub fn open(value: &mut Value) -> Result<Tagged, EnvelopeError> {
    let Some(object) = value.as_object_mut() else {
        return Ok(Tagged::Untagged);
    };
    let Some(tag) = object.remove("schema") else {
        return Ok(Tagged::Untagged);
    };
    let version = object.remove("version");
    let tag_text = tag.as_str().map(str::to_owned).unwrap_or(tag.to_string());
    let schema = Schema::of_tag(&tag_text).ok_or(EnvelopeError::UnknownSchema(tag_text))?;
    let version = match &version {
        Some(number) => number.as_u64().and_then(|v| u32::try_from(v).ok()),
        None => None,
    }
    .ok_or_else(|| EnvelopeError::BadVersion(format!("{version:?}")))?;
    if version > schema.version() {
        return Err(EnvelopeError::Newer { schema, version });
    }
    Ok(Tagged::Kind(schema, version))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Probe {
        b: f64,
        a: Vec<u8>,
    }

    impl Document for Probe {
        const SCHEMA: Schema = Schema::Capacity;
    }

    /// The envelope's keys come first, then the document's own in their order; opening it
    /// gives the kind and version back and leaves the document's fields.
    #[test]
    fn the_envelope_leads_and_opens_back() {
        let dir = std::env::temp_dir().join(format!("codesign-envelope-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("probe.json");
        write_document(&path, &Probe { b: 0.1, a: vec![2] }).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let keys: Vec<&str> = text.lines().filter_map(|l| l.split('"').nth(1)).collect();
        assert_eq!(keys[..4], ["schema", "version", "b", "a"], "{text}");
        let mut value: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(open(&mut value), Ok(Tagged::Kind(Schema::Capacity, 2)));
        assert_eq!(value, serde_json::json!({"b": 0.1, "a": [2]}));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The guide's results page names the versions this build writes (the README said "1
    /// today" once version 2 was written).
    #[test]
    fn the_guide_names_the_versions_written() {
        let page = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide/results.md");
        let text = std::fs::read_to_string(page).unwrap();
        let result = Schema::Solve.version();
        assert_eq!(Schema::Capacity.version(), result);
        let said = format!(
            "its `version` ({result} for a solve or capacity result today, {} for an optimize \
             result, {} for a table, {} for a trade-off)",
            Schema::Optimize.version(),
            Schema::Table.version(),
            Schema::Tradeoff.version()
        );
        let flowing = text.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            flowing.contains(&said),
            "docs/guide/results.md does not say: {said}"
        );
    }

    /// No envelope is version 0; an unknown tag, a version that is no whole number and a newer
    /// version are refused, naming them.
    #[test]
    fn older_unknown_and_newer_envelopes() {
        let mut old = serde_json::json!({"cost": 1.0});
        assert_eq!(open(&mut old), Ok(Tagged::Untagged));
        let mut unknown = serde_json::json!({"schema": "codesign/film", "version": 1});
        let error = open(&mut unknown).unwrap_err();
        assert!(
            error.to_string().contains("\"codesign/film\" is none of"),
            "{error}"
        );
        let mut bad = serde_json::json!({"schema": "codesign/solve", "version": 1.5});
        assert!(matches!(open(&mut bad), Err(EnvelopeError::BadVersion(_))));
        let mut newer = serde_json::json!({"schema": "codesign/solve", "version": 3});
        let error = open(&mut newer).unwrap_err();
        assert!(
            error.to_string().contains("written by a newer codesign"),
            "{error}"
        );
    }
}
