//! The native half of the `codesign` Python package: a task (`NativeTask`) and what it does
//! (check, solve, capacity, optimize), each returning the same JSON document as the command
//! line; a robot with its dynamics and transmission (`NativeRobot`), mirrored from the core; and
//! `serve_worker`, the worker process of co-design runs started from Python.
//!
//! The Python half (`python/codesign/`) turns the documents into objects with numpy arrays and
//! the errors into its exception classes. Every solve runs on a thread of its own with the GIL
//! released; the calling thread waits for it, looking every 100 ms whether Python has a signal
//! to raise (Ctrl-C), and then stops that work alone (`codesign_core::signals::StopToken`).

mod errors;
mod interrupt;
mod options;
mod parts;
mod robot;
mod runs;
mod solution;
mod task;
mod tradeoff;

use pyo3::prelude::*;

/// Serves a co-design run's evaluation requests on stdin and stdout until stdin closes: what
/// `python -m codesign.worker` runs, the worker of `Task.optimize`.
#[pyfunction]
fn serve_worker(py: Python<'_>) -> PyResult<()> {
    py.detach(|| {
        let stdin = std::io::stdin();
        codesign::design::workers::serve(stdin.lock(), std::io::stdout().lock())
            .map_err(|e| e.to_string())
    })
    .map_err(|message| errors::Failure::solver(message).into_py(py))
}

/// The codesign and IPOPT versions of this build.
#[pyfunction]
fn versions() -> (String, String) {
    (
        env!("CARGO_PKG_VERSION").to_owned(),
        codesign_core::ipopt::IPOPT_VERSION.to_owned(),
    )
}

/// The native module `codesign._native`.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    // The interpreter owns INT: a Ctrl-C reaches the waiting thread as KeyboardInterrupt, which
    // then stops the work (see `interrupt`).
    codesign_core::signals::leave_signals_to_host();
    module.add_class::<task::NativeTask>()?;
    module.add_class::<solution::NativeSolution>()?;
    module.add_class::<robot::NativeRobot>()?;
    module.add_function(wrap_pyfunction!(serve_worker, module)?)?;
    module.add_function(wrap_pyfunction!(versions, module)?)?;
    module.add_function(wrap_pyfunction!(task::task_text, module)?)?;
    module.add_function(wrap_pyfunction!(runs::optimize, module)?)?;
    module.add_function(wrap_pyfunction!(runs::log_beside, module)?)?;
    module.add_function(wrap_pyfunction!(parts::parts, module)?)?;
    Ok(())
}
