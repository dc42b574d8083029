//! `codesign worker`: the worker process of co-design runs (internal).

use crate::design::workers::serve;

/// Serves evaluation requests on stdin/stdout until stdin closes.
pub fn run() -> Result<(), String> {
    let stdin = std::io::stdin();
    serve(stdin.lock(), std::io::stdout().lock()).map_err(|e| e.to_string())
}
