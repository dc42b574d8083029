//! Fixtures of the unit tests: the repository's task, its problems, and seeded random numbers.

use crate::model::task::{Task, TaskFile};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::rng::DesignRng;
use crate::solve::SolveSettings;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The repository's root folder, which holds the robots, the tasks and the committed results.
pub fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The repository's task file (the one the built-in task is compiled from).
pub fn task_path() -> PathBuf {
    repository().join("robots/tasks/pick_place.json")
}

/// The repository's task, loaded from its file.
pub fn task() -> Task {
    Task::load(&task_path()).expect("the repository's task loads")
}

/// The planar example with a pulley whose teeth follow r2 and a motor on its upper arm
/// (`robots/examples/planar_2dof/carried_pulley.json`).
pub fn carried_task() -> Task {
    Task::load(&repository().join("robots/examples/planar_2dof/carried_pulley.json"))
        .expect("the example with carried parts loads")
}

/// The repository's task with the load held at rest at its ends (`motion.ends` `hold`), where
/// its own ends are the paper's: the fixture of the tests of the hold as a condition.
pub fn held_task() -> Task {
    let mut task = task();
    task.motion.ends = crate::model::task::Ends::Hold;
    task
}

/// [`formulation`] of [`held_task`].
pub fn held_formulation(payload_kg: f64, space: Space) -> Formulation {
    let mut task = held_task();
    task.payload.mass_kg = payload_kg;
    let robot = Robot::load(&task).expect("the repository's robot loads");
    Formulation::new(&task, robot, space, task.limit_modes).expect("the task formulates")
}

/// The solve settings of the repository's task file (its `solver` section).
pub fn settings() -> SolveSettings {
    let file = TaskFile::load(&task_path()).expect("the repository's task loads");
    SolveSettings::from_section(file.solver.as_ref()).expect("its solver section is valid")
}

/// The repository's task carrying `payload_kg`, formulated in `space` with its limit modes.
pub fn formulation(payload_kg: f64, space: Space) -> Formulation {
    let mut task = task();
    task.payload.mass_kg = payload_kg;
    let robot = Robot::load(&task).expect("the repository's robot loads");
    Formulation::new(&task, robot, space, task.limit_modes).expect("the task formulates")
}

/// Uniform random numbers from the project's seeded stream: the same on every machine.
pub struct Random(DesignRng);

impl Random {
    /// The stream of `seed`.
    pub fn new(seed: u64) -> Random {
        Random(DesignRng::new(seed))
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.uniform()
    }

    /// Uniform in `range`.
    pub fn real(&mut self, range: Range<f64>) -> f64 {
        range.start + (range.end - range.start) * self.unit()
    }

    /// `n` values uniform in [-scale, scale).
    pub fn vector(&mut self, n: usize, scale: f64) -> Vec<f64> {
        (0..n).map(|_| self.real(-scale..scale)).collect()
    }

    /// Uniform among the integers of `range`.
    pub fn index(&mut self, range: Range<usize>) -> usize {
        range.start + ((range.end - range.start) as f64 * self.unit()) as usize
    }
}

/// The planar two-joint example (`robots/examples/planar_2dof`) with its elbow driven by a
/// pose-dependent `row` (a linkage object of the task file) as row 1 of G, the elbow moving
/// between -1 and 1 rad, limit modes `exact`: the fixture of the pose-dependent tests.
pub fn posed_task(row: &str) -> Task {
    let path = repository().join("robots/examples/planar_2dof/task.json");
    let mut task = Task::load(&path).expect("the planar example loads");
    task.transmission.matrix[1] = serde_json::from_str(row).expect("the linkage row parses");
    task.motion.start[1] = -1.0;
    task.motion.goal.joints_mut().expect("a joint goal")[1] = 1.0;
    task
}

/// The two-axis ankle example (`robots/examples/ankle_2dof`), driven by two crank-rods.
pub fn ankle_task() -> Task {
    let path = repository().join("robots/examples/ankle_2dof/task.json");
    Task::load(&path).expect("the ankle example loads")
}

/// A ball screw on the planar example's elbow, its lead the design parameter r2 (in mm): 0.15 m
/// from the elbow on the upper arm to 0.10 m from it on the forearm.
pub const SCREW_ROW: &str = r#"{"linear": {"from": {"link": "upper_arm", "point": [0.15, 0, 0]},
    "to": {"link": "forearm", "point": [0, 0, 0.1]}, "lead_m": "0.001*r2"}}"#;

/// [`SCREW_ROW`] with a stroke of [0.08, 0.25] m: the motion's ends (0.24 m at -1 rad, 0.085 m
/// at 1 rad) lie within it, and the stroke binds where the free motion swings the elbow past
/// the goal.
pub const STROKED_SCREW_ROW: &str = r#"{"linear": {"from": {"link": "upper_arm", "point": [0.15, 0, 0]},
    "to": {"link": "forearm", "point": [0, 0, 0.1]}, "lead_m": "0.001*r2", "stroke_m": [0.08, 0.25]}}"#;

/// A crank and rod driving the planar example's elbow: a crank of 60 mm on the upper arm, 0.2 m
/// behind the elbow, through a 10:1 gear, and a 0.2 m rod to a lever of 50 mm on the forearm.
pub const CRANK_ROW: &str = r#"{"crank_rod": {"crank": {"link": "upper_arm",
    "point": [0.1, 0, 0], "axis": [0, -1, 0], "radius_m": 0.06, "ratio": 10}, "rod_m": 0.2,
    "to": {"link": "forearm", "point": [0, 0, 0.05]}}}"#;

/// The SCARA example (`robots/examples/scara_3dof`): two turning arms and a vertical quill, a
/// prismatic joint driven by a constant row in rad/m; `quill` replaces that row when given, its
/// parameter r3 then a lead in mm (10, within [2.5, 40]).
pub fn scara_task(quill: Option<&str>) -> Task {
    let path = repository().join("robots/examples/scara_3dof/task.json");
    let mut task = Task::load(&path).expect("the SCARA example loads");
    if let Some(row) = quill {
        let transmission = &mut task.transmission;
        transmission.matrix[2] = serde_json::from_str(row).expect("the quill row parses");
        transmission.original[2] = 10.0;
        transmission.bounds[2] = [2.5, 40.0];
    }
    task
}

/// A ball screw along the SCARA's quill, its lead the design parameter r3 (in mm): from 0.05 m
/// above the quill's joint frame on the outer arm down to that frame, (0.05 + q) m apart, so
/// that q_u = 2 pi (0.05 + q) / lead: the constant ratio 2 pi / lead.
pub const QUILL_SCREW_ROW: &str = r#"{"linear": {"from": {"link": "outer_arm", "point": [0.175, 0, 0.05]},
    "to": {"link": "quill", "point": [0, 0, 0]}, "lead_m": "0.001*r3"}}"#;

/// A screw driving the SCARA's quill at a slant, from 75 mm beside its axis on the outer arm:
/// a ratio that changes with the quill's position.
pub const SLANTED_QUILL_ROW: &str = r#"{"linear": {"from": {"link": "outer_arm", "point": [0.1, 0, 0.05]},
    "to": {"link": "quill", "point": [0, 0, 0]}, "lead_m": "0.001*r3"}}"#;
