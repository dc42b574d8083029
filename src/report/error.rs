//! Why a report could not be made: a chart not drawn, a file not written, a result file not
//! read, or results that make no table together.

use crate::store::document::{EnvelopeError, Schema};
use crate::store::StoreError;
use codesign_core::input::InputError;
use codesign_core::transmission::DesignError;
use std::fmt;
use std::path::PathBuf;

/// Why a report could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum ReportError {
    /// plotters could not draw the chart of this title.
    Draw {
        /// The chart's title.
        title: String,
        /// plotters' reason.
        why: String,
    },
    /// A file could not be written.
    Store(StoreError),
    /// The design of a result is outside its design space (it cannot be plotted).
    Design(DesignError),
    /// A result file could not be read, or is no codesign result.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        why: ReadFailure,
    },
    /// Results that make no table together, or an edited one; the message names the files.
    Table(String),
}

/// Why a result file could not be read.
#[derive(Clone, Debug, PartialEq)]
pub enum ReadFailure {
    /// The file itself (missing, not regular, too large, not text).
    Input(InputError),
    /// It is no JSON; the parser's reason.
    NotJson(String),
    /// An object of it gives a key twice (an edited file: which value counts is unknown); the
    /// key and its line.
    RepeatedKey(String),
    /// Its envelope (`schema`, `version`) cannot be read.
    Envelope(EnvelopeError),
    /// It is a table, which is made from results and no result itself.
    Table,
    /// It is a document of this kind where a table was asked for.
    NotATable(Schema),
    /// It is a trade-off of capacity against cycle time (or of T* against payload), which no
    /// table places.
    Tradeoff,
    /// It is a front of parts (`codesign parts`), whose combinations' results lie beside it.
    Pareto,
    /// It is a document of an older version (0: written before the envelope), which
    /// `codesign migrate` brings to this build's.
    Old {
        /// Its kind, where its envelope or (version 0) its fields tell it.
        schema: Option<Schema>,
        /// Its version.
        version: u32,
    },
    /// It is no codesign document (result or table) nor evaluation log (`codesign migrate`).
    NotADocument,
    /// It changed between its reading and its migration (`codesign migrate`).
    Changed,
    /// It is no codesign result of the kind its tag says (for `codesign migrate`, once upgraded);
    /// the kind and the reason.
    NotAResult {
        /// `solve`, `optimize` or `capacity`.
        kind: &'static str,
        /// The parser's reason.
        why: String,
    },
}

impl fmt::Display for ReportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReportError::Draw { title, why } => write!(f, "cannot draw chart '{title}': {why}"),
            ReportError::Store(error) => write!(f, "{error}"),
            ReportError::Design(error) => write!(f, "{error}"),
            ReportError::Read { path, why } => {
                let path = path.display();
                match why {
                    ReadFailure::Input(error) => write!(f, "{path}: {error}"),
                    ReadFailure::NotJson(why) => write!(f, "{path}: not JSON: {why}"),
                    ReadFailure::RepeatedKey(why) => write!(f, "{path}: {why}"),
                    ReadFailure::Envelope(why) => write!(f, "{path}: {why}"),
                    ReadFailure::Table => write!(
                        f,
                        "{path}: a table, made from results: give the result files it was made of"
                    ),
                    ReadFailure::NotATable(schema) => write!(
                        f,
                        "{path}: a {} document, not a table (`paper_table.json`)",
                        schema.tag()
                    ),
                    ReadFailure::Tradeoff => write!(
                        f,
                        "{path}: a trade-off of payload and cycle time, which a table does \
                         not place: give solve, optimize or capacity results"
                    ),
                    ReadFailure::Pareto => write!(
                        f,
                        "{path}: a front of parts (codesign parts), which a table does not \
                         place: give the combinations' optimize results beside it"
                    ),
                    ReadFailure::Old { schema, version } => {
                        let kind = schema.map_or("a codesign document", |s| s.tag());
                        let current = schema.map_or(String::new(), |s| {
                            format!(" (this codesign reads version {})", s.version())
                        });
                        write!(
                            f,
                            "{path}: {kind} of version {version}, written by an older \
                             codesign{current}: run `codesign migrate {path}` to bring it to \
                             this version"
                        )
                    }
                    ReadFailure::Changed => write!(
                        f,
                        "{path}: changed while it was migrated (another command wrote it); run \
                         `codesign migrate {path}` again"
                    ),
                    ReadFailure::NotADocument => {
                        write!(f, "{path}: no codesign result, table or evaluation log")
                    }
                    ReadFailure::NotAResult { kind, why } => {
                        write!(f, "{path}: not a codesign {kind} result: {why}")
                    }
                }
            }
            ReportError::Table(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for ReportError {}

impl From<StoreError> for ReportError {
    fn from(error: StoreError) -> ReportError {
        ReportError::Store(error)
    }
}

impl From<DesignError> for ReportError {
    fn from(error: DesignError) -> ReportError {
        ReportError::Design(error)
    }
}

/// The command line shows a report's error as its message.
impl From<ReportError> for String {
    fn from(error: ReportError) -> String {
        error.to_string()
    }
}
