//! `codesign task`: prints the built-in task, or the built-in robot, as a starting point.

use codesign_core::model::task::BUILT_IN_TASK;
use codesign_core::model::BUILT_IN_URDF;

/// Flags of `codesign task`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print the built-in robot's URDF (`robots/belt_arm.urdf`) instead of the built-in task
    /// (`robots/tasks/pick_place.json`, the task every command poses without `--task`).
    #[arg(long)]
    urdf: bool,
}

/// Writes the text on stdout; a failed write (a full disk behind `>`, a closed stdout) makes
/// the command fail.
pub fn run(args: &Args) -> Result<(), String> {
    let text = if args.urdf {
        BUILT_IN_URDF
    } else {
        BUILT_IN_TASK
    };
    say_raw!("{text}");
    Ok(())
}
