//! The task hash: a name for the problem a result belongs to, the task as read with its robot,
//! that every result file records (`task_hash`), so that `table` never merges the results of two
//! tasks and shows the paper's numbers only beside the paper's task.

use super::robot::BUILT_IN_URDF;
use super::task::{Ends, Task, TaskError};
use crate::hash::fnv1a;
use serde_json::Value;

/// The task hash of `task` as read (before any command-line override) on the robot whose URDF
/// text hashes to `urdf_hash` (`Robot::urdf_hash`): FNV-1a of the task's fields as canonical JSON
/// (keys sorted, numbers as parsed, no whitespace), with `robot`, a path, replaced by
/// `robot_urdf_fnv1a`, the URDF's hash. A task's file name and folder, its spacing, the order of
/// its keys and the spelling of its numbers (`1` or `1.0`) leave it unchanged; so do its
/// `solver` and `experiment` sections, which say how and which runs are made, not what they
/// solve, `motors.names`, labels of plots, and `motors.parts` and the `catalogue` of each
/// `carried` part, whose numbers the task holds once read (a catalogue's path is where it lies, not what is solved). `motion.ends` counts, but `hold`, what a task
/// without the key means, hashes as that task did before the key existed, so that the results
/// and logs of such a task keep their hash.
pub fn task_hash(task: &Task, urdf_hash: &str) -> String {
    let mut value =
        serde_json::to_value(task).expect("a task serialises: numbers, strings and lists only");
    if let Value::Object(fields) = &mut value {
        fields.remove("robot");
        fields.insert("robot_urdf_fnv1a".to_owned(), urdf_hash.into());
        if let Some(Value::Object(motors)) = fields.get_mut("motors") {
            motors.remove("names");
            motors.remove("parts");
        }
        if let Some(Value::Array(carried)) = fields.get_mut("carried") {
            let parts = carried.iter_mut().filter_map(Value::as_object_mut);
            for part in parts
                .flat_map(|p| p.values_mut())
                .filter_map(Value::as_object_mut)
            {
                part.remove("catalogue");
            }
        }
        if task.motion.ends == Ends::Hold {
            if let Some(Value::Object(motion)) = fields.get_mut("motion") {
                motion.remove("ends");
            }
        }
    }
    fnv1a(value.to_string().as_bytes())
}

/// The task hash of the built-in task on the built-in robot: the paper's task, the only one
/// whose table shows the paper's numbers.
pub fn built_in_task_hash() -> Result<String, TaskError> {
    Task::built_in().map(|task| task_hash(&task, &fnv1a(BUILT_IN_URDF.as_bytes())))
}

#[cfg(test)]
mod tests {
    use super::{built_in_task_hash, task_hash};
    use crate::model::task::{Task, TaskFile};
    use crate::model::Robot;

    /// The repository's task file, with its robot loaded: the task as a run reads it.
    fn hash_of_file(path: &std::path::Path) -> String {
        let task = TaskFile::load(path).unwrap().task;
        let robot = Robot::load(&task).unwrap();
        task_hash(&task, robot.urdf_hash())
    }

    /// The built-in task's hash as results recorded it before `motors.names` existed: the field
    /// leaves every existing task's hash as it was, and naming the motors changes none.
    #[test]
    fn motor_names_leave_the_hash_unchanged() {
        let built_in = built_in_task_hash().unwrap();
        assert_eq!(built_in, "dd1db534c1095e98");
        let mut named = Task::built_in().unwrap();
        named.motors.names = Some((1..=4).map(|i| format!("M{i}")).collect());
        let urdf = crate::hash::fnv1a(crate::model::BUILT_IN_URDF.as_bytes());
        assert_eq!(task_hash(&named, &urdf), built_in);
    }

    #[test]
    fn the_built_in_task_and_its_file_have_one_hash() {
        let built_in = built_in_task_hash().unwrap();
        assert_eq!(built_in.len(), 16);
        assert_eq!(hash_of_file(&crate::testing::task_path()), built_in);
    }

    #[test]
    fn the_hash_names_the_problem_not_the_file() {
        let dir = std::env::temp_dir().join(format!("codesign-identity-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let urdf = crate::testing::task_path().with_file_name("../belt_arm.urdf");
        let text = std::fs::read_to_string(crate::testing::task_path()).unwrap();
        let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
        value["robot"] = urdf.to_str().unwrap().into();
        // Another name, folder, spacing, key order, spelling of numbers and solver section, and
        // an experiment section: the same task.
        let respelled = serde_json::to_string_pretty(&value)
            .unwrap()
            .replace("\"horizon_s\": 0.8", "\"horizon_s\": 8e-1")
            .replace("\"tol\": 1e-8", "\"tol\": 1e-7");
        let same = dir.join("renamed.json");
        std::fs::write(
            &same,
            respelled.replacen('{', "{\"experiment\": {\"budget\": {\"seeds\": 2}},", 1),
        )
        .unwrap();
        let built_in = built_in_task_hash().unwrap();
        assert_eq!(hash_of_file(&same), built_in);
        // Another horizon: another task.
        let other = dir.join("other.json");
        std::fs::write(
            &other,
            respelled.replace("\"horizon_s\": 8e-1", "\"horizon_s\": 0.9"),
        )
        .unwrap();
        assert_ne!(hash_of_file(&other), built_in);
        // The same task on an edited robot: another task.
        let task = Task::built_in().unwrap();
        assert_ne!(task_hash(&task, "0123456789abcdef"), built_in);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
