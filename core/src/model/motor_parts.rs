//! Motors chosen from catalogues: the task's `motors.parts`, one catalogue motor per motor
//! (row of G), set that motor's figures of the motor model (docs/model.md, section 3).
//!
//! [`FIGURES`] is the one place where a catalogue motor's numbers become the task's motor
//! figures. For each figure and each motor, the value is the part's where the part gives it
//! (a task that also sets the field must give the same value there, else the error names
//! both); else the task's field; else the ideal motor's (no rotor inertia, no friction). A
//! figure with no ideal value (the torque and speed limits; the no-load speed, k_t and R, which
//! are every motor's or none's) that is missing for a motor whose part does not give it is an
//! error naming the field, the motor and its part. The parts are resolved when the task is read
//! ([`resolve`]), so that every layer downstream reads the motor figures as if written by hand.

use super::catalogue::{Catalogue, CatalogueMotor};
use super::motors::PerMotor;
pub use super::part_slots::PartChoice;
use super::part_slots::{one_task, read_slots};
use crate::text::{number, shown};
use serde_json::{Map, Value};
use std::path::{Path, PathBuf};

/// A figure of the motor model that a catalogue motor may set: the task's key in `motors`,
/// the catalogue's number for it, the number in words, and the value of a motor whose part and
/// task give none (None: no ideal value).
pub struct Figure {
    /// The key in the task's `motors` section.
    pub key: &'static str,
    /// The catalogue motor's number for it, if given.
    pub of_part: fn(&CatalogueMotor) -> Option<f64>,
    /// What the catalogue calls it, for messages.
    pub words: &'static str,
    /// The ideal motor's value, used where neither the part nor the task gives one.
    pub ideal: Option<f64>,
    /// Whether every task has it (the limits); else, without an ideal value, it is every
    /// motor's or none's.
    pub required: bool,
}

/// The motor model's figures that a catalogue motor sets, and from which of its numbers: the
/// torque limit is the peak torque (the motions are seconds long, within the intermittent
/// rating), the speed limit the largest permissible speed, the envelope's no-load speed the
/// no-load speed at the nominal voltage; the rotor inertia, viscous friction, k_t and R as
/// given. The continuous torque, the Coulomb friction, the thermal resistances and the mass
/// are not figures of the motor model: `check` reports the mass and the continuous torque.
pub const FIGURES: [Figure; 7] = [
    Figure {
        key: "torque_limit_nm",
        of_part: |m| m.peak_torque_nm,
        words: "peak torque",
        ideal: None,
        required: true,
    },
    Figure {
        key: "speed_limit_rad_s",
        of_part: |m| m.max_speed_rad_s,
        words: "largest speed",
        ideal: None,
        required: true,
    },
    Figure {
        key: "rotor_inertia_kgm2",
        of_part: |m| m.rotor_inertia_kgm2,
        words: "rotor inertia",
        ideal: Some(0.0),
        required: false,
    },
    Figure {
        key: "viscous_friction_nm_s_per_rad",
        of_part: |m| m.viscous_friction_nm_s_per_rad,
        words: "viscous friction",
        ideal: Some(0.0),
        required: false,
    },
    Figure {
        key: "no_load_speed_rad_s",
        of_part: |m| m.no_load_speed_rad_s,
        words: "no-load speed",
        ideal: None,
        required: false,
    },
    Figure {
        key: "torque_constant_nm_per_a",
        of_part: |m| m.torque_constant_nm_per_a,
        words: "torque constant",
        ideal: None,
        required: false,
    },
    Figure {
        key: "resistance_ohm",
        of_part: |m| m.resistance_ohm,
        words: "winding resistance",
        ideal: None,
        required: false,
    },
];

/// A chosen part read: where it was chosen (`motors.parts[i]`), its choice and its motor.
struct Chosen {
    choice: PartChoice,
    motor: CatalogueMotor,
}

impl Chosen {
    /// How messages name it: `motors.parts[0] ('HT02502', catalogue parts.json)`.
    fn named(&self, slot: usize) -> String {
        format!(
            "motors.parts[{slot}] ('{}' of catalogue {})",
            shown(&self.choice.name),
            shown(&self.choice.catalogue.display().to_string())
        )
    }
}

/// Resolves the `motors.parts` of the task JSON `task` in place: each catalogue path joined to
/// `folder` (the task file's; None: only absolute paths), each part read from its catalogue,
/// and the figures it sets written into the `motors` section by the rule of this module.
/// Without `motors.parts` the task is left as it is. The error names the field at fault.
pub fn resolve(task: &mut Value, folder: Option<&Path>) -> Result<(), String> {
    let Some(motors) = task.get_mut("motors").and_then(Value::as_object_mut) else {
        return Ok(());
    };
    let Some(given) = motors.get("parts") else {
        return Ok(());
    };
    let choices = one_task(&read_slots(given)?)?;
    let chosen = read_parts(choices, folder)?;
    for figure in &FIGURES {
        set_figure(motors, figure, &chosen)?;
    }
    let choices: Vec<&PartChoice> = chosen.iter().map(|c| &c.choice).collect();
    let written = serde_json::to_value(choices).map_err(|e| e.to_string())?;
    motors.insert("parts".to_owned(), written);
    Ok(())
}

/// Reads each chosen motor from its catalogue (each catalogue read once), its path joined to
/// `folder`.
fn read_parts(choices: Vec<PartChoice>, folder: Option<&Path>) -> Result<Vec<Chosen>, String> {
    let mut catalogues: Vec<(PathBuf, Catalogue)> = Vec::new();
    let mut chosen = Vec::with_capacity(choices.len());
    for (slot, mut choice) in choices.into_iter().enumerate() {
        let field = format!("motors.parts[{slot}]");
        choice.catalogue = catalogue_path(&field, &choice.catalogue, folder)?;
        let known = catalogues
            .iter()
            .position(|(path, _)| *path == choice.catalogue);
        let index = match known {
            Some(index) => index,
            None => {
                let catalogue = Catalogue::load(&choice.catalogue)
                    .map_err(|e| format!("{field}.catalogue: {e}"))?;
                catalogues.push((choice.catalogue.clone(), catalogue));
                catalogues.len() - 1
            }
        };
        let catalogue = &catalogues[index].1;
        let Some(motor) = catalogue.motor(&choice.name) else {
            let field = format!("{field}.name");
            return Err(no_such_motor(
                &field,
                &choice.name,
                &choice.catalogue,
                catalogue,
            ));
        };
        let motor = motor.clone();
        chosen.push(Chosen { choice, motor });
    }
    Ok(chosen)
}

/// The catalogue `path` that the entry `field` of a task names, joined to `folder` (the task
/// file's; None: only an absolute path is accepted).
pub fn catalogue_path(field: &str, path: &Path, folder: Option<&Path>) -> Result<PathBuf, String> {
    match (path.is_relative(), folder) {
        (false, _) => Ok(path.to_owned()),
        (true, Some(folder)) => Ok(folder.join(path)),
        (true, None) => Err(format!(
            "{field}.catalogue = {} is relative, and this task has no folder: give an absolute \
             path",
            shown(&path.display().to_string())
        )),
    }
}

/// The error of `name`, given as `field`, naming no motor of `catalogue` (read from `path`):
/// it names the catalogue and lists its motors.
pub fn no_such_motor(field: &str, name: &str, path: &Path, catalogue: &Catalogue) -> String {
    let names: Vec<&str> = catalogue.motors.iter().map(|m| m.name.as_str()).collect();
    format!(
        "{field} = '{}' is no motor of catalogue {} (its motors: {})",
        shown(name),
        shown(&path.display().to_string()),
        match names.is_empty() {
            true => "none".to_owned(),
            false => names.join(", "),
        }
    )
}

/// Sets `figure` in the `motors` section for every motor of `chosen` by the rule of this
/// module, as one number where every motor's is the same; leaves it as the task wrote it where
/// no part gives it.
fn set_figure(
    motors: &mut Map<String, Value>,
    figure: &Figure,
    chosen: &[Chosen],
) -> Result<(), String> {
    let key = figure.key;
    // A value of the wrong type is left for the task's reader, which names its field.
    let task: Option<PerMotor> = match motors.get(key) {
        Some(value) => match serde_json::from_value(value.clone()) {
            Ok(read) => Some(read),
            Err(_) => return Ok(()),
        },
        None => None,
    };
    // A figure no part gives stays as the task wrote it (a limit must then be written).
    if !chosen.iter().any(|c| (figure.of_part)(&c.motor).is_some()) {
        return match figure.required && task.is_none() {
            true => Err(missing(figure, chosen, 0)),
            false => Ok(()),
        };
    }
    let mut values = Vec::with_capacity(chosen.len());
    for (slot, part) in chosen.iter().enumerate() {
        let of_part = (figure.of_part)(&part.motor);
        let of_task = task.as_ref().and_then(|t| t.get(slot));
        if let (Some(p), Some(t)) = (of_part, of_task) {
            if p != t {
                return Err(format!(
                    "motors.{key} = {} conflicts with {}, whose {} is {}: leave motors.{key} \
                     out, or give the part's value",
                    task.as_ref().map_or(String::new(), |t| t.to_string()),
                    part.named(slot),
                    figure.words,
                    number(p)
                ));
            }
        }
        values.push(of_part.or(of_task));
    }
    let first = values.iter().position(Option::is_some).unwrap_or(0);
    let mut filled = Vec::with_capacity(values.len());
    for (slot, value) in values.iter().enumerate() {
        match (value, figure.ideal) {
            (Some(value), _) => filled.push(*value),
            (None, Some(ideal)) => filled.push(ideal),
            (None, None) if figure.required => return Err(missing(figure, chosen, slot)),
            (None, None) => {
                let error = missing(figure, chosen, slot);
                return Err(format!(
                    "{error} ({} gives one, and the {} is every motor's or none's)",
                    chosen[first].named(first),
                    figure.words
                ));
            }
        }
    }
    let all_equal = filled.iter().all(|v| *v == filled[0]);
    let per_motor = match all_equal {
        true => PerMotor::All(filled[0]),
        false => PerMotor::Each(filled),
    };
    let written = serde_json::to_value(per_motor).map_err(|e| e.to_string())?;
    motors.insert(key.to_owned(), written);
    Ok(())
}

/// The error of `figure` missing for motor `slot`, whose part does not give it.
fn missing(figure: &Figure, chosen: &[Chosen], slot: usize) -> String {
    format!(
        "motors.{} is missing for motor {}: {} gives no {}; give motors.{} in the task",
        figure.key,
        slot + 1,
        chosen[slot].named(slot),
        figure.words,
        figure.key
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::identity::built_in_task_hash;
    use crate::model::task::{TaskFile, BUILT_IN_TASK};
    use crate::testing;
    use serde_json::json;

    /// The built-in task's JSON with its `motors` section replaced by `motors`.
    fn with_motors(motors: Value) -> String {
        let mut task: Value = serde_json::from_str(BUILT_IN_TASK).unwrap();
        task["motors"] = motors;
        task.to_string()
    }

    /// The task of `text` read as if from `robots/tasks/`.
    fn read(text: &str) -> Result<TaskFile, String> {
        let folder = testing::repository().join("robots/tasks");
        TaskFile::from_text(text, "t", &folder).map_err(|e| e.to_string())
    }

    fn part(name: &str) -> Value {
        json!({"catalogue": "../catalogue/parts.json", "name": name})
    }

    fn ideal(name: &str) -> Value {
        let catalogue = testing::repository().join("tests/data/catalogue/ideal.json");
        json!({"catalogue": catalogue, "name": name})
    }

    /// Parts set their motors' figures; the task's speed limit fills what they do not give, a
    /// figure no part gives stays as written, and the catalogue's path is joined to the task's
    /// folder.
    #[test]
    fn parts_set_their_motors_figures() {
        let small = part("Allied Motion HT02501-A00");
        let large = part("Allied Motion HT02502-A00");
        let parts = json!([large, large, small, small]);
        let friction = [1e-3; 4];
        let text = with_motors(json!({"speed_limit_rad_s": 100, "parts": parts,
                                      "viscous_friction_nm_s_per_rad": friction}));
        let motors = read(&text).unwrap().task.motors;
        let each = |v: [f64; 2]| Some(PerMotor::Each(vec![v[0], v[0], v[1], v[1]]));
        assert_eq!(Some(motors.torque_limit_nm), each([2.33, 1.48]));
        assert_eq!(motors.speed_limit_rad_s, PerMotor::All(100.0));
        assert_eq!(motors.rotor_inertia_kgm2, each([2.5e-5, 1.7e-5]));
        // No part gives a friction: the task's stays as written, a list.
        let written = Some(PerMotor::Each(friction.to_vec()));
        assert_eq!(motors.viscous_friction_nm_s_per_rad, written);
        assert_eq!(motors.no_load_speed_rad_s, each([121.0, 144.0]));
        assert_eq!(motors.torque_constant_nm_per_a, each([0.189, 0.159]));
        assert_eq!(motors.resistance_ohm, each([1.94, 2.57]));
        let parts = motors.parts.unwrap();
        assert!(parts[0]
            .catalogue
            .ends_with("robots/tasks/../catalogue/parts.json"));
        assert!(parts[0].catalogue.is_absolute());
    }

    /// The ideal part's figures are the built-in task's: the task reads equal to it but for
    /// its parts, and hashes as it does; written back, it reads back the same.
    #[test]
    fn the_ideal_part_is_the_built_in_task() {
        let text = with_motors(json!({"parts": vec![ideal("ideal 1.7 N m"); 4]}));
        let file = read(&text).unwrap();
        let mut task = file.task.clone();
        assert_eq!(task.motors.parts.as_ref().map(Vec::len), Some(4));
        let urdf = crate::hash::fnv1a(crate::model::BUILT_IN_URDF.as_bytes());
        assert_eq!(
            crate::model::identity::task_hash(&task, &urdf),
            built_in_task_hash().unwrap()
        );
        task.motors.parts = None;
        assert_eq!(
            task.motors,
            crate::model::task::Task::built_in().unwrap().motors
        );
        let written = serde_json::to_string(&file.task).unwrap();
        assert_eq!(read(&written).unwrap().task, file.task);
    }

    /// A field the task sets against its part's value is refused naming both; the same value
    /// is accepted.
    #[test]
    fn a_conflicting_field_names_the_field_and_the_part() {
        let parts = json!(vec![part("Allied Motion HT02502-A00"); 4]);
        let text = with_motors(
            json!({"speed_limit_rad_s": 100, "rotor_inertia_kgm2": 3.6e-5,
                                      "parts": parts}),
        );
        let error = read(&text).unwrap_err();
        assert!(
            error.contains(
                "motors.rotor_inertia_kgm2 = 3.6e-5 conflicts with motors.parts[0] ('Allied \
                 Motion HT02502-A00' of catalogue "
            ) && error
                .contains("whose rotor inertia is 2.5e-5: leave motors.rotor_inertia_kgm2 out"),
            "{error}"
        );
        let same = with_motors(json!({"speed_limit_rad_s": 100, "torque_limit_nm": 2.33,
                                      "parts": parts}));
        assert!(read(&same).is_ok());
    }

    #[test]
    fn errors_name_the_field_the_motor_and_the_part() {
        let slow = part("Allied Motion HT02502-A00");
        let cases = [
            (
                json!({"parts": vec![part("Allied Motion HT02502-A00"); 4]}),
                "motors.speed_limit_rad_s is missing for motor 1: motors.parts[0] ('Allied \
                 Motion HT02502-A00' of catalogue",
            ),
            (
                json!({"torque_limit_nm": 1, "no_load_speed_rad_s": [150, 150, 140, 150],
                       "parts": vec![ideal("no peak torque"); 4]}),
                "motors.no_load_speed_rad_s = [150, 150, 140, 150] conflicts with motors.parts[2]",
            ),
            (
                json!({"torque_limit_nm": 1, "speed_limit_rad_s": 1,
                       "parts": vec![ideal("no peak torque"); 4]}),
                "motors.speed_limit_rad_s = 1 conflicts",
            ),
            (
                json!({"parts": [ideal("no peak torque"), ideal("ideal 1.7 N m"),
                                 ideal("ideal 1.7 N m"), ideal("ideal 1.7 N m")]}),
                "motors.torque_limit_nm is missing for motor 1",
            ),
            (
                json!({"speed_limit_rad_s": 100, "parts": [slow, slow, slow, ideal("ideal 1.7 N m")]}),
                "motors.no_load_speed_rad_s is missing for motor 4: motors.parts[3] ('ideal 1.7 N \
                 m' of catalogue",
            ),
            (
                json!({"speed_limit_rad_s": 100, "parts": [slow, slow, slow]}),
                "motors.parts has 3 parts but transmission.matrix has 4 rows",
            ),
            (
                json!({"speed_limit_rad_s": 100, "parts": []}),
                "motors.parts is empty",
            ),
            (
                json!({"parts": [{"catalogue": "../catalogue/parts.json", "name": "HT"}]}),
                "motors.parts[0].name = 'HT' is no motor of catalogue",
            ),
            (
                json!({"parts": [{"catalogue": "absent.json", "name": "HT"}]}),
                "motors.parts[0].catalogue: catalogue ",
            ),
            (
                json!({"parts": [{"catalogue": "../catalogue/parts.json", "motor": "HT"}]}),
                "motors.parts[0].motor: unknown field `motor`",
            ),
        ];
        for (motors, expected) in cases {
            let error = read(&with_motors(motors)).unwrap_err();
            assert!(error.starts_with(&format!("task t: {expected}")), "{error}");
        }
        // The task's torque limit fills in the peak torque a part does not give.
        let filled = json!({"torque_limit_nm": 1, "parts": vec![ideal("no peak torque"); 4]});
        let motors = read(&with_motors(filled)).unwrap().task.motors;
        assert_eq!(motors.torque_limit_nm, PerMotor::All(1.0));
        let missing = read(&with_motors(
            json!({"parts": [{"catalogue": "absent.json", "name": "HT"}]}),
        ));
        assert!(missing.unwrap_err().contains("absent.json: cannot read"));
    }
}
