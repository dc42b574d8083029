//! `codesign task`: prints the built-in task, or the built-in robot, as a starting point.

use codesign_core::model::task::BUILT_IN_TASK;
use codesign_core::model::BUILT_IN_URDF;

/// Flags of `codesign task`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print the built-in robot's URDF (`robots/belt_arm.urdf`) instead of the task (printed as
    /// a template for one's own robot: the built-in task with `motion.ends` `hold`).
    #[arg(long)]
    urdf: bool,
}

/// The built-in task as a template for a user's own robot: the paper's task with its ends set
/// to `hold`, the physical default (the motors hold the load at rest at the start and the goal).
pub fn template() -> String {
    BUILT_IN_TASK.replacen("\"ends\": \"paper\"", "\"ends\": \"hold\"", 1)
}

/// Writes the text on stdout; a failed write (a full disk behind `>`, a closed stdout) makes
/// the command fail.
pub fn run(args: &Args) -> Result<(), String> {
    let text = if args.urdf {
        BUILT_IN_URDF.to_owned()
    } else {
        template()
    };
    say_raw!("{text}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use codesign_core::model::task::{Ends, Task};

    #[test]
    fn the_template_is_the_built_in_task_holding_its_load() {
        let template: Task = {
            let mut value: serde_json::Value = serde_json::from_str(&super::template()).unwrap();
            value.as_object_mut().unwrap().remove("solver");
            value.as_object_mut().unwrap().remove("robot");
            serde_json::from_value(value).unwrap()
        };
        let built_in = Task::built_in().unwrap();
        assert_eq!(built_in.motion.ends, Ends::Paper);
        assert_eq!(template.motion.ends, Ends::Hold);
        let mut held = built_in;
        held.motion.ends = Ends::Hold;
        assert_eq!(template, held);
    }
}
