//! Co-design of the gear ratios and the motion of robots with parallel (belt) transmissions.
//!
//! The data flow one way: the robot model, its rigid-body dynamics, the trajectory problem, the
//! IPOPT solve, the design loop, and the reports. Beneath them all, the store writes result
//! files and the evaluation log, and imports nothing from the rest of the crate but `signals`
//! (what INT, TERM and HUP do: never stop a write half done).

#![warn(missing_docs)]

/// Writes a line on stderr like `eprintln!`, but a failed write (stderr on a full disk, a closed
/// stderr) is ignored instead of panicking: a note is never worth a crash.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::write_note(format_args!($($arg)*))
    };
}

/// The writer behind `note!`: one line on stderr, write errors ignored.
#[doc(hidden)]
pub fn write_note(text: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

pub mod cli;
pub mod design;
pub mod dynamics;
pub mod experiment;
pub mod hash;
pub mod input;
pub mod ipopt;
pub mod jet;
pub mod json_keys;
pub mod ldl;
pub mod model;
pub mod parallel;
pub mod problem;
pub mod report;
pub mod signals;
pub mod solve;
pub mod stats;
pub mod store;
#[cfg(test)]
mod testing;
pub mod text;
pub mod transmission;
