//! `codesign task`: prints the built-in task, or the built-in robot, as a starting point.

use crate::model::task::BUILT_IN_TASK;
use crate::model::BUILT_IN_URDF;
use std::io::Write;

/// Flags of `codesign task`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print the built-in robot's URDF (`robots/belt_arm.urdf`) instead of the task.
    #[arg(long)]
    urdf: bool,
}

/// Writes the text on stdout; a failed write (a full disk behind `>`) is an error.
pub fn run(args: &Args) -> Result<(), String> {
    let text = if args.urdf {
        BUILT_IN_URDF
    } else {
        BUILT_IN_TASK
    };
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
        .map_err(|e| format!("cannot write to stdout: {e}"))
}
