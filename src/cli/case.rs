//! One co-design run as plain data: what `optimize` reads from its flags and what `reproduce`
//! plans, with every check of the settings in one place.

use super::common::{ModelArgs, ProblemArgs};
use crate::design::capacity::CapacitySettings;
use crate::design::cmaes::CmaesSettings;
use crate::design::evaluate::{Objective, PayloadRange};
use crate::design::gradient::GradientSettings;
use crate::design::penalty::{Grading, Penalty};
use crate::design::workers::{Launcher, SOLVE_TIMEOUT_S};
use crate::model::task::{check_payload, LimitModes, Task};
use crate::report::codesign::{Method, OptimizeInputs};
use crate::store::log::Start;
use std::path::Path;

/// `text` quoted for `sh`: in single quotes, each single quote written as '\''.
pub fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// A co-design run of one case: the problem, the outer method and its settings, and how the
/// evaluations run.
#[derive(Clone, Debug)]
pub struct Case {
    /// Task, robot and payload.
    pub model: ModelArgs,
    /// Space, limit modes and linear solver.
    pub problem: ProblemArgs,
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
    pub fn new(model: ModelArgs, problem: ProblemArgs, method: Method) -> Case {
        Case {
            model,
            problem,
            method,
            objective: Objective::Cost,
            cmaes: CmaesSettings::default(),
            gradient: GradientSettings::default(),
            penalty: Penalty::PAPER,
            workers: None,
            solve_timeout_s: SOLVE_TIMEOUT_S,
            worker_command: None,
            start: Start::Fresh,
        }
    }

    /// Checks the settings that need no task; every error names the flag of `optimize` that
    /// sets the value, with the rule and its reason.
    pub fn validate(&self) -> Result<(), String> {
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
        if !(self.solve_timeout_s.is_finite() && self.solve_timeout_s > 0.0) {
            return Err(format!(
                "--solve-timeout {}: must be a positive number of seconds",
                self.solve_timeout_s
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
                if !(resolution_kg.is_finite() && resolution_kg > 0.0) =>
            {
                Err(format!(
                    "--capacity-resolution {resolution_kg}: must be a positive mass"
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
            check_payload(payload).map_err(|why| format!("--payloads {payload}: {why}"))?;
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
        if let Some(task) = &self.model.task {
            push("--task", shell_quote(&task.to_string_lossy()));
        }
        if let Some(robot) = &self.model.robot {
            push("--robot", shell_quote(&robot.to_string_lossy()));
        }
        if let Some(payload) = self.model.payload {
            push("--payload", payload.to_string());
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

    /// The settings of the run as its document and log header record them, for `task` (the
    /// overrides applied) with limit `modes`.
    pub fn inputs(&self, task: &Task, modes: LimitModes) -> OptimizeInputs {
        let mut recorded = task.clone();
        // The linear solver is recorded in its own field, so that a log written before the
        // field existed (MUMPS) compares by that field alone.
        recorded.solver.linear_solver = None;
        OptimizeInputs {
            method: self.method,
            objective: self.objective.clone(),
            task_file: self.model.source().label(),
            task: recorded,
            linear_solver: task.solver.linear_solver(),
            space: self.problem.space,
            payload_kg: task.payload.mass_kg,
            limit_modes: modes,
            seed: self.cmaes.seed,
            population: self.cmaes.population,
            generations: self.cmaes.generations,
            sigma0: self.cmaes.sigma0,
            penalty: self.penalty.base,
            grading: self.penalty.grading,
            ftol: self.cmaes.ftol,
            xtol: self.cmaes.xtol,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Case;
    use crate::cli::common::{ModelArgs, ProblemArgs};
    use crate::design::evaluate::Objective;
    use crate::problem::Space;
    use crate::report::codesign::Method;
    use crate::store::log::Start;

    fn case(method: Method) -> Case {
        let model = ModelArgs {
            task: None,
            robot: None,
            payload: Some(1.0),
        };
        let problem = ProblemArgs {
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
        let mut timeout = case(Method::Cmaes);
        timeout.solve_timeout_s = f64::NAN;
        assert!(timeout
            .validate()
            .unwrap_err()
            .starts_with("--solve-timeout"));
    }
}
