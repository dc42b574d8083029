//! The result store: result files written whole or not at all
//! ([`files`]), the evaluation log of a co-design run ([`log`]), and the advisory locks that keep
//! two runs off one output ([`lock`]).
//!
//! The store imports nothing from the rest of the crate, and of the core only the hash
//! ([`codesign_core::hash`], its log's checksums). Its errors are typed ([`StoreError`])
//! and name paths, never command-line flags: the command line adds the flags that lead on.

pub mod document;
pub mod files;
mod lines;
pub mod lock;
pub mod log;
pub mod log_upgrade;

/// The name of the evaluation log's format, its header's first field.
const LOG_FORMAT: &str = "codesign-evaluation-log";

/// How every evaluation log's first line begins (its header's `format`, written first): how a
/// log is known whatever its name.
pub const LOG_HEADER_PREFIX: &str = "{\"format\":\"codesign-evaluation-log\"";

use std::fmt;
use std::path::{Path, PathBuf};

/// What went wrong storing or reading back a file.
#[derive(Clone, Debug, PartialEq)]
pub enum StoreError {
    /// An operation on `path` failed; `why` is the system's reason.
    Io {
        /// What was attempted.
        action: Action,
        /// The path it was attempted on.
        path: PathBuf,
        /// The system's reason.
        why: String,
    },
    /// `path` cannot take a result, found when checking it before any work is done.
    Refused {
        /// The output as given.
        path: PathBuf,
        /// Why it is refused.
        why: Refusal,
    },
    /// `path` was left as it was instead of being written.
    NotWritten {
        /// The output as given.
        path: PathBuf,
        /// Why it was not written.
        why: Refusal,
    },
    /// `path` names no file (it ends in `..` or is a root).
    NotAFilePath {
        /// The path as given.
        path: PathBuf,
    },
    /// Another process holds the lock of `path`.
    Locked {
        /// What `path` is.
        thing: Thing,
        /// The locked file or folder.
        path: PathBuf,
        /// The holder's process id, when Linux's /proc/locks tells it.
        pid: Option<u32>,
    },
    /// The evaluation log at `path` was written by a run with other settings.
    DifferentRun {
        /// The log.
        path: PathBuf,
        /// The first differing settings, as `setting: log X, this command Y` (and `N more`).
        differences: Vec<String>,
    },
    /// A fresh run found an evaluation log with entries at `path`.
    LogExists {
        /// The log.
        path: PathBuf,
    },
    /// A line of the evaluation log at `path`, other than a torn last one, is unreadable.
    DamagedLine {
        /// The log.
        path: PathBuf,
        /// The line's number, from 1.
        line: usize,
        /// What is wrong with it.
        why: Damage,
    },
    /// The file at `path` is not an evaluation log.
    NotALog {
        /// The file.
        path: PathBuf,
        /// Why its first line is no log header, when it is no JSON of one.
        why: Option<String>,
    },
    /// The evaluation log at `path` is of an older format, which `codesign migrate` upgrades.
    OldLog {
        /// The log.
        path: PathBuf,
        /// The parser's reason, if any.
        why: Option<String>,
    },
    /// The evaluation log at `path` was replaced by another process while this one opened it.
    Replaced {
        /// The log.
        path: PathBuf,
    },
    /// A value bound for `path` could not be serialised.
    Serialise {
        /// The file it was bound for.
        path: PathBuf,
        /// The serialiser's reason.
        why: String,
    },
}

/// An operation on a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Reading a file.
    Read,
    /// Writing a file.
    Write,
    /// Creating a folder and its parents.
    CreateFolder,
    /// Creating a file of this kind.
    Create(Thing),
    /// Opening a file or folder of this kind.
    Open(Thing),
    /// Taking the lock of a file or folder of this kind.
    Lock(Thing),
    /// Emptying a file.
    Empty,
    /// Cutting a file short.
    Truncate,
    /// Removing a file.
    Remove,
}

/// The kinds of files and folders the store opens and locks, as its messages name them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Thing {
    /// The evaluation log of a co-design run.
    EvaluationLog,
    /// A folder of results.
    OutputFolder,
    /// The original of a file `codesign migrate` replaces, kept beside it.
    Original,
}

/// Why an output is refused.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// It is no regular file, even through symbolic links.
    Kind(FileKind),
    /// It is a symbolic link to nothing.
    DanglingLink,
    /// Its kind cannot be read; the system's reason.
    Unreadable(String),
    /// It is one of the command's inputs, named by where it came from (e.g. `--task`).
    Input {
        /// Where the input was named.
        source: String,
        /// The input's path.
        input: PathBuf,
    },
    /// It is a regular file that this user may not write (or that no one may), of these
    /// permission bits.
    NotWritable {
        /// Its permission bits.
        mode: u32,
    },
    /// It ends in `/`: it names a folder, not a file.
    NamesFolder,
    /// Its file name is longer than the system takes with a temporary file's suffix, bytes.
    NameTooLong {
        /// The name's length.
        bytes: usize,
        /// The longest name that fits.
        limit: usize,
    },
    /// It is an evaluation log, by its name or its first line (where a symbolic link points
    /// too), which only a co-design run writes beside its result.
    LogName,
    /// Its folder takes no new file.
    FolderNotWritable {
        /// The folder.
        folder: PathBuf,
        /// The system's reason.
        why: String,
    },
}

/// The kind of a file that is no regular file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A folder.
    Folder,
    /// A character or block device.
    Device,
    /// A FIFO (named pipe).
    Fifo,
    /// A Unix socket.
    Socket,
    /// Any other kind.
    Other,
}

/// What is wrong with a damaged line of an evaluation log.
#[derive(Clone, Debug, PartialEq)]
pub enum Damage {
    /// It is no JSON of an entry; the parser's reason.
    NotARecord(String),
    /// Its checksum does not match its content.
    ChecksumMismatch,
    /// It has no checksum in a log whose entries all carry one.
    NoChecksum,
    /// It is longer than any entry, or not text (see [`lines::Line::text`]).
    NotALine(String),
}

impl fmt::Display for Thing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Thing::EvaluationLog => "the evaluation log",
            Thing::OutputFolder => "the output folder",
            Thing::Original => "the copy of the original",
        })
    }
}

impl fmt::Display for Action {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Action::Read => f.write_str("read"),
            Action::Write => f.write_str("write"),
            Action::CreateFolder => f.write_str("create folder"),
            Action::Create(thing) => write!(f, "create {thing}"),
            Action::Open(thing) => write!(f, "open {thing}"),
            Action::Lock(thing) => write!(f, "lock {thing}"),
            Action::Empty => f.write_str("empty"),
            Action::Truncate => f.write_str("truncate"),
            Action::Remove => f.write_str("remove"),
        }
    }
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::Folder => "a folder",
            FileKind::Device => "a device",
            FileKind::Fifo => "a FIFO",
            FileKind::Socket => "a socket",
            FileKind::Other => "not a regular file",
        })
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::Kind(kind) => write!(
                f,
                "is {kind}; codesign writes only regular files and leaves it untouched"
            ),
            Refusal::DanglingLink => f.write_str(
                "a symbolic link to a missing file; links are followed only to existing regular \
                 files",
            ),
            Refusal::Unreadable(why) => f.write_str(why),
            Refusal::Input { source, input } => write!(
                f,
                "that is an input of this command ({source} {}); writing there would destroy it, \
                 choose another path",
                input.display()
            ),
            Refusal::NotWritable { mode } => write!(
                f,
                "is not writable by this user (mode {mode:03o}); codesign leaves it untouched"
            ),
            Refusal::NamesFolder => {
                f.write_str("ends in /, /. or /..: it names a folder; give a file name")
            }
            Refusal::NameTooLong { bytes, limit } => write!(
                f,
                "its file name is {bytes} bytes long; at most {limit} fit beside the suffix of \
                 the temporary file it is written through"
            ),
            Refusal::LogName => f.write_str(
                "is an evaluation log (named .log.jsonl, or one by its first line, also where a \
                 symbolic link points), which only a co-design run writes beside its result; \
                 choose another name",
            ),
            Refusal::FolderNotWritable { folder, why } => {
                write!(f, "cannot write in its folder {}: {why}", folder.display())
            }
        }
    }
}

impl fmt::Display for Damage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Damage::NotARecord(why) => write!(f, "not an evaluation record ({why})"),
            Damage::ChecksumMismatch => f.write_str("its checksum does not match its content"),
            Damage::NoChecksum => f.write_str("the record has no checksum"),
            Damage::NotALine(why) => f.write_str(why),
        }
    }
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoreError::Io { action, path, why } => {
                write!(f, "cannot {action} {}: {why}", path.display())
            }
            StoreError::Refused { path, why } => write!(f, "{}: {why}", path.display()),
            StoreError::NotWritten { path, why } => {
                write!(f, "cannot write {}: {why}", path.display())
            }
            StoreError::NotAFilePath { path } => {
                write!(f, "cannot write {}: not a file path", path.display())
            }
            StoreError::Locked { thing, path, pid } => {
                let holder =
                    pid.map_or_else(|| "process unknown".to_owned(), |p| format!("pid {p}"));
                write!(
                    f,
                    "{thing} {} is in use by another run ({holder}): wait for it to end or stop it",
                    path.display()
                )
            }
            StoreError::DifferentRun { path, differences } => write!(
                f,
                "{} belongs to a different run ({})",
                path.display(),
                differences.join("; ")
            ),
            StoreError::LogExists { path } => {
                write!(f, "the evaluation log {} exists already", path.display())
            }
            StoreError::DamagedLine { path, line, why } => write!(
                f,
                "{} line {line}: {why}; the log was edited or damaged",
                path.display()
            ),
            StoreError::NotALog { path, why: None } => {
                write!(f, "{} is not an evaluation log", path.display())
            }
            StoreError::NotALog {
                path,
                why: Some(why),
            } => write!(
                f,
                "{} is not an evaluation log (line 1: {why})",
                path.display()
            ),
            StoreError::OldLog { path, why } => {
                let why = why
                    .as_ref()
                    .map_or(String::new(), |why| format!(" ({why})"));
                write!(
                    f,
                    "{} is an evaluation log of an older codesign{why}: run `codesign migrate {}` \
                     to bring it to this version",
                    path.display(),
                    path.display()
                )
            }
            StoreError::Replaced { path } => write!(
                f,
                "the evaluation log {} was replaced while this run opened it; run again",
                path.display()
            ),
            StoreError::Serialise { path, why } => {
                write!(f, "cannot serialise {}: {why}", path.display())
            }
        }
    }
}

impl std::error::Error for StoreError {}

impl StoreError {
    /// The failure of `action` on `path` with the system's `error`.
    fn io(action: Action, path: &Path, error: &std::io::Error) -> StoreError {
        StoreError::Io {
            action,
            path: path.to_owned(),
            why: error.to_string(),
        }
    }
}
