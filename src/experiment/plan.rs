//! The experiment of a task as data: its [`Experiment`] (payloads, budgets), the budget and
//! output folder a [`PlanRequest`] asks for, and every co-design run of it as a [`Case`] with
//! the file it writes ([`PlannedRun`]).

use super::{CapacityOf, Layout, RunName};
use crate::design::capacity::CapacitySettings;
use crate::design::penalty::{Grading, Penalty, PENALTY};
use crate::design::run::{
    task_source, Case, CaseError, Execution, Method, ModelChoice, ProblemChoice, RunSettings,
};
use crate::design::score::{Objective, PayloadRange};
use crate::report::trajectory::every_plot_file;
use crate::store::log::Start;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::experiment::{Budget, Experiment, MAX_SEEDS};
use codesign_core::model::task::Ends;
use codesign_core::problem::Space;
use std::fmt;
use std::path::{Path, PathBuf};

/// Both spaces, joint first.
pub const SPACES: [Space; 2] = [Space::Joint, Space::Actuation];
/// The penalty of the runs beyond the paper at the edge of feasibility.
const GRADED_PENALTY: Penalty = Penalty {
    base: PENALTY,
    grading: Grading::Graded,
};
/// The space of the design for a payload range: beyond the paper, one design for the whole
/// range (the paper's stated goal is fruit from 1 to 3 kg).
const RANGE_SPACE: Space = Space::Actuation;

/// One co-design run of the experiment.
#[derive(Clone, Debug)]
pub struct PlannedRun {
    /// The name of its result in `runs/`, e.g. `actuation-1kg-seed0`.
    pub name: RunName,
    /// The run.
    pub case: Case,
}

/// What a reproduction asks of the task's experiment: each value None takes the experiment's.
#[derive(Clone, Debug)]
pub struct PlanRequest {
    /// The reduced run: the experiment's quick budget, written to `results/quick/` by default.
    pub quick: bool,
    /// Seeds per case, replacing the budget's.
    pub seeds: Option<u64>,
    /// CMA-ES population, replacing the budget's.
    pub population: Option<usize>,
    /// CMA-ES generations, replacing the budget's.
    pub generations: Option<usize>,
    /// The results folder (None: `results/`, or `results/quick/` for the quick run).
    pub folder: Option<PathBuf>,
    /// The task file (None: the built-in task).
    pub task: Option<PathBuf>,
    /// The linear solver inside IPOPT (None: the task's).
    pub linear_solver: Option<LinearSolver>,
    /// The settings every CMA-ES run shares (bound handling, warm starts); the plan sets the
    /// rest per run.
    pub cmaes: RunSettings,
    /// How every run's evaluations run and how the CMA-ES runs treat earlier logs.
    pub execution: Execution,
    /// What the motion asks at its ends (None: the task's).
    pub ends: Option<Ends>,
}

/// Why an experiment cannot be planned.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanError {
    /// A value the request gave is out of its range (keys `seeds`, `population`,
    /// `generations`, or a setting of the runs).
    Request(CaseError),
    /// A size of the task's experiment section is out of its range; names the task and field.
    Task(String),
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlanError::Request(error) => write!(f, "{error}"),
            PlanError::Task(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for PlanError {}

/// The experiment: its payloads, where it writes, how much it runs, and the settings every run
/// shares.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Labelled as a reduced run in the table.
    pub quick: bool,
    /// The task's experiment: its payloads and budgets.
    pub experiment: Experiment,
    /// The budget: the experiment's (its quick one when quick), with the request applied.
    pub budget: Budget,
    /// The output folder and where each result lies in it.
    pub layout: Layout,
    /// The task file (None: the built-in task).
    pub task: Option<PathBuf>,
    /// The linear solver inside IPOPT (None: the task's).
    pub linear_solver: Option<LinearSolver>,
    /// The settings every CMA-ES run shares (bound handling, warm starts).
    pub cmaes: RunSettings,
    /// How every run's evaluations run, and how the CMA-ES runs treat the logs of an earlier
    /// reproduction.
    pub execution: Execution,
    /// What the motion asks at its ends in every run: the request's, else the task's.
    pub ends: Ends,
    /// Whether this plan is the section beyond the paper that solves Table II's cases under
    /// `hold` ([`Plan::hold_section`]): its originals, CMA-ES runs and capacities only.
    pub is_hold_section: bool,
}

impl Plan {
    /// The plan of the task's `experiment` that `request` asks for: its seeds, population and
    /// generations replace the budget's values (the quick budget's when quick), its ends the
    /// task's `task_ends`; fails on a size out of range, naming the request's key or the
    /// task's field.
    pub fn new(
        request: &PlanRequest,
        experiment: Experiment,
        task_ends: Ends,
    ) -> Result<Plan, PlanError> {
        let base = if request.quick {
            experiment.quick_budget
        } else {
            experiment.budget
        };
        let budget = Budget {
            seeds: request.seeds.unwrap_or(base.seeds),
            population: request.population.unwrap_or(base.population),
            generations: request.generations.unwrap_or(base.generations),
            ..base
        };
        let folder = request.folder.clone().unwrap_or_else(|| {
            PathBuf::from(if request.quick {
                "results/quick"
            } else {
                "results"
            })
        });
        let plan = Plan {
            quick: request.quick,
            experiment,
            budget,
            layout: Layout::new(folder),
            task: request.task.clone(),
            linear_solver: request.linear_solver,
            cmaes: request.cmaes.clone(),
            execution: request.execution.clone(),
            ends: request.ends.unwrap_or(task_ends),
            is_hold_section: false,
        };
        plan.check_sizes(request)?;
        Ok(plan)
    }

    /// Beyond the paper, where the plan poses the paper's ends: Table II's cases (the original
    /// designs, CMA-ES per co-designed payload, space and seed, and their capacities) under
    /// `hold`, written to `OUT_DIR/hold/`. None under `hold` or `rest`, whose table it is.
    pub fn hold_section(&self) -> Option<Plan> {
        (self.ends == Ends::Paper && !self.is_hold_section).then(|| Plan {
            layout: self.layout.hold(),
            ends: Ends::Hold,
            is_hold_section: true,
            ..self.clone()
        })
    }

    /// Whether the budget is below the experiment's full one in any respect.
    pub fn is_reduced(&self) -> bool {
        let (b, full) = (&self.budget, &self.experiment.budget);
        self.quick
            || b.population < full.population
            || b.generations < full.generations
            || b.seeds < full.seeds
    }

    /// Checks the sizes before anything is created; errors name the request's key, or the
    /// task's field where the request did not give the value, with the limit and its reason.
    fn check_sizes(&self, request: &PlanRequest) -> Result<(), PlanError> {
        let section = if self.quick { "quick_budget" } else { "budget" };
        let in_task = |field: &str, value: String, rule: &str| {
            let task = task_source(self.task.as_ref());
            PlanError::Task(format!(
                "{task}: experiment.{section}.{field} = {value}: {rule}"
            ))
        };
        let seeds = self.budget.seeds;
        if !(1..=MAX_SEEDS).contains(&seeds) {
            let rule = format!("must be 1 to {MAX_SEEDS} (20 times the paper's 5)");
            return Err(match request.seeds {
                Some(_) => PlanError::Request(CaseError::new("seeds", seeds, rule)),
                None => in_task("seeds", seeds.to_string(), &rule),
            });
        }
        let cost = self.cost_case(Space::Actuation, 1.0, 0);
        if let Err(e) = cost.settings.cmaes.validate() {
            let given = match e.field {
                "population" => request.population.is_some(),
                "generations" => request.generations.is_some(),
                _ => true,
            };
            if !given {
                return Err(in_task(e.field, e.value, &e.rule));
            }
        }
        cost.validate().map_err(PlanError::Request)?;
        for run in self.capacity_runs() {
            (run.case.settings.cmaes.validate())
                .map_err(|e| in_task(&format!("capacity_{}", e.field), e.value, &e.rule))?;
        }
        Ok(())
    }

    /// A run in `space` at `payload` (None: the task's) with `method`, the plan's shared flags
    /// (`bounds` and `warm_start` for CMA-ES only) and every other setting at its default.
    fn case(&self, space: Space, payload: Option<f64>, method: Method) -> Case {
        let model = ModelChoice {
            task: task_source(self.task.as_ref()),
            robot: None,
            payload,
            ends: Some(self.ends),
        };
        let problem = ProblemChoice {
            space,
            torque_mode: None,
            speed_mode: None,
            linear_solver: self.linear_solver,
        };
        let mut case = Case::new(model, problem, method);
        if method == Method::Cmaes {
            // The gradient method keeps its iterates in the design space itself.
            case.settings = self.cmaes.clone();
        }
        case.execution = self.execution.clone();
        case
    }

    /// The CMA-ES run on the cost of one case and seed.
    fn cost_case(&self, space: Space, payload: f64, seed: u64) -> Case {
        let mut case = self.case(space, Some(payload), Method::Cmaes);
        case.settings.cmaes.seed = seed;
        case.settings.cmaes.population = self.budget.population;
        case.settings.cmaes.generations = self.budget.generations;
        case
    }

    /// Beyond the paper: one design for the experiment's payload range (none when it is empty),
    /// CMA-ES on the mean cost in [`RANGE_SPACE`] with the graded penalty (at the paper's 3 kg
    /// most designs are infeasible, and a flat penalty leaves CMA-ES nothing to rank; seed 0,
    /// the cost runs' budget).
    fn range_runs(&self) -> Vec<PlannedRun> {
        let payloads = &self.experiment.range_payloads_kg;
        let (Some(first), Some(last)) = (payloads.first(), payloads.last()) else {
            return Vec::new();
        };
        let mut case = self.case(RANGE_SPACE, None, Method::Cmaes);
        case.settings.objective = Objective::Range(PayloadRange {
            payloads_kg: payloads.clone(),
        });
        case.settings.set_penalty(GRADED_PENALTY);
        case.settings.cmaes.population = self.budget.population;
        case.settings.cmaes.generations = self.budget.generations;
        vec![PlannedRun {
            name: RunName::Range {
                space: RANGE_SPACE,
                first_kg: *first,
                last_kg: *last,
            },
            case,
        }]
    }

    /// The output folder.
    pub fn out_dir(&self) -> &Path {
        self.layout.root()
    }

    /// Every result `--from-runs` reads (`merge::read_all`): the original designs', the
    /// co-design runs' and the original designs' capacities. Under `--from-runs` they are
    /// inputs, which no output may be.
    pub fn merged_inputs(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = (self.experiment.original_payloads_kg.iter())
            .flat_map(|&payload| SPACES.map(|space| self.layout.original(space, payload)))
            .collect();
        let runs = [self.cost_runs(), self.gradient_runs(), self.beyond_runs()];
        files.extend(runs.iter().flatten().map(|run| self.layout.run(&run.name)));
        files.extend(SPACES.map(|space| self.layout.capacity(CapacityOf::Original(space))));
        files
    }

    /// Every file the reproduction writes itself, existing ones to be checked before any work
    /// (a co-design run checks its own): the table and its page, the original designs' results
    /// and plots (of a transmission of `motors` motors), the capacities.
    pub fn outputs(&self, motors: usize) -> Vec<PathBuf> {
        let mut files = vec![
            self.layout.table_markdown(),
            self.layout.table_json(),
            self.layout.index(),
        ];
        for &payload in &self.experiment.original_payloads_kg {
            for space in SPACES {
                files.push(self.layout.original(space, payload));
                let plots = self.layout.original_plots(space, payload);
                files.extend(every_plot_file(motors).iter().map(|name| plots.join(name)));
            }
        }
        for space in SPACES {
            files.push(self.layout.capacity(CapacityOf::Original(space)));
            for payload in &self.experiment.codesign_payloads_kg {
                files.push(self.layout.capacity(CapacityOf::Best(space, *payload)));
            }
        }
        // Folders not made yet hold nothing to protect.
        files.retain(|file| file.parent().is_some_and(Path::is_dir));
        files
    }

    /// The paper's co-design runs: CMA-ES on the cost, per co-designed payload, space and seed.
    pub fn cost_runs(&self) -> Vec<PlannedRun> {
        let mut runs = Vec::new();
        for &payload in &self.experiment.codesign_payloads_kg {
            for space in SPACES {
                for seed in 0..self.budget.seeds {
                    runs.push(PlannedRun {
                        name: RunName::Cost {
                            space,
                            payload_kg: payload,
                            seed,
                        },
                        case: self.cost_case(space, payload, seed),
                    });
                }
            }
        }
        runs
    }

    /// Beyond the paper: the gradient method per co-designed payload and space, and with the
    /// graded penalty per graded payload and space. Its results record no CMA-ES budget
    /// (population and generations 0).
    pub fn gradient_runs(&self) -> Vec<PlannedRun> {
        let mut runs = Vec::new();
        if self.is_hold_section {
            return runs;
        }
        for &payload in &self.experiment.codesign_payloads_kg {
            for space in SPACES {
                runs.push(PlannedRun {
                    name: RunName::Gradient {
                        space,
                        payload_kg: payload,
                        graded: false,
                    },
                    case: self.gradient_case(space, payload),
                });
            }
        }
        for &payload in &self.experiment.graded_payloads_kg {
            for space in SPACES {
                let mut case = self.gradient_case(space, payload);
                case.settings.set_penalty(GRADED_PENALTY);
                runs.push(PlannedRun {
                    name: RunName::Gradient {
                        space,
                        payload_kg: payload,
                        graded: true,
                    },
                    case,
                });
            }
        }
        runs
    }

    /// The gradient method's run in `space` at `payload` (it has no log to resume).
    fn gradient_case(&self, space: Space, payload: f64) -> Case {
        let mut case = self.case(space, Some(payload), Method::Gradient);
        case.settings.cmaes.population = 0;
        case.settings.cmaes.generations = 0;
        if case.execution.start == Start::Resume {
            case.execution.start = Start::Fresh;
        }
        case
    }

    /// The CMA-ES runs beyond the paper: the capacity designs, the payload range, and the
    /// graded payloads' cases with the graded penalty.
    pub fn beyond_runs(&self) -> Vec<PlannedRun> {
        if self.is_hold_section {
            return Vec::new();
        }
        let mut runs = self.capacity_runs();
        runs.extend(self.range_runs());
        runs.extend(self.graded_runs());
        runs
    }

    /// Beyond the paper: the graded payloads (the paper's 3 kg, at the edge of feasibility) with
    /// the graded penalty, per payload, space and seed, on the cost runs' budget.
    fn graded_runs(&self) -> Vec<PlannedRun> {
        let mut runs = Vec::new();
        for &payload in &self.experiment.graded_payloads_kg {
            for space in SPACES {
                for seed in 0..self.budget.seeds {
                    let mut case = self.cost_case(space, payload, seed);
                    case.settings.set_penalty(GRADED_PENALTY);
                    runs.push(PlannedRun {
                        name: RunName::Graded {
                            space,
                            payload_kg: payload,
                            seed,
                        },
                        case,
                    });
                }
            }
        }
        runs
    }

    /// Beyond the paper: the design that lifts the most, per space, by CMA-ES on minus the
    /// capacity (seed 0, the capacity budget).
    fn capacity_runs(&self) -> Vec<PlannedRun> {
        SPACES
            .iter()
            .map(|&space| {
                let mut case = self.case(space, None, Method::Cmaes);
                case.settings.objective = Objective::Capacity(CapacitySettings::default());
                case.settings.cmaes.population = self.budget.capacity_population;
                case.settings.cmaes.generations = self.budget.capacity_generations;
                PlannedRun {
                    name: RunName::Capacity { space },
                    case,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::{Plan, PlanError, PlanRequest};
    use crate::design::run::{Execution, Method, RunSettings};
    use codesign_core::model::experiment::{Budget, Experiment};
    use codesign_core::model::task::Ends;

    /// The request of a reproduction with every value the experiment's.
    fn request() -> PlanRequest {
        PlanRequest {
            quick: false,
            seeds: None,
            population: None,
            generations: None,
            folder: None,
            task: None,
            linear_solver: None,
            cmaes: RunSettings::new(Method::Cmaes),
            execution: Execution::default(),
            ends: None,
        }
    }

    fn plan(request: &PlanRequest) -> Result<Plan, PlanError> {
        Plan::new(request, Experiment::paper(), Ends::Paper)
    }

    #[test]
    fn sizes_are_checked_with_their_limits() {
        assert_eq!(plan(&request()).unwrap().budget, Budget::PAPER);
        // Issue 38, item 16: a value of the request out of its range names its key.
        let refused = |request: PlanRequest, key: &str, rule: &str| match plan(&request) {
            Err(PlanError::Request(error)) => {
                assert_eq!(error.key, key);
                assert!(error.rule.starts_with(rule), "{error}");
            }
            other => panic!("{other:?}"),
        };
        let seeds = PlanRequest {
            seeds: Some(0),
            ..request()
        };
        refused(seeds, "seeds", "must be 1 to");
        let population = PlanRequest {
            population: Some(0),
            ..request()
        };
        refused(population, "population", "must be 5 to");
        let generations = PlanRequest {
            generations: Some(1 << 40),
            ..request()
        };
        refused(generations, "generations", "must be at most");
        // The same size from the task file is the file's error, naming its field.
        let mut experiment = Experiment::paper();
        experiment.budget.seeds = 0;
        match Plan::new(&request(), experiment, Ends::Paper) {
            Err(PlanError::Task(message)) => assert!(
                message.contains("experiment.budget.seeds = 0: must be 1 to"),
                "{message}"
            ),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_experiment_has_every_case_once() {
        let quick = plan(&PlanRequest {
            quick: true,
            ..request()
        })
        .unwrap();
        assert!(quick.is_reduced());
        assert!(!plan(&request()).unwrap().is_reduced());
        let names: Vec<String> = quick
            .cost_runs()
            .into_iter()
            .chain(quick.gradient_runs())
            .chain(quick.beyond_runs())
            .map(|run| run.name.to_string())
            .collect();
        assert_eq!(names.len(), 2 * 2 * 2 + (4 + 2) + 2 + 1 + 2 * 2);
        assert!(names.contains(&"actuation-3kg-graded-gradient".to_owned()));
        assert!(names.contains(&"joint-3kg-graded-seed1".to_owned()));
        assert!(names.contains(&"actuation-range-1-3kg-seed0".to_owned()));
        assert_eq!(names[0], "joint-1kg-seed0");
        assert!(names.contains(&"actuation-3kg-gradient".to_owned()));
        let unique: std::collections::BTreeSet<&String> = names.iter().collect();
        assert_eq!(unique.len(), names.len(), "{names:?}");
        assert!(names.contains(&"joint-capacity-seed0".to_owned()));
    }

    #[test]
    fn the_task_s_experiment_names_the_runs() {
        let experiment = Experiment {
            codesign_payloads_kg: vec![2.0],
            graded_payloads_kg: vec![],
            range_payloads_kg: vec![0.5, 2.5],
            budget: Budget {
                seeds: 1,
                ..Budget::PAPER
            },
            ..Experiment::paper()
        };
        let plan = Plan::new(&request(), experiment, Ends::Paper).unwrap();
        let names: Vec<String> = plan
            .cost_runs()
            .into_iter()
            .chain(plan.gradient_runs())
            .chain(plan.beyond_runs())
            .map(|run| run.name.to_string())
            .collect();
        assert_eq!(
            names,
            [
                "joint-2kg-seed0",
                "actuation-2kg-seed0",
                "joint-2kg-gradient",
                "actuation-2kg-gradient",
                "joint-capacity-seed0",
                "actuation-capacity-seed0",
                "actuation-range-0.5-2.5kg-seed0",
            ]
        );
        // A task's budget below the paper's is the experiment's full run, not a reduced one.
        assert!(!plan.is_reduced());
        let mut quick = PlanRequest {
            quick: true,
            ..request()
        };
        assert!(Plan::new(&quick, Experiment::paper(), Ends::Paper)
            .unwrap()
            .is_reduced());
        quick.seeds = Some(1);
        assert_eq!(
            Plan::new(&quick, Experiment::paper(), Ends::Paper)
                .unwrap()
                .budget
                .seeds,
            1
        );
    }
}
