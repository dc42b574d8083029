//! Why a worker pool or a worker stopped.

use super::protocol::Hello;
use crate::design::score::ScoreError;
use codesign_core::model::ModelError;
use std::fmt;
use std::io;

/// Why the pool (the parent's side) or a worker (`codesign worker`) stopped. A worker that
/// crashes, hangs or answers nonsense is no error: it is replaced, and its design penalised.
#[derive(Debug)]
pub enum WorkerError {
    /// The pool was asked for no workers.
    NoWorkers,
    /// More workers than [`super::MAX_GROUPS`] would run at once.
    TooMany,
    /// A worker said no hello within the time limit: the command starts no codesign worker.
    NoHello {
        /// The command that started it.
        launcher: String,
        /// The time it was given, s.
        seconds: f64,
    },
    /// A worker process could not be started.
    Start {
        /// The command that starts it.
        launcher: String,
        /// Why it did not start.
        source: io::Error,
    },
    /// A started worker has no pipe of this name (`stdin`, `stdout`).
    NoPipe(&'static str),
    /// A worker ended before its hello (its setup could not be sent, or its output ended): the
    /// command starts no codesign worker.
    EndedEarly {
        /// The command that started it.
        launcher: String,
        /// How it ended, where known (`exit status: 2`).
        status: Option<String>,
    },
    /// Every thread reading the workers' answers stopped.
    ReadersStopped,
    /// The host asked the run to stop (its `signals::StopToken`, Ctrl-C in Python).
    Interrupted,
    /// A worker's hello differs from the pool's: another build, or another reading of the setup.
    Refused {
        /// The command that started it.
        launcher: String,
        /// What it said instead, in words.
        what: String,
        /// The pool's hello.
        expected: Box<Hello>,
    },
    /// The pool could not encode a line of the protocol.
    Encode(serde_json::Error),
    /// The worker setup could not be encoded to compute its hash.
    EncodeSetup(serde_json::Error),
    /// A worker could not encode its hello or an answer.
    EncodeAnswer(serde_json::Error),
    /// A worker could not read its setup line.
    ReadSetup(io::Error),
    /// A worker's setup line is not a setup.
    MalformedSetup(serde_json::Error),
    /// A worker could not build the formulations of its setup.
    Fitness(ScoreError),
    /// A worker could not read the robot of its setup.
    Robot(ModelError),
    /// A worker could not read a request line.
    ReadRequest(io::Error),
    /// A worker's request line is not a request.
    MalformedRequest(serde_json::Error),
    /// A worker could not write its answer (other than to a parent that is gone).
    Answer(io::Error),
}

impl fmt::Display for WorkerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorkerError::NoWorkers => f.write_str("--workers must be at least 1"),
            WorkerError::NoHello { launcher, seconds } => write!(
                f,
                "the worker started by `{launcher}` said no hello within {seconds:.0} s (the \
                 --solve-timeout): is it a codesign worker (`codesign worker`, `{{}} worker`)?"
            ),
            WorkerError::TooMany => write!(
                f,
                "more than {} workers at once: each is a process group this run must be able \
                 to stop",
                super::MAX_GROUPS
            ),
            WorkerError::Start { launcher, source } => {
                write!(f, "cannot start a worker with `{launcher}`: {source}")
            }
            WorkerError::NoPipe(pipe) => write!(f, "worker has no {pipe}"),
            WorkerError::EndedEarly { launcher, status } => {
                let how = status
                    .as_deref()
                    .map_or(String::new(), |s| format!(" ({s})"));
                write!(
                    f,
                    "the worker started by `{launcher}` ended before its hello{how}: is it a \
                     codesign worker (`codesign worker`, `{{}} worker`)?"
                )
            }
            WorkerError::ReadersStopped => f.write_str("all worker readers stopped"),
            WorkerError::Interrupted => f.write_str("interrupted"),
            WorkerError::Refused {
                launcher,
                what,
                expected,
            } => write!(
                f,
                "refused the worker started by `{launcher}`: {what}; this run is {expected}. \
                 Results of mixed builds are never merged: run the same codesign build on every \
                 machine"
            ),
            WorkerError::Encode(e) => e.fmt(f),
            WorkerError::EncodeSetup(e) => write!(f, "worker setup: {e}"),
            WorkerError::EncodeAnswer(e) => write!(f, "worker: {e}"),
            WorkerError::ReadSetup(e) => write!(f, "worker: cannot read its setup: {e}"),
            WorkerError::MalformedSetup(e) => write!(f, "worker: malformed setup line: {e}"),
            WorkerError::Fitness(e) => e.fmt(f),
            WorkerError::Robot(e) => write!(f, "worker: {e}"),
            WorkerError::ReadRequest(e) => write!(f, "worker: cannot read a request: {e}"),
            WorkerError::MalformedRequest(e) => write!(f, "worker: malformed request: {e}"),
            WorkerError::Answer(e) => write!(f, "worker: cannot answer: {e}"),
        }
    }
}

impl std::error::Error for WorkerError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WorkerError::Start { source: e, .. }
            | WorkerError::ReadSetup(e)
            | WorkerError::ReadRequest(e)
            | WorkerError::Answer(e) => Some(e),
            WorkerError::Encode(e)
            | WorkerError::EncodeSetup(e)
            | WorkerError::EncodeAnswer(e)
            | WorkerError::MalformedSetup(e)
            | WorkerError::MalformedRequest(e) => Some(e),
            WorkerError::Fitness(e) => Some(e),
            WorkerError::Robot(e) => Some(e),
            WorkerError::NoWorkers
            | WorkerError::TooMany
            | WorkerError::NoHello { .. }
            | WorkerError::EndedEarly { .. }
            | WorkerError::NoPipe(_)
            | WorkerError::ReadersStopped
            | WorkerError::Interrupted
            | WorkerError::Refused { .. } => None,
        }
    }
}

impl From<ScoreError> for WorkerError {
    fn from(error: ScoreError) -> WorkerError {
        WorkerError::Fitness(error)
    }
}
