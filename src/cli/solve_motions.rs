//! `codesign solve` on a task with several motions (`motions`): the motion `--motion` names, or
//! each motion solved and summarised in turn, with the task's score of them (docs/model.md,
//! section 10, "Several motions").

use super::failure::{Failure, INFEASIBLE_EXIT};
use super::solve_args::{
    configure, design, formulate, refuse_unwritable, solve_error, with_flags, Args,
};
use super::solve_summary::print_summary;
use crate::design::run::Loaded;
use codesign_core::choice::Choice;
use codesign_core::model::task::{MotionTask, MotionsScore, Task};
use codesign_core::solve::solve_design_from;
use codesign_core::text::number;

/// `loaded` with its task replaced by its motion `name` (the robot carrying that motion's
/// payload); an error when the task has no `motions` list or no motion of that name.
pub(super) fn pick_motion(loaded: Loaded, name: &str) -> Result<Loaded, Failure> {
    (loaded.one_motion(Some(name))).map_err(|why| Failure::from(format!("--motion {why}")))
}

/// The motions' names, comma-separated.
fn names(motions: &[MotionTask]) -> String {
    let names: Vec<&str> = motions.iter().map(|motion| motion.name.as_str()).collect();
    names.join(", ")
}

/// Refuses the flags that are of one motion (a result, plots, an export, a start, the
/// derivative checker) on a task whose motions are each solved.
fn refuse_single(args: &Args, task: &Task) -> Result<(), Failure> {
    let flags = [
        ("--out", args.out.is_some()),
        ("--plot", args.plot.is_some()),
        ("--export", args.export.is_requested()),
        ("--start", args.start.is_some()),
        ("--check-derivatives", args.check_derivatives),
    ];
    match flags.iter().find(|(_, given)| *given) {
        Some((flag, _)) => Err(Failure::Usage(format!(
            "{flag} is of one motion, and the task lists {} ({}): name one with --motion NAME",
            task.motions.len(),
            names(&task.motion_tasks())
        ))),
        None => Ok(()),
    }
}

/// Solves each motion of `loaded`'s task at the design of the flags (with `--duration`,
/// `--steps` and `--elastic` applied to each), prints each one's summary and the task's score
/// of them; fails after them where `--fail-if-infeasible` asks it to and a motion is infeasible.
pub(super) fn solve_each(args: &Args, loaded: Loaded) -> Result<(), Failure> {
    refuse_single(args, &loaded.task)?;
    let Loaded {
        task,
        robot,
        mut settings,
        ..
    } = loaded;
    configure(args, &mut settings);
    let (ratios, source) = design(args, &task);
    let (mut weighted, mut infeasible) = (Vec::new(), Vec::new());
    for motion in task.motion_tasks() {
        let one = with_flags(args, motion.task);
        say!(
            "motion {} (weight {}, {} kg, {} s):",
            motion.name,
            number(motion.weight),
            number(one.payload.mass_kg),
            one.motion.horizon
        );
        let formulation = formulate(
            args,
            &one,
            robot.with_payload(one.payload.mass_kg),
            &settings,
        )?;
        let (result, _) = solve_design_from(&formulation, &ratios, &settings, None)
            .map_err(|e| solve_error(args, &format!("{source}, motion {}", motion.name), e))?;
        refuse_unwritable(&result, &format!("{source}, motion {}", motion.name))?;
        print_summary(&formulation, &result);
        match result.feasible {
            true => weighted.push(motion.weight * result.cost),
            false => infeasible.push(motion.name),
        }
    }
    let score = task.motions_score;
    match score.combine(&weighted).filter(|_| infeasible.is_empty()) {
        Some((cost, _)) => say!(
            "{} motions: J = {cost:.6}, the {} of w_i J_i (motions_score {})",
            task.motions.len(),
            match score {
                MotionsScore::Sum => "sum",
                MotionsScore::Worst => "largest",
            },
            score.name()
        ),
        None => say!(
            "{} motions: the design is infeasible for {}",
            task.motions.len(),
            infeasible.join(", ")
        ),
    }
    match infeasible.is_empty() || !args.fail_if_infeasible {
        true => Ok(()),
        false => Err(Failure::Infeasible(format!(
            "{source}: the design is infeasible for motion {}; --fail-if-infeasible makes that \
             exit {INFEASIBLE_EXIT}",
            infeasible.join(", ")
        ))),
    }
}
