//! Motors chosen from a catalogue (`motors.parts`) through whole solves: a part with the
//! numbers of the paper's ideal motor (`tests/data/catalogue/ideal.json`) reproduces the
//! original design's solves of `robots/tasks/pick_place.json` bit for bit.

use super::{solve_design, SolveSettings};
use crate::model::task::{Task, TaskFile};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;

/// The repository's task with every motor the ideal catalogue part, and its solve settings.
fn ideal_parts_task() -> (Task, SolveSettings) {
    let path = testing::task_path();
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let catalogue = testing::repository().join("tests/data/catalogue/ideal.json");
    let part = serde_json::json!({"catalogue": catalogue, "name": "ideal 1.7 N m"});
    value["motors"] = serde_json::json!({"parts": [part, part, part, part]});
    let folder = path.parent().unwrap();
    let file = TaskFile::from_text(&value.to_string(), "ideal parts", folder).unwrap();
    let settings = SolveSettings::from_section(file.solver.as_ref()).unwrap();
    (file.task, settings)
}

/// J, the iterations, the trajectory and every other figure of the result are those of the
/// task's own motors, at 0 and 1 kg in both spaces (the times aside).
#[test]
fn the_ideal_part_reproduces_the_original_design_bit_for_bit() {
    let (parts, settings) = ideal_parts_task();
    assert!(parts.motors.parts.is_some());
    let original = testing::task();
    let solve = |task: &Task, payload: f64, space: Space| {
        let mut task = task.clone();
        task.payload.mass_kg = payload;
        let robot = Robot::load(&task).unwrap();
        let formulation = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
        solve_design(&formulation, &task.transmission.original, &settings).unwrap()
    };
    for space in [Space::Joint, Space::Actuation] {
        for payload in [0.0, 1.0] {
            let expected = solve(&original, payload, space);
            let mut found = solve(&parts, payload, space);
            found.solve_seconds = expected.solve_seconds;
            assert_eq!(
                found.cost.to_bits(),
                expected.cost.to_bits(),
                "{space} {payload} kg"
            );
            assert_eq!(
                found.iterations, expected.iterations,
                "{space} {payload} kg"
            );
            assert_eq!(found, expected, "{space} {payload} kg");
        }
    }
}
