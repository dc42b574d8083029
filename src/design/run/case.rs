//! One co-design run as plain data: what `optimize` reads from its flags and what `reproduce`
//! plans, with every check of the settings in one place. Its errors name the flag of
//! `codesign optimize` that sets each value, since a case is what those flags pose.

use super::document::{OptimizeInputs, RecordedHash, VerdictRule};
use super::settings::Method;
use super::settings::{CaseError, Execution, RunSettings};
use crate::design::gradient::GradientSettings;
use crate::design::workers::Launcher;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::identity::task_hash;
use codesign_core::model::task::{
    check_payload, Ends, LimitMode, LimitModes, Task, TaskFile, TaskSource,
};
use codesign_core::model::Robot;
use codesign_core::problem::Space;
use codesign_core::solve::{SolveSettings, TaskRecord};
use codesign_core::text::number;
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

    /// Checks what needs no file: the payload's range.
    pub fn validate(&self) -> Result<(), CaseError> {
        match self.payload {
            Some(payload) => check_payload(payload)
                .map_err(|why| CaseError::new("payload_kg", number(payload), why.to_string())),
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
        self.validate().map_err(|e| e.to_string())?;
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

impl Loaded {
    /// This with its task replaced by the motion `name` of its `motions` list (the robot
    /// carrying that motion's payload), or with the task as it is for `name` None and a task of
    /// one motion; what is wrong otherwise, in words that follow the flag or keyword naming
    /// the motion (`NAME: ...`, to follow `--motion `; for None a sentence of its own).
    pub fn one_motion(self, name: Option<&str>) -> Result<Loaded, String> {
        let motions = self.task.motion_tasks();
        let names: Vec<&str> = motions.iter().map(|m| m.name.as_str()).collect();
        let names = names.join(", ");
        let Some(name) = name else {
            return match motions.is_empty() {
                true => Ok(self),
                false => Err(format!(
                    "the task lists {} motions ({names}); name the one to solve",
                    motions.len()
                )),
            };
        };
        if motions.is_empty() {
            return Err(format!(
                "{name}: the task has no `motions` list (it has one motion, `motion`); leave \
                 the motion out"
            ));
        }
        let Some(motion) = motions.into_iter().find(|motion| motion.name == name) else {
            return Err(format!(
                "{name}: the task has no motion of that name (its motions: {names})"
            ));
        };
        Ok(Loaded {
            robot: self.robot.with_payload(motion.task.payload.mass_kg),
            task: motion.task,
            ..self
        })
    }
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

/// `text` quoted for `sh`: in single quotes, each single quote written as '\''.
pub fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// A co-design run of one case: the problem, the settings that decide its result, and how its
/// evaluations run.
#[derive(Clone, Debug)]
pub struct Case {
    /// Task, robot and payload.
    pub model: ModelChoice,
    /// Space, limit modes and linear solver.
    pub problem: ProblemChoice,
    /// The method, objective, CMA-ES settings, penalty, bound handling and warm starts.
    pub settings: RunSettings,
    /// The gradient method's settings.
    pub gradient: GradientSettings,
    /// Workers, timeout and start.
    pub execution: Execution,
}

impl Case {
    /// A run of `method` with every setting at its default: the paper's CMA-ES, the flat
    /// penalty, one worker per core, a fresh start.
    pub fn new(model: ModelChoice, problem: ProblemChoice, method: Method) -> Case {
        Case {
            model,
            problem,
            settings: RunSettings::new(method),
            gradient: GradientSettings::default(),
            execution: Execution::default(),
        }
    }

    /// The outer method.
    pub fn method(&self) -> Method {
        self.settings.method
    }

    /// Checks the settings that need no task; the error names the setting by its key.
    pub fn validate(&self) -> Result<(), CaseError> {
        self.model.validate()?;
        self.settings
            .validate(self.model.payload, self.execution.start)?;
        self.execution.validate()
    }

    /// How the run's workers start, for this binary at `program`.
    pub fn launcher(&self, program: &Path) -> Launcher {
        match &self.execution.worker_command {
            None => Launcher::Program(program.to_owned()),
            Some(line) => {
                Launcher::Shell(line.replace("{}", &shell_quote(&program.to_string_lossy())))
            }
        }
    }

    /// The settings in which the run recorded as `inputs` differs from this case, as `key:
    /// recorded X, planned Y` (none: it is a run of this case): its settings key by key, its
    /// space, and its payload where the case gives one. The task is not compared: the case
    /// names it by path only.
    pub fn differences(&self, inputs: &OptimizeInputs) -> Vec<String> {
        let mut found = self.settings.differences(&inputs.settings);
        if inputs.space != self.problem.space {
            found.push(format!(
                "space: recorded {}, planned {}",
                inputs.space, self.problem.space
            ));
        }
        if let Some(payload) = self.model.payload.filter(|p| *p != inputs.payload_kg) {
            found.push(format!(
                "payload_kg: recorded {}, planned {payload}",
                inputs.payload_kg
            ));
        }
        found
    }

    /// The settings of the run as its document and log header record them, for the task, robot,
    /// solve settings (the linear solver chosen applied) and task hash `loaded`, with limit
    /// `modes`.
    pub fn inputs(&self, loaded: &Loaded, modes: LimitModes) -> OptimizeInputs {
        let (task, settings) = (&loaded.task, &loaded.settings);
        OptimizeInputs {
            settings: self.settings.recorded(),
            task_file: self.model.source().label(),
            // The linear solver is recorded in its own field, not in the task's solve settings.
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
            verdict_rule: VerdictRule::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Case, Method, ModelChoice, ProblemChoice};
    use crate::design::bounds::BoundHandling;
    use crate::design::score::Objective;
    use crate::store::log::Start;
    use codesign_core::problem::Space;

    fn case(method: Method) -> Case {
        let model = ModelChoice {
            task: codesign_core::model::task::TaskSource::BuiltIn,
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

    /// The key of the setting `case` is refused for.
    fn refused(case: &Case) -> &'static str {
        case.validate().unwrap_err().key
    }

    #[test]
    fn population_and_generations_are_checked_for_cma_es_only() {
        let mut cmaes = case(Method::Cmaes);
        cmaes.settings.cmaes.population = 0;
        let error = cmaes.validate().unwrap_err();
        assert_eq!(error.key, "population");
        assert!(error.rule.starts_with("must be 5 to"), "{error}");
        let mut gradient = case(Method::Gradient);
        gradient.settings.cmaes.population = 0;
        gradient.settings.cmaes.generations = 0;
        gradient.validate().unwrap();
    }

    #[test]
    fn every_error_names_its_setting() {
        let mut sigma = case(Method::Cmaes);
        sigma.settings.cmaes.sigma0 = -1.0;
        assert_eq!(refused(&sigma), "sigma0");
        let mut resumed = case(Method::Gradient);
        resumed.execution.start = Start::Resume;
        assert_eq!(refused(&resumed), "start");
        let mut capacity = case(Method::Gradient);
        capacity.settings.objective = Objective::Capacity(Default::default());
        assert_eq!(refused(&capacity), "objective");
        let mut graded = case(Method::Cmaes);
        graded.settings.objective = Objective::Capacity(Default::default());
        graded.settings.set_penalty("graded".parse().unwrap());
        assert_eq!(refused(&graded), "grading");
        // The gradient method grades too: it descends on the elastic problem.
        let mut descent = case(Method::Gradient);
        descent.settings.set_penalty("graded".parse().unwrap());
        descent.validate().unwrap();
        let mut clipped = case(Method::Gradient);
        clipped.settings.bounds = BoundHandling::Clip;
        assert_eq!(refused(&clipped), "bounds");
        clipped.settings.method = Method::Cmaes;
        clipped.validate().unwrap();
        let mut timeout = case(Method::Cmaes);
        for absurd in [f64::NAN, 1e300, 0.0, 1e-300, 0.5] {
            timeout.execution.solve_timeout_s = absurd;
            assert_eq!(refused(&timeout), "solve_timeout_s");
        }
        let mut heavy = case(Method::Cmaes);
        heavy.model.payload = Some(-1.0);
        assert_eq!(refused(&heavy), "payload_kg");
    }
}
