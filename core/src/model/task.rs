//! The task file: every default of the co-design problem that is not in the URDF.
//!
//! A task file (JSON, e.g. `robots/tasks/pick_place.json`) names the robot's URDF, the tool point
//! and payload, the motion to make, the cost weights, the Cartesian box, the motors, the
//! transmission's structure with its design space and the limit modes. Its `solver` section, the
//! settings of IPOPT, is not part of the model: [`TaskFile`] keeps it as written, for the solve
//! layer to read (`solve::SolveSettings::from_section`); its optional `experiment` section, what
//! `reproduce` runs, is read into [`Experiment`] (`super::experiment`). Units are SI throughout: m, kg, s, rad, N m. Frames: the world is the URDF's root link.
//!
//! `robots/tasks/pick_place.json` is compiled into the binary as the built-in task
//! ([`Task::built_in`]), so that every command works without files from any folder.

pub use super::carried::{CarriedMass, CarriedPart, CarriedPulley};
pub use super::ends::Ends;
use super::experiment::Experiment;
pub use super::horizon::Horizon;
pub use super::minimum_time::MINIMUM_TIME_RANGE;
use crate::choice::Choice;
use crate::input::{read_text, MAX_TASK_BYTES};
use crate::text::shown;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use super::goal::{Goal, TcpGoal};
pub use super::motions::{MotionEntry, MotionTask, MotionsScore, MAX_MOTION_NAME};
pub use super::motors::{Motors, PartChoice, PerMotor};
pub use super::ranges::{
    check_horizon, check_payload, check_steps, FieldError, OutOfRange, MAX_GRAVITY, MAX_HORIZON_S,
    MAX_PAYLOAD_KG, MAX_POINT_M, MAX_STEPS, MIN_HORIZON_S,
};
pub use super::via::{JointVia, TcpVia, Upright, Via, ViaTime};

/// The built-in task: the text of `robots/tasks/pick_place.json`, compiled in.
pub const BUILT_IN_TASK: &str = include_str!("../../../robots/tasks/pick_place.json");

/// A whole task file.
///
/// A task is data: it may be read from JSON ([`Task::load`]) or written in code, as here the
/// built-in arm's pick-and-place with a lighter motion of 20 intervals.
///
/// ```
/// use codesign_core::model::task::*;
///
/// let tool = PointOnLink { link: "link_4".into(), point: [0.0, 0.0, 0.15] };
/// let r = |name: &str| MatrixEntry::Ratio(name.into());
/// let c = MatrixEntry::Constant;
/// let task = Task {
///     robot: None, // the built-in arm
///     gravity: [0.0, 0.0, -9.81],
///     tcp: tool.clone(),
///     payload: Payload { mass_kg: 1.0, at: tool },
///     motion: Motion {
///         start: vec![0.0, 1.885, 0.0, 0.0],
///         goal: vec![-3.1416, -1.5708, -1.5708, 0.0].into(),
///         horizon: Horizon::Fixed(0.8),
///         steps: 20,
///         ends: Ends::Paper,
///         via: vec![],
///         upright: None,
///     },
///     weights: Weights { position: 0.01, velocity: 0.01, control: 0.001, time: 0.0 },
///     cartesian_box: CartesianBox::default(),
///     motors: Motors::ideal(PerMotor::All(1.7), PerMotor::All(100.0)),
///     transmission: TransmissionSpec {
///         matrix: vec![
///             MatrixRow::Entries(vec![r("r1"), c(0.0), c(0.0), c(0.0)]),
///             MatrixRow::Entries(vec![r("r2"), r("r2"), c(0.0), c(0.0)]),
///             MatrixRow::Entries(vec![c(1.0), r("r3"), r("r4"), r("r4")]),
///             MatrixRow::Entries(vec![c(1.0), r("r3"), r("r4"), r("-r4")]),
///         ],
///         original: vec![6.0, 3.0, 1.0, 1.0],
///         bounds: vec![[1.0, 9.0], [1.0, 9.0], [1.0, 3.0], [1.0, 3.0]],
///         order: vec!["r3 <= r2".into(), "r2 < r1".into()],
///     },
///     limit_modes: LimitModes { torque: LimitMode::Paper, speed: LimitMode::Exact },
///     motions: Vec::new(), // one motion: `motion`
///     motions_score: MotionsScore::Sum,
///     carried: vec![],
/// };
/// task.validate()?;
/// // The same task as JSON reads back equal.
/// let json = serde_json::to_string(&task)?;
/// assert_eq!(serde_json::from_str::<Task>(&json)?, task);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Task {
    /// Path of the robot's URDF, relative to the task file's folder (resolved when loaded);
    /// absent or null: the built-in robot, `robots/belt_arm.urdf` compiled in.
    pub robot: Option<PathBuf>,
    /// Gravity in the world frame, m/s^2.
    pub gravity: [f64; 3],
    /// The tool centre point whose position the Cartesian box constrains.
    pub tcp: PointOnLink,
    /// The payload: a point mass fixed to a link.
    pub payload: Payload,
    /// The motion: start and goal poses, horizon and discretisation.
    pub motion: Motion,
    /// The weights of the trajectory cost.
    pub weights: Weights,
    /// The soft Cartesian box on the TCP, per world axis (absent axes are free).
    pub cartesian_box: CartesianBox,
    /// The motors driving the transmission.
    pub motors: Motors,
    /// The transmission's structure, original design and design space.
    pub transmission: TransmissionSpec,
    /// How actuator limits become joint-space limits.
    pub limit_modes: LimitModes,
    /// Several motions of one design, each a named, weighted change of `motion` (and of the
    /// payload); empty (and not written) for a task of one motion.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "super::motions::non_empty"
    )]
    pub motions: Vec<MotionEntry>,
    /// How the motions' optimal costs make the task's score: their weighted sum (the default,
    /// not written) or the worst weighted one.
    #[serde(default, skip_serializing_if = "MotionsScore::is_sum")]
    pub motions_score: MotionsScore,
    /// Parts carried by links: pulleys whose teeth follow a ratio, motors and gearboxes
    /// (`super::carried`); empty (and not written) for none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub carried: Vec<CarriedPart>,
}

/// A task file as read: the task, its `solver` section as written (absent: none), which the
/// solve layer reads, and its `experiment` section, which `reproduce` runs.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskFile {
    /// The task.
    pub task: Task,
    /// The `solver` section: IPOPT's settings, not interpreted by the model.
    pub solver: Option<Value>,
    /// The `experiment` section, checked, its fields left out at the paper's values (absent:
    /// the paper's experiment).
    pub experiment: Experiment,
}

/// A point fixed in a link's frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointOnLink {
    /// The link's name in the URDF.
    pub link: String,
    /// Coordinates in the link's frame, m.
    pub point: [f64; 3],
}

/// A point-mass payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Payload {
    /// Mass in kg (0 for none); overridden by `--payload`.
    pub mass_kg: f64,
    /// Where it is attached.
    pub at: PointOnLink,
}

/// The motion to plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motion {
    /// Joint positions at t = 0, rad (joint order of the URDF chain from the root).
    pub start: Vec<f64>,
    /// Where the motion ends: joint positions at t = horizon, rad, or a TCP position within a
    /// tolerance (`{"tcp": [x, y, z], "tol_m": tol}`), the last node's angles then free.
    pub goal: Goal,
    /// Duration T, s: fixed, or free within bounds (`{"free": [T_min, T_max]}`).
    #[serde(rename = "horizon_s")]
    pub horizon: Horizon,
    /// Number of intervals N (nodes 0..=N).
    pub steps: usize,
    /// What the motion asks at its ends beyond q and v fixed at nodes 0 and N: nothing (the
    /// paper's `paper`), the load held at rest (`hold`, when the key is absent), or that and zero
    /// acceleration at nodes 0 and N-1 (`rest`).
    #[serde(default)]
    pub ends: Ends,
    /// Points the motion passes, each joint angles or a TCP position at a time (absent: none;
    /// docs/model.md, section 6).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub via: Vec<Via>,
    /// A link whose axis stays within a tolerance of the world's vertical at every node
    /// (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upright: Option<Upright>,
}

/// Weights of J = sum_k wq |q_k|^2 + wv |v_k|^2 + wu |u_k|^2 + box penalties + w_T T.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Weights {
    /// wq, per rad^2.
    pub position: f64,
    /// wv, per (rad/s)^2.
    pub velocity: f64,
    /// wu, per (N m)^2.
    pub control: f64,
    /// w_T, per s: the weight of the duration T in J (0, and not written, when absent). With
    /// every other weight 0, no box and a free horizon, J* = w_T T* is the minimum time.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub time: f64,
}

/// Whether a weight is 0: an absent weight is not written, so that the task hash of a task
/// written before the weight existed stays as it was.
fn is_zero(weight: &f64) -> bool {
    *weight == 0.0
}

/// A soft interval on one world coordinate of the TCP: penalty weight * violation^2.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SoftInterval {
    /// Lower and upper bound, m.
    pub range: [f64; 2],
    /// rho, per m^2.
    pub weight: f64,
}

/// The soft Cartesian box, per world axis.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CartesianBox {
    /// World x.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<SoftInterval>,
    /// World y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<SoftInterval>,
    /// World z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<SoftInterval>,
}

pub use super::matrix_row::MatrixRow;

/// One entry of the transmission matrix G: a constant or a signed design ratio.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum MatrixEntry {
    /// A fixed number.
    Constant(f64),
    /// `"r2"`, `"-r4"` or `"0.5*r2"`: a finite non-zero multiple of the named ratio
    /// (1-based).
    Ratio(String),
}

/// The transmission: motor angles q_u = G(r) q, joint torques tau = G(r)^T tau_u.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransmissionSpec {
    /// G(r), row i = motor i, column j = joint j: constant entries, or a linkage whose ratio
    /// changes with the pose.
    pub matrix: Vec<MatrixRow>,
    /// The original design r.
    pub original: Vec<f64>,
    /// Bounds [lower, upper] of each ratio.
    pub bounds: Vec<[f64; 2]>,
    /// Order constraints between ratios, e.g. `"r3 <= r2"`, `"r2 < r1"`.
    pub order: Vec<String>,
}

/// How actuator limits are mapped to joint space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LimitMode {
    /// Elementwise G^T (torque) or G^-1 (speed) applied to the bound vectors, as the paper prints.
    Paper,
    /// The tightest symmetric box containing the true polytope: sum_j |G_ji| * limit.
    Interval,
    /// The true limits as linear constraints.
    Exact,
}

impl Choice for LimitMode {
    const ALL: &'static [LimitMode] = &[LimitMode::Paper, LimitMode::Interval, LimitMode::Exact];

    fn name(self) -> &'static str {
        LimitMode::name(self)
    }
}

impl LimitMode {
    /// `paper`, `interval` or `exact`, as the task file and the flags spell it.
    pub fn name(self) -> &'static str {
        match self {
            LimitMode::Paper => "paper",
            LimitMode::Interval => "interval",
            LimitMode::Exact => "exact",
        }
    }
}

/// The limit modes of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitModes {
    /// Joint torque bounds of the joint-space problem.
    pub torque: LimitMode,
    /// Joint speed bounds (both problems).
    pub speed: LimitMode,
}

/// Where a task comes from.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum TaskSource {
    /// The built-in task, [`BUILT_IN_TASK`].
    #[default]
    BuiltIn,
    /// A task file.
    File(PathBuf),
    /// A task a program built in memory (the Python package's `Task.with_changes`), read and
    /// checked as a file is ([`TaskFile::from_text`]).
    Given(Arc<GivenTask>),
}

/// A task built in memory: what it was made from, in words, and the task read from it.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenTask {
    /// What the task was made from, e.g. `robots/tasks/pick_place.json with changes`.
    pub label: String,
    /// The task as read.
    pub file: TaskFile,
}

impl TaskSource {
    /// The file's path, `built-in`, or a given task's label: how result files record where
    /// their task came from.
    pub fn label(&self) -> String {
        match self {
            TaskSource::BuiltIn => "built-in".to_owned(),
            TaskSource::File(path) => path.display().to_string(),
            TaskSource::Given(given) => given.label.clone(),
        }
    }

    /// The task file's path, if the task comes from one.
    pub fn path(&self) -> Option<&Path> {
        match self {
            TaskSource::File(path) => Some(path),
            TaskSource::BuiltIn | TaskSource::Given(_) => None,
        }
    }

    /// Loads the task file from here: the built-in one ([`Task::built_in`]), a file
    /// ([`Task::load`]) or the given one, with its `solver` section.
    pub fn load(&self) -> Result<TaskFile, TaskError> {
        match self {
            TaskSource::BuiltIn => TaskFile::built_in(),
            TaskSource::File(path) => TaskFile::load(path),
            TaskSource::Given(given) => Ok(given.file.clone()),
        }
    }
}

impl fmt::Display for TaskSource {
    /// How messages name the task: `task file t.json`, its name as a terminal may show it
    /// ([`shown`]: an escape in it written `\u{1b}`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TaskSource::BuiltIn => write!(f, "built-in task"),
            TaskSource::File(path) => write!(f, "task file {}", shown(&path.display().to_string())),
            TaskSource::Given(given) => write!(f, "task {}", shown(&given.label)),
        }
    }
}

/// A task that could not be read or does not make sense; names its source and the field.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskError {
    /// The task file, the built-in task or a given task, in words (`task file t.json`).
    pub source: String,
    /// What is wrong, naming the field.
    pub message: String,
}

impl fmt::Display for TaskError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.source, self.message)
    }
}

impl std::error::Error for TaskError {}

impl TaskFile {
    /// Reads and checks a task file. A relative robot path is resolved against the file's folder.
    pub fn load(path: &Path) -> Result<TaskFile, TaskError> {
        let source = TaskSource::File(path.to_owned()).to_string();
        let text = read_text(path, MAX_TASK_BYTES).map_err(|e| TaskError {
            source: source.clone(),
            message: e.to_string(),
        })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        TaskFile::from_json(&text, source, Some(folder)).map(|file| file.robot_from(folder))
    }

    /// Reads and checks the JSON `text` of a task built in memory, as a file is read, its
    /// errors naming the task by `label`; a relative robot path is resolved against `folder`.
    pub fn from_text(text: &str, label: &str, folder: &Path) -> Result<TaskFile, TaskError> {
        let source = format!("task {}", shown(label));
        if text.len() as u64 > MAX_TASK_BYTES {
            return Err(TaskError {
                source,
                message: format!("longer than the {MAX_TASK_BYTES} bytes a task may have"),
            });
        }
        TaskFile::from_json(text, source, Some(folder)).map(|file| file.robot_from(folder))
    }

    /// This task file with a relative robot path resolved against `folder`.
    fn robot_from(mut self, folder: &Path) -> TaskFile {
        if let Some(robot) = self.task.robot.as_mut().filter(|robot| robot.is_relative()) {
            *robot = folder.join(&*robot);
        }
        self
    }

    /// The built-in task, [`BUILT_IN_TASK`], with the built-in robot. Its `robot` path,
    /// `../belt_arm.urdf` beside `robots/tasks/`, names the very URDF compiled in as the built-in
    /// robot, so it is replaced by `None`.
    pub fn built_in() -> Result<TaskFile, TaskError> {
        let mut file = TaskFile::from_json(BUILT_IN_TASK, TaskSource::BuiltIn.to_string(), None)?;
        file.task.robot = None;
        Ok(file)
    }

    /// Parses and checks the JSON `text` of a task from `source` (named in errors); the robot
    /// path is left as written, the `solver` section is kept as written, the `experiment`
    /// section is read and checked, the motors' catalogue parts are read, their paths joined
    /// to `folder` (`super::motor_parts::resolve`).
    fn from_json(text: &str, source: String, folder: Option<&Path>) -> Result<TaskFile, TaskError> {
        let parsed = crate::json_keys::check_unique_keys(text)
            .and_then(|()| serde_json::from_str::<Value>(text).map_err(|e| e.to_string()))
            .and_then(|mut value| {
                let mut section = |name| value.as_object_mut().and_then(|map| map.remove(name));
                let solver = section("solver");
                let experiment = Experiment::from_section(section("experiment").as_ref())
                    .map_err(|e| e.to_string())?;
                super::motor_parts::resolve(&mut value, folder)?;
                super::carried::resolve(&mut value, folder)?;
                let task = read_task(text, &value)?;
                task.validate().map_err(|e| e.to_string())?;
                Ok(TaskFile {
                    task,
                    solver,
                    experiment,
                })
            });
        parsed.map_err(|message| TaskError { source, message })
    }
}

/// Reads the task `value` parsed from `text` (its `solver` and `experiment` sections taken
/// out); a value of the wrong type is named with its field and line, e.g.
/// `motion.steps at line 10: invalid type: string "10", expected usize`.
fn read_task(text: &str, value: &Value) -> Result<Task, String> {
    crate::json_keys::read_value(value).map_err(|error| {
        let field = error.field("");
        let line = crate::json_keys::line_of(text, &error.path);
        match (field.is_empty(), line) {
            (true, _) => error.message,
            (false, Some(line)) => format!("{field} at line {line}: {}", error.message),
            (false, None) => format!("{field}: {}", error.message),
        }
    })
}

impl Task {
    /// Reads and checks a task file, without its `solver` section ([`TaskFile::load`]).
    pub fn load(path: &Path) -> Result<Task, TaskError> {
        TaskFile::load(path).map(|file| file.task)
    }

    /// The built-in task without its `solver` section ([`TaskFile::built_in`]).
    pub fn built_in() -> Result<Task, TaskError> {
        TaskFile::built_in().map(|file| file.task)
    }

    /// The time step h = T / N of a fixed horizon, s; None where T is free or the via points
    /// split the grid into phases (the steps are then the problem's,
    /// [`crate::problem::Setting::step_at`]).
    pub fn step_s(&self) -> Option<f64> {
        let fixed = self.motion.horizon.fixed_s()?;
        if self.motion.phased() {
            return None;
        }
        Some(fixed / self.motion.steps as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_task_path() -> PathBuf {
        crate::testing::task_path()
    }

    #[test]
    fn default_task_loads_with_the_spec_values() {
        let task = Task::load(&default_task_path()).unwrap();
        assert_eq!(task.motion.steps, 50);
        assert!((task.step_s().unwrap() - 0.016).abs() < 1e-15);
        assert!((task.motion.start[1] - 0.6 * std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(task.transmission.original, vec![6.0, 3.0, 1.0, 1.0]);
        assert_eq!(task.limit_modes.torque, LimitMode::Paper);
        let robot = task.robot.unwrap();
        assert!(robot.ends_with("belt_arm.urdf"));
        assert!(robot.starts_with(default_task_path().parent().unwrap()));
    }

    #[test]
    fn built_in_task_is_the_task_file_with_the_built_in_robot() {
        let file = Task::load(&default_task_path()).unwrap();
        let robot_file = file.robot.clone().unwrap();
        let built_in = Task::built_in().unwrap();
        assert_eq!(built_in.robot, None);
        assert_eq!(
            built_in,
            Task {
                robot: None,
                ..file
            }
        );
        let urdf = std::fs::read_to_string(robot_file).unwrap();
        assert_eq!(urdf, crate::model::robot::BUILT_IN_URDF);
    }

    #[test]
    fn errors_name_the_built_in_task_and_a_task_without_robot_means_the_built_in_one() {
        let broken = BUILT_IN_TASK.replacen("\"steps\": 50", "\"steps\": 0", 1);
        let message = TaskFile::from_json(&broken, TaskSource::BuiltIn.to_string(), None)
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with("built-in task: motion.steps"),
            "{message}"
        );
        let without = BUILT_IN_TASK.replacen("\"robot\": \"../belt_arm.urdf\",", "", 1);
        assert_ne!(without, BUILT_IN_TASK);
        let task = TaskFile::from_json(&without, TaskSource::BuiltIn.to_string(), None)
            .unwrap()
            .task;
        assert_eq!(task.robot, None);
    }

    #[test]
    fn errors_name_the_file_and_field() {
        let text = std::fs::read_to_string(default_task_path()).unwrap();
        let dir = std::env::temp_dir().join(format!("codesign-task-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let cases = [
            (
                "\"horizon_s\": 0.8",
                "\"horizon_s\": -1",
                "motion.horizon_s",
            ),
            ("\"steps\": 50", "\"stepz\": 50", "stepz"),
            (
                "\"steps\": 50",
                "\"steps\": 99999999999",
                "motion.steps = 99999999999: the number of intervals must be 1 to 5000",
            ),
            ("\"horizon_s\": 0.8", "\"horizon_s\": 1e9", "<= 3600"),
            (
                "\"position\": 0.01",
                "\"position\": 1e308",
                "weights.position = 1e308 must be >= 0 and <= 1000000 per rad^2 (",
            ),
            (
                "\"weight\": 1000.0",
                "\"weight\": 1e-320",
                "cartesian_box.y.weight = 1e-320 must be 0 or at least 2.2250738585072014e-308",
            ),
            (
                "\"steps\": 50",
                "\"steps\": \"10\"",
                "motion.steps at line 10: invalid type: string \"10\", expected usize",
            ),
            (
                "[0.0, 0.0, -9.81]",
                "[0.0, -9.81]",
                "gravity at line 3: invalid length 2, expected an array of length 3",
            ),
            (
                "[[1.0, 9.0], [1.0, 9.0]",
                "[[1.0, 9.0], [1.0, \"9\"]",
                "transmission.bounds[1][1] at line 27: invalid type: string",
            ),
            (
                "\"mass_kg\": 0.0",
                "\"mass_kg\": 1e6",
                "payload.mass_kg = 1000000: the payload must be",
            ),
            ("\"mass_kg\": 0.0", "\"mass_kg\": -2", "payload.mass_kg"),
            ("[-1.0, 0.4]", "[0.4, -1.0]", "cartesian_box.y.range"),
            ("\"torque\": \"paper\"", "\"torque\": \"papr\"", "papr"),
            (
                "\"steps\": 50,",
                "\"steps\": 10, \"steps\": 5000,",
                "the key `steps` is given twice in one object (only one value can count) at line 10",
            ),
            (
                "\"limit_modes\"",
                "\"experiment\": {\"budget\": {\"seeds\": 0}}, \"limit_modes\"",
                "experiment.budget.seeds = 0: must be 1 to 100",
            ),
        ];
        for (k, (from, to, field)) in cases.into_iter().enumerate() {
            assert!(text.contains(from));
            let path = dir.join(format!("case{k}.json"));
            std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
            let message = Task::load(&path).unwrap_err().to_string();
            assert!(message.contains(field), "{message}");
            assert!(message.contains(&path.display().to_string()), "{message}");
        }
        let missing = Task::load(&dir.join("absent.json"))
            .unwrap_err()
            .to_string();
        assert!(
            missing.contains("absent.json") && missing.contains("cannot read"),
            "{missing}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
