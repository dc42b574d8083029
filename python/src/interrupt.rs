//! Work that Ctrl-C can stop: it runs on a thread of its own under a stop token of its own
//! (`signals::StopToken`), the GIL released, while the calling thread waits and looks every
//! 100 ms whether Python has a signal to raise. On one (or when the progress callback raises) it
//! stops that token: the work's IPOPT solves end at their next iteration as errors, never as
//! verdicts, and a co-design run stops before its next evaluation, its log kept. It waits for the
//! work and raises the exception; the work's outcome, whatever it is, is dropped. Work of other
//! calls, under other tokens, runs on.

use crate::errors::{Failure, Outcome};
use codesign_core::signals::{self, StopToken};
use pyo3::prelude::*;
use std::sync::mpsc::{channel, RecvTimeoutError, Sender};
use std::time::Duration;

/// How often the waiting thread looks for a signal.
const POLL: Duration = Duration::from_millis(100);

/// What the work's thread sends: progress (evaluations done, best fitness so far), or its end.
pub enum Message<T> {
    /// One more evaluation of a co-design run: (done, total, best fitness).
    Progress(u64, u64, f64),
    /// The work's outcome.
    Done(Outcome<T>),
}

/// The progress of [`run`] handed to the Python callable `progress(done, total, best)`, where
/// one is given.
pub fn calling(
    progress: Option<Py<PyAny>>,
) -> impl FnMut(Python<'_>, u64, u64, f64) -> PyResult<()> {
    move |py, done, total, best| match &progress {
        Some(callback) => callback.call1(py, (done, total, best)).map(|_| ()),
        None => Ok(()),
    }
}

/// Runs `work` on a thread of its own (handing it a sender for its progress), calls `progress`
/// with the GIL for each progress message, and returns its outcome; a Python signal (Ctrl-C)
/// stops the work and is raised once the work has stopped.
pub fn run<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce(Sender<Message<T>>) -> Outcome<T> + Send + 'static,
    mut progress: impl FnMut(Python<'_>, u64, u64, f64) -> PyResult<()>,
) -> PyResult<T> {
    let (sender, mut receiver) = channel();
    let own = sender.clone();
    let token = StopToken::new();
    let stop = token.clone();
    let thread = std::thread::Builder::new()
        .name("codesign".to_owned())
        .spawn(move || {
            let outcome = signals::under(Some(token), || work(own.clone()));
            let _ = own.send(Message::Done(outcome));
        })
        .map_err(|e| Failure::solver(format!("could not start a thread: {e}")).into_py(py))?;
    drop(sender);
    let stopped = |py: Python<'_>, thread: std::thread::JoinHandle<()>, error: PyErr| {
        stop.stop();
        let _ = py.detach(|| thread.join());
        Err(error)
    };
    let outcome = loop {
        // A receiver is not Sync: the waiting closure takes it by unique reference.
        let waiting = &mut receiver;
        let received = py.detach(move || waiting.recv_timeout(POLL));
        // Signals are looked for after every message too: a run whose evaluations answer faster
        // than the poll never waits long enough to time out.
        if let Err(signal) = py.check_signals() {
            return stopped(py, thread, signal);
        }
        match received {
            Ok(Message::Done(outcome)) => break outcome,
            Ok(Message::Progress(done, total, best)) => {
                if let Err(error) = progress(py, done, total, best) {
                    return stopped(py, thread, error);
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => {
                break Err(Failure::solver(
                    "the solve's thread ended without an answer",
                ));
            }
        }
    };
    let _ = thread.join();
    outcome.map_err(|failure| failure.into_py(py))
}
