//! What the whole-command benchmarks share: timing a command and reading the machine's load.

use std::process::Command;
use std::time::Instant;

/// Runs `command`, which must succeed, and returns its standard output and wall time, s.
pub fn timed(command: &mut Command) -> (String, f64) {
    let start = Instant::now();
    let output = command.output().expect("the command starts");
    let wall = start.elapsed().as_secs_f64();
    assert!(
        output.status.success(),
        "{command:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    (String::from_utf8_lossy(&output.stdout).into_owned(), wall)
}

/// The machine's load averages over 1, 5 and 15 minutes, as /proc/loadavg gives them.
pub fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}
