//! Catalogue parts with the numbers of a task's own motors, and a massless pulley, through
//! whole solves: the reproduction harness (issue 53). Each of its 20 cases (both spaces, 0, 1
//! and 3 kg, every limit mode, hard and elastic solves, the ends `paper`, `rest` and `hold`,
//! the torque-speed envelope, rotor inertia with friction and electrical figures, transmission
//! losses, two example robots, one driven through a ball screw) is solved twice: with the
//! motors as the task writes them, and with every motor a part of
//! `tests/data/catalogue/harness.json` carrying exactly its numbers and a pulley of that
//! catalogue's massless belt series on a link, its teeth following a ratio of the design. The
//! two results are equal bit for bit.

use super::{solve_design, solve_elastic, SolveSettings, TrajectoryResult};
use crate::model::carried::CarriedMassAt;
use crate::model::catalogue::Catalogue;
use crate::model::motor_parts::FIGURES;
use crate::model::task::{Ends, LimitMode, LimitModes, PerMotor, Task, TaskFile};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;
use serde_json::{json, Map, Value};
use std::path::PathBuf;

/// The harness's catalogue: its cases' motors as parts, and the belt series `massless`.
fn catalogue_path() -> PathBuf {
    testing::repository().join("tests/data/catalogue/harness.json")
}

/// One case of the harness: its task, how it is solved, and where its pulley sits.
struct Case {
    /// What the case exercises, for messages.
    label: &'static str,
    /// The task file, under `robots/`.
    file: &'static str,
    /// What the case changes in the task (its motors' figures, its ends).
    edit: fn(&mut Task),
    space: Space,
    /// The payload, kg (None: the task's).
    payload: Option<f64>,
    /// The limit modes (None: the task's).
    modes: Option<LimitModes>,
    /// The design (None: the task's original).
    design: Option<&'static [f64]>,
    /// The elastic problem (`solve_elastic`) rather than the rule of `solve_design`.
    elastic: bool,
    /// The link that carries the pulley and the ratio its teeth follow.
    pulley: (&'static str, &'static str),
}

/// A case of the paper's arm (`robots/tasks/pick_place.json`), its pulley on `link_2` with
/// r2's teeth.
fn arm(label: &'static str, space: Space, payload: f64) -> Case {
    Case {
        label,
        file: "tasks/pick_place.json",
        edit: |_| {},
        space,
        payload: Some(payload),
        modes: None,
        design: None,
        elastic: false,
        pulley: ("link_2", "r2"),
    }
}

/// A case of an example robot (`robots/examples/`) as its task gives it.
fn example(
    label: &'static str,
    file: &'static str,
    space: Space,
    pulley: (&'static str, &'static str),
) -> Case {
    Case {
        file,
        payload: None,
        pulley,
        ..arm(label, space, 0.0)
    }
}

impl Case {
    fn modes(self, torque: LimitMode, speed: LimitMode) -> Case {
        let modes = Some(LimitModes { torque, speed });
        Case { modes, ..self }
    }

    fn at(self, design: &'static [f64]) -> Case {
        let design = Some(design);
        Case { design, ..self }
    }

    fn elastic(self) -> Case {
        Case {
            elastic: true,
            ..self
        }
    }

    fn with(self, edit: fn(&mut Task)) -> Case {
        Case { edit, ..self }
    }

    /// The case's task with the motors as it writes them.
    fn task(&self) -> Task {
        let mut task = Task::load(&testing::repository().join("robots").join(self.file)).unwrap();
        (self.edit)(&mut task);
        if let Some(payload) = self.payload {
            task.payload.mass_kg = payload;
        }
        task
    }

    /// `task` solved as the case says, with the repository task's solve settings.
    fn solve(&self, task: &Task, settings: &SolveSettings) -> TrajectoryResult {
        let robot = Robot::load(task).unwrap();
        let modes = self.modes.unwrap_or(task.limit_modes);
        let formulation = Formulation::new(task, robot, self.space, modes).unwrap();
        let design = self.design.unwrap_or(&task.transmission.original);
        let solved = match self.elastic {
            true => solve_elastic(&formulation, design, settings),
            false => solve_design(&formulation, design, settings),
        };
        solved.unwrap_or_else(|e| panic!("{}: {e}", self.label))
    }
}

/// Rotor inertia and viscous friction per motor (`solve::tests::with_motor_terms`), with a
/// torque constant and a winding resistance, so that results report the copper losses.
fn motor_terms(task: &mut Task) {
    *task = super::tests::with_motor_terms(task);
    task.motors.torque_constant_nm_per_a = Some(PerMotor::All(0.1));
    task.motors.resistance_ohm = Some(PerMotor::All(2.0));
}

/// The 20 cases: the cheapest designs and payloads that exercise each feature.
fn cases() -> Vec<Case> {
    use LimitMode::{Exact, Interval, Paper};
    use Space::{Actuation, Joint};
    vec![
        arm("original design, 0 kg", Joint, 0.0),
        arm("original design, 0 kg", Actuation, 0.0),
        arm("original design, 1 kg", Joint, 1.0),
        arm("original design, 1 kg", Actuation, 1.0),
        arm("the paper's 1 kg design, 3 kg", Actuation, 3.0).at(&[9.0, 7.72, 3.0, 3.0]),
        arm("torque exact, speed exact", Joint, 1.0).modes(Exact, Exact),
        arm("torque interval, speed interval", Joint, 1.0).modes(Interval, Interval),
        arm("torque paper, speed paper", Joint, 1.0).modes(Paper, Paper),
        arm("elastic", Actuation, 1.0).elastic(),
        arm("elastic, torque exact", Joint, 1.0)
            .modes(Exact, Exact)
            .elastic(),
        arm("ends hold", Actuation, 1.0).with(|t| t.motion.ends = Ends::Hold),
        arm("ends rest", Joint, 0.0)
            .with(|t| t.motion.ends = Ends::Rest)
            .modes(Exact, Exact),
        arm("envelope", Actuation, 1.0)
            .with(|t| t.motors.no_load_speed_rad_s = Some(PerMotor::All(250.0)))
            .at(&[7.0, 4.0, 2.0, 2.0]),
        arm("envelope, torque interval", Joint, 0.0)
            .with(|t| t.motors.no_load_speed_rad_s = Some(PerMotor::All(250.0)))
            .modes(Interval, Exact)
            .at(&[6.5, 3.5, 1.5, 1.2]),
        arm("rotor inertia, friction, k_t and R", Actuation, 1.0)
            .with(motor_terms)
            .at(&[7.0, 4.0, 2.0, 2.0]),
        arm(
            "rotor inertia, friction, k_t and R, torque exact",
            Joint,
            0.0,
        )
        .with(motor_terms)
        .modes(Exact, Paper)
        .at(&[8.0, 4.0, 2.0, 2.5]),
        arm("losses per motor", Actuation, 1.0)
            .with(|t| t.motors.efficiency = Some(PerMotor::Each(vec![0.9, 0.85, 0.95, 0.8])))
            .at(&[7.0, 4.0, 2.0, 2.3]),
        arm("losses, torque interval", Joint, 0.0)
            .with(|t| t.motors.efficiency = Some(PerMotor::All(0.9)))
            .modes(Interval, Exact),
        example(
            "planar arm, elbow on a ball screw",
            "examples/planar_2dof/ball_screw.json",
            Actuation,
            ("upper_arm", "r1"),
        ),
        example(
            "SCARA",
            "examples/scara_3dof/task.json",
            Joint,
            ("inner_arm", "r2"),
        ),
    ]
}

/// The name of the harness catalogue's motor whose every figure of the motor model
/// ([`FIGURES`]) is motor `i`'s in the task's `motors` section `motors` (absent where the
/// task gives none).
fn part_with(motors: &Map<String, Value>, i: usize, catalogue: &Catalogue) -> String {
    let of_task = |key: &str| {
        let value = motors.get(key)?;
        serde_json::from_value::<PerMotor>(value.clone())
            .unwrap()
            .get(i)
    };
    let same = |motor: &&_| FIGURES.iter().all(|f| (f.of_part)(motor) == of_task(f.key));
    let found = catalogue.motors.iter().find(same);
    let found = found.unwrap_or_else(|| {
        panic!(
            "harness.json has no motor of motor {}'s figures in {motors:?}",
            i + 1
        )
    });
    found.name.clone()
}

/// `task` with every motor a part of the harness's catalogue carrying exactly its figures (the
/// figures left out of `motors`, for the parts to set) and a massless pulley on `link` whose
/// teeth follow `ratio`, read as a task file is read.
fn with_parts(task: &Task, catalogue: &Catalogue, (link, ratio): (&str, &str)) -> Task {
    let path = catalogue_path();
    let mut value = serde_json::to_value(task).unwrap();
    let motors = value["motors"].as_object_mut().unwrap();
    let written = motors.clone();
    let parts: Vec<Value> = (0..task.transmission.matrix.len())
        .map(|i| json!({"catalogue": path, "name": part_with(&written, i, catalogue)}))
        .collect();
    for figure in &FIGURES {
        motors.remove(figure.key);
    }
    motors.insert("parts".to_owned(), json!(parts));
    let pulley = json!({"catalogue": path, "series": "massless", "teeth_of": ratio,
                        "driver_teeth": 12});
    value["carried"] = json!([{"link": link, "at": [0.05, 0.0, 0.0], "pulley": pulley}]);
    let folder = testing::repository();
    TaskFile::from_text(&value.to_string(), "harness", &folder)
        .unwrap()
        .task
}

/// The mass of the motors `task` chooses from the harness's catalogue, summed as results sum
/// it, kg.
fn parts_mass_kg(task: &Task, catalogue: &Catalogue) -> f64 {
    let mut total = 0.0;
    for part in task.motors.parts.as_deref().unwrap() {
        total += catalogue.motor(&part.name).unwrap().mass_kg.unwrap();
    }
    total
}

/// Each case's result with catalogue parts and a massless pulley is the result with the
/// task's own motors, bit for bit: J, the iterations, dJ*/dr, the verdict, the trajectory and
/// every other field, but for those that record the parts and the times.
#[test]
fn catalogue_parts_and_a_massless_pulley_reproduce_the_harness_bit_for_bit() {
    let settings = testing::settings();
    let catalogue = Catalogue::load(&catalogue_path()).unwrap();
    let cases = cases();
    assert_eq!(cases.len(), 20);
    for case in cases {
        let label = format!("{} ({}, {})", case.label, case.file, case.space);
        let own = case.task();
        let parts = with_parts(&own, &catalogue, case.pulley);
        // The parts set the very figures the task gave its motors, and nothing else moved.
        let mut bare = parts.clone();
        (bare.motors.parts, bare.carried) = (None, Vec::new());
        assert_eq!(bare, own, "{label}: the task read with parts");
        let expected = case.solve(&own, &settings);
        let mut found = case.solve(&parts, &settings);
        assert_eq!(found.cost.to_bits(), expected.cost.to_bits(), "{label}");
        assert_eq!(found.iterations, expected.iterations, "{label}");
        // What differs, and only there: the solve's times; the carried parts' masses at the
        // design (the pulley's, 0 kg), which the task without parts does not list; and the
        // actuator mass, the parts' masses and the pulley's, which it has none of.
        let pulley = CarriedMassAt {
            link: case.pulley.0.to_owned(),
            kind: "pulley".to_owned(),
            name: "massless".to_owned(),
            mass_kg: 0.0,
        };
        assert_eq!(found.carried, vec![pulley], "{label}");
        let mass = parts_mass_kg(&parts, &catalogue);
        assert_eq!(found.actuator_mass_kg, Some(mass), "{label}");
        assert!(expected.carried.is_empty() && expected.actuator_mass_kg.is_none());
        found.solve_seconds = expected.solve_seconds;
        (found.carried, found.actuator_mass_kg) = (Vec::new(), None);
        assert_eq!(found, expected, "{label}");
    }
}
