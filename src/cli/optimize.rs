//! `codesign optimize`: co-design of one case (space, payload, seed) with CMA-ES or the gradient
//! method.

use super::common::{listed_number, ModelArgs, ProblemArgs};
use super::failure::Failure;
use super::progress::progress_line;
use super::run_flags::{case_error, RunArgs};
use super::store_hints::run_error;
use crate::cli::choice::choice;
use crate::design::capacity::CapacitySettings;
use crate::design::cmaes::CmaesSettings;
use crate::design::gradient::GradientSettings;
use crate::design::penalty::Penalty;
use crate::design::run::{run_case, Case, Method, MotionCost, OptimizeDocument};
use crate::design::score::{Objective, PayloadRange};
use crate::store::log::{log_beside, Start};
use codesign_core::choice::Choice;
use codesign_core::text::number;
use std::path::PathBuf;

/// Flags of `codesign optimize`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Outer-level method: `cmaes`, CMA-ES as in pagmo (the paper's), or `gradient`, projected
    /// quasi-Newton on the exact dJ*/dr with warm-started inner solves.
    #[arg(long, value_parser = choice::<Method>(), default_value = "cmaes")]
    pub method: Method,
    /// What to minimise: the trajectory cost at the payload, minus the payload capacity (each
    /// evaluation then bisects the payload: about 10 solves), or the least duration of the
    /// motion.
    #[arg(long, value_enum, default_value = "cost")]
    pub objective: ObjectiveKind,
    /// Payloads of `--objective range`, kg: each evaluation solves the design at every one (in
    /// its worker) and scores the mean cost, or the penalty when any is infeasible.
    #[arg(
        long,
        value_name = "KG,KG,..",
        value_delimiter = ',',
        num_args = 1..,
        value_parser = listed_number
    )]
    pub payloads: Option<Vec<f64>>,
    /// Resolution of the capacity search of `--objective capacity`, kg.
    #[arg(long, value_name = "KG", default_value_t = CapacitySettings::default().resolution_kg)]
    pub capacity_resolution: f64,
    /// Largest payload the capacity search of `--objective capacity` tries, kg, as `capacity
    /// --max`: designs that carry it tie there [default: 64].
    #[arg(long, value_name = "KG")]
    pub max: Option<f64>,
    #[command(flatten)]
    pub gradient: GradientArgs,
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Seed of CMA-ES's random numbers.
    #[arg(long, default_value_t = CmaesSettings::default().seed)]
    pub seed: u64,
    /// CMA-ES population size lambda.
    #[arg(long, default_value_t = CmaesSettings::default().population)]
    pub population: usize,
    /// CMA-ES generations after the initial population.
    #[arg(long, default_value_t = CmaesSettings::default().generations)]
    pub generations: usize,
    /// Initial step size, relative to the width of the design box: above 0, at most 1 (pagmo's
    /// range).
    #[arg(long, default_value_t = CmaesSettings::default().sigma0)]
    pub sigma: f64,
    #[command(flatten)]
    pub run: RunArgs,
    /// Result file (JSON); the evaluation log is written beside it as FILE.log.jsonl and locked
    /// for the whole run (a second run on the same file fails at once). A symbolic link is
    /// followed, and the log sits beside the file it points to; an input file, a folder, a
    /// special file or a file the user may not write is refused.
    #[arg(long, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
    /// Continue an interrupted run from its evaluation log (a run without a log starts afresh).
    #[arg(long)]
    pub resume: bool,
    /// Start afresh even if the evaluation log of an earlier run exists (it is deleted).
    #[arg(long, conflicts_with = "resume")]
    pub overwrite: bool,
}

/// The gradient method's flags, which `optimize` and `parts` share (`--penalty` scores
/// CMA-ES's designs too).
#[derive(Debug, Clone, clap::Args)]
pub struct GradientArgs {
    /// Iterations per start of the gradient method.
    #[arg(long, value_name = "N", default_value_t = GradientSettings::default().max_iterations)]
    pub gradient_iterations: usize,
    /// How invalid or infeasible designs score: `flat` (the paper's 1e6 for every one),
    /// `graded` (infeasible designs 1e6 to 2e6 by their torque deficit and speed excess from the
    /// elastic problem, invalid ones 2e6 to 3e6 by their distance from the design space, so that
    /// CMA-ES moves toward feasibility; the gradient method then descends on the elastic
    /// problem's objective, from infeasible starts too), or a number (flat, of that value).
    #[arg(long, value_name = "flat|graded|VALUE", default_value_t = Penalty::PAPER)]
    pub penalty: Penalty,
}

impl GradientArgs {
    /// The gradient method's settings these flags give.
    pub fn settings(&self) -> GradientSettings {
        GradientSettings {
            max_iterations: self.gradient_iterations,
            ..GradientSettings::default()
        }
    }
}

impl Args {
    /// The run these flags ask for.
    pub fn case(&self) -> Case {
        let mut case = Case::new(self.model.choice(), self.problem.choice(), self.method);
        let settings = &mut case.settings;
        settings.objective = match self.objective {
            ObjectiveKind::Cost => Objective::Cost,
            ObjectiveKind::Capacity => Objective::Capacity(CapacitySettings {
                resolution_kg: self.capacity_resolution,
                max_kg: self.max.unwrap_or(CapacitySettings::default().max_kg),
                ..CapacitySettings::default()
            }),
            ObjectiveKind::Range => Objective::Range(PayloadRange {
                payloads_kg: self.payloads.clone().unwrap_or_default(),
            }),
            ObjectiveKind::Energy => Objective::Energy,
            ObjectiveKind::Time => Objective::Time,
        };
        settings.cmaes = CmaesSettings {
            population: self.population,
            generations: self.generations,
            sigma0: self.sigma,
            seed: self.seed,
            ..CmaesSettings::default()
        };
        settings.set_penalty(self.gradient.penalty);
        self.run.apply(settings);
        case.gradient = self.gradient.settings();
        case.execution = self
            .run
            .execution(Start::from_flags(self.resume, self.overwrite));
        case
    }
}

/// The objective as a flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectiveKind {
    /// The optimal trajectory cost J (the paper's criterion).
    Cost,
    /// Minus the payload capacity.
    Capacity,
    /// The mean cost over the payloads of `--payloads`: one design for the whole range.
    Range,
    /// The motors' copper losses, J, which the trajectory problem then minimises instead of J
    /// (actuation space; needs the task's motors.torque_constant_nm_per_a and
    /// motors.resistance_ohm).
    Energy,
    /// The least duration T* of the motion, s: each design solves the task's pure minimum-time
    /// problem (the task's free horizon, or its fixed T freed to [0.3 T, 1.5 T]; J = T, no other
    /// weight, no box).
    Time,
}

/// Where a capacity run's designs reached its search's largest payload, in words: that the best
/// capacity is that ceiling, and how many evaluations reached it; None when none did.
pub fn ceiling_text(document: &OptimizeDocument) -> Option<String> {
    let Objective::Capacity(search) = &document.inputs.settings.objective else {
        return None;
    };
    let reached = document.at_max.filter(|&count| count > 0)?;
    Some(format!(
        "the search's ceiling (--max {} kg), reached by {reached} of {} evaluations, whose \
         capacities may be larger: a larger --max tells",
        number(search.max_kg),
        document.evaluations
    ))
}

/// The run's result in one line: the best design and its fitness, or that none was feasible.
fn summary(document: &OptimizeDocument) -> String {
    let join = |ratios: &[f64]| {
        let texts: Vec<String> = ratios.iter().map(|r| format!("{r:.4}")).collect();
        texts.join(", ")
    };
    let best = join(&document.best_ratios);
    let objective = &document.inputs.settings.objective;
    let found = match (objective, &document.payload_costs, document.best_cost) {
        (_, _, None) => "no feasible design found".to_owned(),
        (Objective::Capacity(_), _, Some(cost)) => {
            let found = format!("largest payload capacity {:.3} kg at r = ({best})", -cost);
            match ceiling_text(document) {
                Some(ceiling) => format!("{found}: {ceiling}"),
                None => found,
            }
        }
        (Objective::Range(_), Some(costs), Some(mean)) => {
            let per_payload: Vec<String> = costs
                .best
                .iter()
                .map(|c| format!("{} kg: {:.4}", c.payload_kg, c.cost))
                .collect();
            format!(
                "best r = ({best}) with mean J = {mean:.6} ({}; original design: {:.6})",
                per_payload.join(", "),
                document.original_cost
            )
        }
        (Objective::Time, _, Some(seconds)) if document.motion_costs.is_none() => format!(
            "best r = ({best}) with T* = {seconds:.6} s (original design: T* = {:.6} s)",
            document.original_cost
        ),
        (_, _, Some(cost)) => match &document.motion_costs {
            Some(costs) => {
                let (name, unit) = match objective {
                    Objective::Time => ("T*", " s"),
                    _ => ("J", ""),
                };
                format!(
                    "best r = ({best}) with {name} = {cost:.6}{unit}, the {} of the motions' \
                     ({}; original design: {name} = {:.6}{unit})",
                    costs.score.name(),
                    motions_text(&costs.best),
                    document.original_cost
                )
            }
            None => format!(
                "best r = ({best}) with J = {cost:.6} (original design: J = {:.6})",
                document.original_cost
            ),
        },
    };
    format!(
        "{found}; {} evaluations ({} replayed), {}; {}",
        document.evaluations,
        document.replayed,
        work_text(document),
        document.stop_reason
    )
}

/// Each motion's cost at a design, `NAME (w 2): 1.2345`, or why it is infeasible.
fn motions_text(costs: &[MotionCost]) -> String {
    let each: Vec<String> = (costs.iter())
        .map(|c| match c.feasible {
            true => format!("{} (w {}): {:.4}", c.name, number(c.weight), c.cost),
            false => format!(
                "{} (w {}): infeasible, {}",
                c.name,
                number(c.weight),
                c.status
            ),
        })
        .collect();
    each.join(", ")
}

/// Where a run's solver time went, in words: the median and total solve time, then the shares
/// of invalid and infeasible designs and the IPOPT iterations of each kind of verdict (where
/// the document counts them).
pub fn work_text(document: &OptimizeDocument) -> String {
    let timing = if document.median_solve_seconds.is_nan() {
        "no solve timed".to_owned()
    } else {
        format!(
            "median solve {:.1} ms, total solver time {:.1} s",
            document.median_solve_seconds * 1e3,
            document.solve_seconds_total
        )
    };
    match &document.verdicts {
        Some(verdicts) => format!("{timing}; {verdicts}"),
        None => timing,
    }
}

/// Runs `codesign optimize` and prints a summary.
pub fn run(args: &Args) -> Result<(), Failure> {
    let out = args.out.clone().unwrap_or_else(|| {
        let payload = args
            .model
            .payload
            .map_or_else(|| "task".to_owned(), |p| format!("{p}kg"));
        PathBuf::from(format!(
            "optimize-{}-{payload}-seed{}.json",
            args.problem.space, args.seed
        ))
    });
    if args.payloads.is_some() && args.objective != ObjectiveKind::Range {
        return Err(Failure::Usage(
            "--payloads: only with --objective range".to_owned(),
        ));
    }
    if args.max.is_some() && args.objective != ObjectiveKind::Capacity {
        return Err(Failure::Usage(
            "--max: only with --objective capacity".to_owned(),
        ));
    }
    let case = args.case();
    case.validate().map_err(case_error)?;
    let document = run_case(&case, &out, &progress_line).map_err(run_error)?;
    say!("{}", summary(&document));
    for bound in document.best_at_bounds() {
        say!("  at its bounds: {bound}");
    }
    match args.method {
        Method::Cmaes => say!(
            "result written to {} (evaluation log {})",
            out.display(),
            log_beside(&out).display()
        ),
        Method::Gradient => say!("result written to {}", out.display()),
    }
    Ok(())
}
