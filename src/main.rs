//! The `codesign` command line; everything it does lives in the library's `cli` module.

use std::sync::atomic::{AtomicBool, Ordering};

/// Whether the process started with its stdout closed (`codesign ... >&-`). Rust's runtime
/// reopens a closed stdout on /dev/null before `main`, so this is seen earlier, below.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Runs before Rust's runtime starts (an ELF initialiser): notes a closed descriptor 1.
extern "C" fn note_closed_stdout() {
    // SAFETY: F_GETFD only queries the descriptor's flags.
    let closed = unsafe { libc::fcntl(1, libc::F_GETFD) } == -1;
    STDOUT_CLOSED.store(closed, Ordering::Relaxed);
}

#[used]
#[link_section = ".init_array"]
static NOTE_CLOSED_STDOUT: extern "C" fn() = note_closed_stdout;

fn main() -> std::process::ExitCode {
    codesign::cli::main(STDOUT_CLOSED.load(Ordering::Relaxed))
}
