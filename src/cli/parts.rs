//! `codesign parts`: a search over the candidate parts of a task, each combination co-designed
//! in its ratios by the gradient method, and the front of actuator mass against the objective
//! (`pareto.json` and `pareto.svg`).

use super::common::{ModelArgs, ProblemArgs};
use super::failure::Failure;
use super::optimize::GradientArgs;
use super::progress::progress_line;
use super::run_flags::{case_error, ExecutionArgs};
use super::store_hints::run_error;
use crate::design::parts::{run_parts, PartsError, PartsEvent, PartsObjective, PartsSearch};
use crate::report::pareto::{write_pareto, PARETO_JSON, PARETO_SVG};
use crate::store::log::Start;
use codesign_core::model::part_family::PartsFamily;
use codesign_core::text::rounded;
use std::path::PathBuf;

/// Flags of `codesign parts`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// What judges each combination's design: `cost`, the optimal trajectory cost J* at the
    /// payload (the gradient method minimises it); `time`, the least duration T* of the motion
    /// (the gradient method minimises it); `capacity`, the payload capacity of the design the
    /// gradient method finds for the cost at the payload (larger is better).
    #[arg(long, value_enum, default_value = "cost")]
    pub objective: ObjectiveKind,
    #[command(flatten)]
    pub gradient: GradientArgs,
    #[command(flatten)]
    pub execution: ExecutionArgs,
    /// Output folder (made if missing): one co-design result per combination of parts, named
    /// from its candidates' parts, and pareto.json with its plot pareto.svg.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Continue an interrupted search: the combinations whose result is in the folder are
    /// read, not run again.
    #[arg(long)]
    pub resume: bool,
    /// Start afresh over an earlier search's folder: every combination is run again.
    #[arg(long, conflicts_with = "resume")]
    pub overwrite: bool,
}

/// The objective as a flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectiveKind {
    /// The optimal trajectory cost J* at the payload.
    Cost,
    /// The payload capacity of the design co-designed for the cost.
    Capacity,
    /// The least duration T* of the motion.
    Time,
}

impl Args {
    /// The search these flags ask for, its task read.
    fn search(&self) -> Result<PartsSearch, Failure> {
        let Some(task) = &self.model.task else {
            return Err(Failure::Usage(
                "--task: give a task file whose motors.parts offer candidates".to_owned(),
            ));
        };
        let family = PartsFamily::load(task).map_err(|e| Failure::Work(e.to_string()))?;
        Ok(PartsSearch {
            family,
            task_file: task.display().to_string(),
            model: self.model.choice(),
            problem: self.problem.choice(),
            objective: match self.objective {
                ObjectiveKind::Cost => PartsObjective::Cost,
                ObjectiveKind::Capacity => PartsObjective::Capacity,
                ObjectiveKind::Time => PartsObjective::Time,
            },
            penalty: self.gradient.penalty,
            gradient: self.gradient.settings(),
            execution: (self.execution).execution(Start::from_flags(self.resume, self.overwrite)),
        })
    }
}

/// Runs `codesign parts`: a line per combination, then the front.
pub fn run(args: &Args) -> Result<(), Failure> {
    args.model.validate()?;
    let search = args.search()?;
    search.validate().map_err(case_error)?;
    let mut observe = |event: PartsEvent<'_>| tell(args, event);
    let document = run_parts(&search, &args.out, &progress_line, &mut observe).map_err(
        |error| match error {
            PartsError::Case(error) => case_error(error),
            PartsError::Folder(why) => Failure::Work(why),
            PartsError::Run { parts, error } => {
                Failure::Work(format!("parts [{parts}]: {}", run_error(error)))
            }
        },
    )?;
    write_pareto(&args.out, &document).map_err(Failure::Work)?;
    say!(
        "front: {} of {} combinations ({} dominated, {} infeasible)",
        document.points.len(),
        document.points.len() + document.dominated.len() + document.infeasible.len(),
        document.dominated.len(),
        document.infeasible.len()
    );
    for point in &document.points {
        if let Some((mass, value)) = point.placed() {
            say!(
                "  {mass:.3} kg: {} = {} ({})",
                args.objective_name(),
                rounded(value),
                point.parts.join(", ")
            );
        }
    }
    say!(
        "written to {} ({} and {} beside the combinations' results)",
        args.out.display(),
        PARETO_JSON,
        PARETO_SVG
    );
    Ok(())
}

/// Prints a line for `event`: the combination starting, or its objective, r*, actuator mass
/// and work (or why it is infeasible).
fn tell(args: &Args, event: PartsEvent<'_>) {
    match event {
        PartsEvent::Started {
            index,
            total,
            combination,
        } => say!(
            "[{}/{total}] {} ({:.3} kg of motors)",
            index + 1,
            combination.parts.join(", "),
            combination.motor_mass_kg
        ),
        PartsEvent::Done {
            point, replayed, ..
        } => {
            let how = if replayed {
                " (read from the folder)"
            } else {
                ""
            };
            let ratios: Vec<String> = point.ratios.iter().map(|r| format!("{r:.4}")).collect();
            match point.placed() {
                Some((mass, value)) => say!(
                    "  {} = {} at r = ({}), actuator mass {mass:.3} kg; {} solves, {} \
                     iterations, {:.1} s{how}",
                    args.objective_name(),
                    rounded(value),
                    ratios.join(", "),
                    point.solves,
                    point.iterations,
                    point.wall_seconds
                ),
                None => say!(
                    "  infeasible: {}; {} solves, {:.1} s{how}",
                    point.stop_reason,
                    point.solves,
                    point.wall_seconds
                ),
            }
        }
    }
}

impl Args {
    /// The objective's value's name in the printed lines.
    fn objective_name(&self) -> &'static str {
        match self.objective {
            ObjectiveKind::Cost => "J*",
            ObjectiveKind::Capacity => "capacity (kg)",
            ObjectiveKind::Time => "T* (s)",
        }
    }
}
