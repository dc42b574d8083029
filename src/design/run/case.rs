//! One co-design run as plain data: what `optimize` reads from its flags and what `reproduce`
//! plans, with every check of the settings in one place. Its errors name the flag of
//! `codesign optimize` that sets each value, since a case is what those flags pose.

use super::document::{Method, OptimizeInputs, RecordedHash, VerdictRule};
use crate::design::bounds::BoundHandling;
use crate::design::capacity::{CapacitySettings, MIN_RESOLUTION_KG};
use crate::design::cmaes::CmaesSettings;
use crate::design::gradient::GradientSettings;
use crate::design::penalty::{Grading, Penalty};
use crate::design::score::{Objective, PayloadRange};
use crate::design::warm::WarmStart;
use crate::design::workers::{Launcher, SOLVE_TIMEOUT_S};
use crate::ipopt::LinearSolver;
use crate::model::identity::task_hash;
use crate::model::task::{check_payload, Ends, LimitMode, LimitModes, Task, TaskFile, TaskSource};
use crate::model::Robot;
use crate::problem::Space;
use crate::solve::{SolveSettings, TaskRecord};
use crate::store::log::Start;
use crate::text::number;
use std::path::{Path, PathBuf};

/// Where the task and robot of a run come from, and its payload (`--task`, `--robot`,
/// `--payload`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelChoice {
    /// Where the task comes from.
    pub task: TaskSource,
    /// The robot's URDF, replacing the task's; None: the task's.
    pub robot: Option<PathBuf>,
    /// The payload, kg, replacing the task's.
    pub payload: Option<f64>,
    /// What the motion asks at its ends, replacing the task's `motion.ends`.
    pub ends: Option<Ends>,
}

/// The task `task` names, or the built-in one.
pub fn task_source(task: Option<&PathBuf>) -> TaskSource {
    task.map_or(TaskSource::BuiltIn, |path| TaskSource::File(path.clone()))
}

impl ModelChoice {
    /// Where the task comes from.
    pub fn source(&self) -> TaskSource {
        self.task.clone()
    }

    /// The files a run with this choice reads, each with where it was named: the task file
    /// (unless built in) and the robot's URDF (unless built in). An output must be none of them.
    pub fn inputs<'a>(&'a self, task: &'a Task) -> Vec<(&'static str, &'a Path)> {
        let task_file = self.task.path().map(|path| ("--task", path));
        let robot = task.robot.as_deref().map(|path| ("robot", path));
        task_file.into_iter().chain(robot).collect()
    }

    /// Checks what needs no file: the payload's range; the message names `--payload`.
    pub fn validate(&self) -> Result<(), String> {
        match self.payload {
            Some(payload) => check_payload(payload)
                .map_err(|why| format!("--payload {}: {why}", number(payload))),
            None => Ok(()),
        }
    }

    /// Loads the task (with the overrides applied), the robot carrying the payload, the solve
    /// settings of the task file's `solver` section, and the task hash.
    pub fn load(&self) -> Result<Loaded, String> {
        let file = self.source().load().map_err(|e| e.to_string())?;
        self.load_from(&file, None)
    }

    /// As [`ModelChoice::load`], from `file`, the task file already read; `robot`, where given,
    /// is the robot of that file's own task (its URDF, its payload), reused instead of read
    /// again unless this choice names another robot (a host that solves one task many times).
    pub fn load_from(&self, file: &TaskFile, robot: Option<&Robot>) -> Result<Loaded, String> {
        let source = self.source();
        let settings = SolveSettings::from_section(file.solver.as_ref())
            .map_err(|e| format!("{source}: {e}"))?;
        let mut as_read = file.task.clone();
        if let Some(ends) = self.ends {
            // The ends are part of the problem solved: the task hash counts them.
            as_read.motion.ends = ends;
        }
        let mut task = as_read.clone();
        if let Some(robot) = &self.robot {
            task.robot = Some(robot.clone());
        }
        self.validate()?;
        if let Some(payload) = self.payload {
            task.payload.mass_kg = payload;
        }
        let robot = match robot.filter(|_| self.robot.is_none()) {
            Some(robot) => robot.with_payload(task.payload.mass_kg),
            None => Robot::load(&task).map_err(|e| match (&self.robot, self.source()) {
                (None, source @ TaskSource::File(_)) => format!(
                    "{e} (the `robot` of {source}, relative to its folder; see `codesign task --help`)"
                ),
                _ => e.to_string(),
            })?,
        };
        Ok(Loaded {
            task_hash: task_hash(&as_read, robot.urdf_hash()),
            task,
            robot,
            settings,
        })
    }
}

/// What a run loads ([`ModelChoice::load`]).
pub struct Loaded {
    /// The task with the overrides applied (robot, payload).
    pub task: Task,
    /// The robot, carrying the payload.
    pub robot: Robot,
    /// The solve settings of the task file's `solver` section.
    pub settings: SolveSettings,
    /// The task hash of the task as read on this robot (`model::identity::task_hash`): the
    /// `--payload` override aside, `--robot` and `--ends` included.
    pub task_hash: String,
}

/// The space, limit modes and linear solver of a run's trajectory problems (`--space`,
/// `--torque-mode`, `--speed-mode`, `--linear-solver`).
#[derive(Clone, Debug, PartialEq)]
pub struct ProblemChoice {
    /// Joint or actuation space.
    pub space: Space,
    /// Joint torque limit mode; None: the task's.
    pub torque_mode: Option<LimitMode>,
    /// Joint speed limit mode; None: the task's.
    pub speed_mode: Option<LimitMode>,
    /// Linear solver inside IPOPT; None: the task's `solver.linear_solver`, else ldl.
    pub linear_solver: Option<LinearSolver>,
}

impl ProblemChoice {
    /// Applies the linear solver chosen to the solve settings.
    pub fn configure(&self, settings: &mut SolveSettings) {
        settings.override_linear_solver(self.linear_solver);
    }

    /// The limit modes: the ones chosen, else the task's.
    pub fn modes(&self, task: &Task) -> LimitModes {
        LimitModes {
            torque: self.torque_mode.unwrap_or(task.limit_modes.torque),
            speed: self.speed_mode.unwrap_or(task.limit_modes.speed),
        }
    }
}

/// The longest `--solve-timeout`, s: a week, beyond any solve of a task (the largest problem
/// allowed solves in minutes).
pub const MAX_SOLVE_TIMEOUT_S: f64 = 604_800.0;

/// The shortest `--solve-timeout`, s: a worker process must start, load its task and say hello
/// within it, which takes a fraction of a second.
pub const MIN_SOLVE_TIMEOUT_S: f64 = 1.0;

/// `text` quoted for `sh`: in single quotes, each single quote written as '\''.
pub fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// A co-design run of one case: the problem, the outer method and its settings, and how the
/// evaluations run.
#[derive(Clone, Debug)]
pub struct Case {
    /// Task, robot and payload.
    pub model: ModelChoice,
    /// Space, limit modes and linear solver.
    pub problem: ProblemChoice,
    /// The outer method.
    pub method: Method,
    /// What is minimised.
    pub objective: Objective,
    /// CMA-ES's settings; recorded in the result of every run (a gradient run of `reproduce`
    /// records population and generations 0).
    pub cmaes: CmaesSettings,
    /// The gradient method's settings.
    pub gradient: GradientSettings,
    /// How invalid or infeasible designs are scored.
    pub penalty: Penalty,
    /// Whether CMA-ES's samples are evaluated as drawn or projected onto the design space.
    pub bounds: BoundHandling,
    /// Whether CMA-ES's designs start from a solution of their generation's mean.
    pub warm_start: WarmStart,
    /// Worker processes (default: one per core).
    pub workers: Option<usize>,
    /// A solve taking longer than this counts as a hung worker, s.
    pub solve_timeout_s: f64,
    /// The shell command that starts one worker, `{}` standing for this binary's path (None:
    /// this binary's `worker`, started directly).
    pub worker_command: Option<String>,
    /// Fresh start, resumption of its evaluation log, or replacement of it.
    pub start: Start,
}

impl Case {
    /// A run of `method` with every setting at its default: the paper's CMA-ES, the flat
    /// penalty, one worker per core, a fresh start.
    pub fn new(model: ModelChoice, problem: ProblemChoice, method: Method) -> Case {
        Case {
            model,
            problem,
            method,
            objective: Objective::Cost,
            cmaes: CmaesSettings::default(),
            gradient: GradientSettings::default(),
            penalty: Penalty::PAPER,
            bounds: BoundHandling::Penalty,
            warm_start: WarmStart::default(),
            workers: None,
            solve_timeout_s: SOLVE_TIMEOUT_S,
            worker_command: None,
            start: Start::Fresh,
        }
    }

    /// Checks the settings that need no task; every error names the flag of `optimize` that
    /// sets the value, with the rule and its reason.
    pub fn validate(&self) -> Result<(), String> {
        self.model.validate()?;
        if self.method == Method::Cmaes {
            // The gradient method has no population or generations (reproduce records 0).
            self.cmaes.validate().map_err(|e| {
                let flag = match e.field {
                    "sigma0" => "sigma",
                    field => field,
                };
                format!("--{flag} {}: {}", e.value, e.rule)
            })?;
        }
        if self.penalty.grading == Grading::Graded {
            self.check_graded()?;
        }
        if self.method == Method::Gradient && !self.bounds.is_penalty() {
            return Err(format!(
                "--bounds {}: the gradient method keeps its iterates in the design space itself; \
                 use --method cmaes",
                self.bounds
            ));
        }
        if !(self.solve_timeout_s.is_finite()
            && (MIN_SOLVE_TIMEOUT_S..=MAX_SOLVE_TIMEOUT_S).contains(&self.solve_timeout_s))
        {
            return Err(format!(
                "--solve-timeout {}: must be {MIN_SOLVE_TIMEOUT_S} to {MAX_SOLVE_TIMEOUT_S} \
                 seconds (a worker needs about a second to start and say hello; no solve of a \
                 task takes a week)",
                number(self.solve_timeout_s)
            ));
        }
        if self.workers == Some(0) {
            return Err("--workers 0: must be at least 1".to_owned());
        }
        if self
            .worker_command
            .as_ref()
            .is_some_and(|line| line.trim().is_empty())
        {
            return Err("--worker-command: must be a shell command, e.g. \"{} worker\"".to_owned());
        }
        match (self.method, &self.objective) {
            (Method::Gradient, Objective::Capacity(_)) => Err(
                "--objective capacity: the capacity is not differentiable in r; use --method cmaes"
                    .to_owned(),
            ),
            (Method::Gradient, Objective::Range(_)) => Err(
                "--objective range: the gradient method descends one payload's cost; use \
                 --method cmaes"
                    .to_owned(),
            ),
            (_, Objective::Range(range)) => self.check_range(range),
            (Method::Gradient, _) if self.start == Start::Resume => Err(
                "--resume continues CMA-ES runs; a gradient run is short, start it again"
                    .to_owned(),
            ),
            (_, &Objective::Capacity(CapacitySettings { resolution_kg, .. }))
                if !(resolution_kg.is_finite() && resolution_kg >= MIN_RESOLUTION_KG) =>
            {
                Err(format!(
                    "--capacity-resolution {}: must be a mass of at least {MIN_RESOLUTION_KG} \
                     kg (1 mg, below what any scale resolves)",
                    number(resolution_kg)
                ))
            }
            _ => Ok(()),
        }
    }

    /// Checks that a graded penalty has something to grade: the cost of a design, at one
    /// payload or (CMA-ES) over a range.
    fn check_graded(&self) -> Result<(), String> {
        if matches!(self.objective, Objective::Capacity(_)) {
            return Err(
                "--penalty graded: the capacity search has no elastic form; use \
                 --objective cost or range"
                    .to_owned(),
            );
        }
        Ok(())
    }

    /// Checks the payloads of `--objective range`: at least one, each a valid payload, and no
    /// `--payload` beside them.
    fn check_range(&self, range: &PayloadRange) -> Result<(), String> {
        if let Some(payload) = self.model.payload {
            return Err(format!(
                "--payload {payload}: --objective range solves every payload of --payloads; leave \
                 --payload out"
            ));
        }
        if range.payloads_kg.is_empty() {
            return Err("--objective range: give the payloads with --payloads KG,KG,..".to_owned());
        }
        for &payload in &range.payloads_kg {
            check_payload(payload)
                .map_err(|why| format!("--payloads {}: {why}", number(payload)))?;
        }
        Ok(())
    }

    /// How the run's workers start, for this binary at `program`.
    pub fn launcher(&self, program: &Path) -> Launcher {
        match &self.worker_command {
            None => Launcher::Program(program.to_owned()),
            Some(line) => {
                Launcher::Shell(line.replace("{}", &shell_quote(&program.to_string_lossy())))
            }
        }
    }

    /// The flags of `codesign optimize` that pose this run (all but `--out`): what `reproduce
    /// --plan` prints.
    pub fn flags(&self) -> Vec<String> {
        let mut flags: Vec<String> = Vec::new();
        let mut push = |flag: &str, value: String| flags.extend([flag.to_owned(), value]);
        match &self.model.task {
            TaskSource::BuiltIn => {}
            TaskSource::File(task) => push("--task", shell_quote(&task.to_string_lossy())),
            // A task built in memory has no flag: its text is what the run's log records.
            TaskSource::Given(given) => push("--task", shell_quote(&given.label)),
        }
        if let Some(robot) = &self.model.robot {
            push("--robot", shell_quote(&robot.to_string_lossy()));
        }
        if let Some(payload) = self.model.payload {
            push("--payload", payload.to_string());
        }
        if let Some(ends) = self.model.ends {
            push("--ends", ends.to_string());
        }
        push("--space", self.problem.space.name().to_owned());
        if let Some(solver) = self.problem.linear_solver {
            push("--linear-solver", solver.name().to_owned());
        }
        if self.method == Method::Gradient {
            push("--method", "gradient".to_owned());
            push(
                "--gradient-iterations",
                self.gradient.max_iterations.to_string(),
            );
        }
        match &self.objective {
            Objective::Cost => {}
            Objective::Capacity(settings) => {
                push("--objective", "capacity".to_owned());
                push("--capacity-resolution", settings.resolution_kg.to_string());
            }
            Objective::Range(range) => {
                push("--objective", "range".to_owned());
                let payloads: Vec<String> = range.payloads_kg.iter().map(f64::to_string).collect();
                push("--payloads", payloads.join(","));
            }
        }
        push("--seed", self.cmaes.seed.to_string());
        push("--population", self.cmaes.population.to_string());
        push("--generations", self.cmaes.generations.to_string());
        push("--sigma", self.cmaes.sigma0.to_string());
        push("--penalty", self.penalty.to_string());
        if !self.bounds.is_penalty() {
            push("--bounds", self.bounds.to_string());
        }
        if self.method == Method::Cmaes && !self.warm_start.is_on() {
            push("--warm-start", self.warm_start.to_string());
        }
        if let Some(workers) = self.workers {
            push("--workers", workers.to_string());
        }
        if let Some(line) = &self.worker_command {
            push("--worker-command", shell_quote(line));
        }
        match self.start {
            Start::Fresh => {}
            Start::Resume => flags.push("--resume".to_owned()),
            Start::Overwrite => flags.push("--overwrite".to_owned()),
        }
        flags
    }

    /// The settings in which a run recorded as `inputs` differs from this case, as
    /// `setting: recorded X, case Y` (none: it is a run of this case). The task itself is not
    /// compared: the case names it by path only.
    pub fn differences(&self, inputs: &OptimizeInputs) -> Vec<String> {
        let mut found = Vec::new();
        let mut compare = |name: &str, recorded: String, case: String| {
            if recorded != case {
                found.push(format!("{name}: recorded {recorded}, planned {case}"));
            }
        };
        compare(
            "method",
            format!("{:?}", inputs.method),
            format!("{:?}", self.method),
        );
        compare(
            "objective",
            format!("{:?}", inputs.objective),
            format!("{:?}", self.objective),
        );
        compare(
            "space",
            inputs.space.to_string(),
            self.problem.space.to_string(),
        );
        if let Some(payload) = self.model.payload {
            compare(
                "payload_kg",
                inputs.payload_kg.to_string(),
                payload.to_string(),
            );
        }
        let penalty = |base: f64, grading| format!("{base} {grading:?}");
        compare(
            "penalty",
            penalty(inputs.penalty, inputs.grading),
            penalty(self.penalty.base, self.penalty.grading),
        );
        if self.method == Method::Cmaes {
            let c = &self.cmaes;
            compare("seed", inputs.seed.to_string(), c.seed.to_string());
            compare(
                "population",
                inputs.population.to_string(),
                c.population.to_string(),
            );
            compare(
                "generations",
                inputs.generations.to_string(),
                c.generations.to_string(),
            );
            compare("sigma0", inputs.sigma0.to_string(), c.sigma0.to_string());
            compare("bounds", inputs.bounds.to_string(), self.bounds.to_string());
            compare(
                "warm_start",
                inputs.warm_start.to_string(),
                self.warm_start.to_string(),
            );
        }
        found
    }

    /// The settings of the run as its document and log header record them, for the task, robot,
    /// solve settings (the linear solver chosen applied) and task hash `loaded`, with limit
    /// `modes`.
    pub fn inputs(&self, loaded: &Loaded, modes: LimitModes) -> OptimizeInputs {
        let (task, settings) = (&loaded.task, &loaded.settings);
        OptimizeInputs {
            method: self.method,
            objective: self.objective.clone(),
            task_file: self.model.source().label(),
            // The linear solver is recorded in its own field, so that a log written before the
            // field existed (MUMPS) compares by that field alone.
            task: TaskRecord {
                task: task.clone(),
                solver: settings.recorded(),
            },
            linear_solver: settings.linear_solver(),
            robot_hash: RecordedHash(Some(loaded.robot.urdf_hash().to_owned())),
            task_hash: RecordedHash(Some(loaded.task_hash.clone())),
            space: self.problem.space,
            payload_kg: task.payload.mass_kg,
            limit_modes: modes,
            seed: self.cmaes.seed,
            population: self.cmaes.population,
            generations: self.cmaes.generations,
            sigma0: self.cmaes.sigma0,
            penalty: self.penalty.base,
            grading: self.penalty.grading,
            bounds: self.bounds,
            ftol: self.cmaes.ftol,
            xtol: self.cmaes.xtol,
            verdict_rule: VerdictRule::default(),
            warm_start: match self.method {
                Method::Cmaes => self.warm_start,
                Method::Gradient => WarmStart::Off,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Case, Method, ModelChoice, ProblemChoice};
    use crate::design::bounds::BoundHandling;
    use crate::design::score::Objective;
    use crate::problem::Space;
    use crate::store::log::Start;

    fn case(method: Method) -> Case {
        let model = ModelChoice {
            task: crate::model::task::TaskSource::BuiltIn,
            robot: None,
            payload: Some(1.0),
            ends: None,
        };
        let problem = ProblemChoice {
            space: Space::Actuation,
            torque_mode: None,
            speed_mode: None,
            linear_solver: None,
        };
        Case::new(model, problem, method)
    }

    #[test]
    fn population_and_generations_are_checked_for_cma_es_only() {
        let mut cmaes = case(Method::Cmaes);
        cmaes.cmaes.population = 0;
        let error = cmaes.validate().unwrap_err();
        assert!(error.starts_with("--population 0: must be 5 to"), "{error}");
        let mut gradient = case(Method::Gradient);
        gradient.cmaes.population = 0;
        gradient.cmaes.generations = 0;
        gradient.validate().unwrap();
    }

    #[test]
    fn every_error_names_its_flag() {
        let mut sigma = case(Method::Cmaes);
        sigma.cmaes.sigma0 = -1.0;
        assert!(sigma.validate().unwrap_err().starts_with("--sigma -1:"));
        let mut resumed = case(Method::Gradient);
        resumed.start = Start::Resume;
        assert!(resumed.validate().unwrap_err().starts_with("--resume"));
        let mut capacity = case(Method::Gradient);
        capacity.objective = Objective::Capacity(Default::default());
        assert!(capacity
            .validate()
            .unwrap_err()
            .starts_with("--objective capacity"));
        let mut graded = case(Method::Cmaes);
        graded.objective = Objective::Capacity(Default::default());
        graded.penalty = "graded".parse().unwrap();
        assert!(graded
            .validate()
            .unwrap_err()
            .starts_with("--penalty graded"));
        // The gradient method grades too: it descends on the elastic problem.
        let mut descent = case(Method::Gradient);
        descent.penalty = "graded".parse().unwrap();
        descent.validate().unwrap();
        let mut clipped = case(Method::Gradient);
        clipped.bounds = BoundHandling::Clip;
        assert!(clipped.validate().unwrap_err().starts_with("--bounds clip"));
        clipped.method = Method::Cmaes;
        clipped.validate().unwrap();
        let mut timeout = case(Method::Cmaes);
        for absurd in [f64::NAN, 1e300, 0.0, 1e-300, 0.5] {
            timeout.solve_timeout_s = absurd;
            assert!(timeout
                .validate()
                .unwrap_err()
                .starts_with("--solve-timeout"));
        }
    }
}
