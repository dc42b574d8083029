//! A task whose `motors.parts` offer candidates: a family of tasks, one per combination of
//! parts ([`PartsFamily`]). Each combination ([`Combination`]) names one motor per slot, and
//! its task ([`PartsFamily::task_of`]) is the task file with every slot's `candidates` (and
//! `same_as`) replaced by that motor's `name`, read as that file written by hand would be: the
//! same task, the same task hash.

use super::catalogue::Catalogue;
use super::motor_parts::{catalogue_path, no_such_motor};
use super::part_slots::{read_slots, source_of, PartSlot};
use super::task::{TaskError, TaskFile, TaskSource};
use crate::input::{read_text, MAX_TASK_BYTES};
use crate::text::shown;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The most combinations a family may have: each is a co-design of its own.
pub const MAX_COMBINATIONS: usize = 256;

/// A task file with candidates in `motors.parts`, read and checked: every candidate a motor of
/// its catalogue with a mass, and the task of every combination valid.
#[derive(Clone, Debug)]
pub struct PartsFamily {
    /// How messages and results name the file (`task file t.json`, or a given label).
    source: String,
    /// The path or label the combinations' tasks are named after.
    label: String,
    /// The task file's folder, which relative paths are joined to.
    folder: PathBuf,
    /// The task JSON as written.
    value: Value,
    /// The entries of `motors.parts`.
    slots: Vec<PartSlot>,
    /// Per slot: the names it may take and each one's mass, kg (empty for a `same_as` slot).
    options: Vec<Vec<(String, f64)>>,
}

/// One combination of parts: a motor per slot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Combination {
    /// Each slot's motor, by its name in the catalogue, in G's order.
    pub parts: Vec<String>,
    /// The motors' mass summed, kg (the carried parts aside).
    pub motor_mass_kg: f64,
}

impl PartsFamily {
    /// Reads and checks the task file at `path`.
    pub fn load(path: &Path) -> Result<PartsFamily, TaskError> {
        let source = TaskSource::File(path.to_owned()).to_string();
        let text = read_text(path, MAX_TASK_BYTES).map_err(|e| TaskError {
            source: source.clone(),
            message: e.to_string(),
        })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        let label = path.display().to_string();
        PartsFamily::read(&text, source, label, folder)
    }

    /// Reads and checks the task JSON `text`, named `label`, its relative paths joined to
    /// `folder`.
    pub fn from_text(text: &str, label: &str, folder: &Path) -> Result<PartsFamily, TaskError> {
        let source = format!("task {}", shown(label));
        PartsFamily::read(text, source, label.to_owned(), folder)
    }

    fn read(
        text: &str,
        source: String,
        label: String,
        folder: &Path,
    ) -> Result<PartsFamily, TaskError> {
        let error = |message| TaskError {
            source: source.clone(),
            message,
        };
        let value = crate::json_keys::check_unique_keys(text)
            .and_then(|()| serde_json::from_str::<Value>(text).map_err(|e| e.to_string()))
            .map_err(error)?;
        let Some(given) = value.pointer("/motors/parts") else {
            return Err(error(
                "motors.parts is missing: a search over parts chooses each motor among the \
                 `candidates` of its entry of motors.parts"
                    .to_owned(),
            ));
        };
        let slots = read_slots(given).map_err(error)?;
        let options = read_options(&slots, folder).map_err(error)?;
        let family = PartsFamily {
            source: source.clone(),
            label,
            folder: folder.to_owned(),
            value,
            slots,
            options,
        };
        family.check_combinations().map_err(error)?;
        Ok(family)
    }

    /// Checks the number of combinations, and reads the task of each.
    fn check_combinations(&self) -> Result<(), String> {
        let count = (self.options.iter())
            .filter(|o| !o.is_empty())
            .try_fold(1usize, |n, o| n.checked_mul(o.len()))
            .filter(|&n| n <= MAX_COMBINATIONS);
        if count.is_none() {
            return Err(format!(
                "motors.parts: its candidates make more than {MAX_COMBINATIONS} combinations, \
                 each a co-design of its own: offer fewer"
            ));
        }
        for combination in self.combinations() {
            // The error's source is the combination's task; its message is the family's.
            self.task_of(&combination).map_err(|e| e.message)?;
        }
        Ok(())
    }

    /// How messages name the family's file: `task file t.json`.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The slots that offer candidates, in G's order.
    pub fn choice_slots(&self) -> Vec<usize> {
        (0..self.slots.len())
            .filter(|&slot| matches!(self.slots[slot], PartSlot::Candidates { .. }))
            .collect()
    }

    /// Every combination, by increasing motor mass (combinations of equal mass in the order
    /// of the candidates as written, the first slot's changing slowest).
    pub fn combinations(&self) -> Vec<Combination> {
        let mut found: Vec<Vec<usize>> = vec![Vec::new()];
        for options in self.options.iter().filter(|o| !o.is_empty()) {
            found = (found.iter())
                .flat_map(|picked| {
                    (0..options.len()).map(move |k| [picked.as_slice(), &[k]].concat())
                })
                .collect();
        }
        let mut combinations: Vec<Combination> = found
            .iter()
            .map(|picked| self.combination(picked))
            .collect();
        combinations.sort_by(|a, b| a.motor_mass_kg.total_cmp(&b.motor_mass_kg));
        combinations
    }

    /// The combination of `picked`, one index per slot that is not `same_as`.
    fn combination(&self, picked: &[usize]) -> Combination {
        let own: Vec<usize> = (0..self.slots.len())
            .filter(|&slot| !self.options[slot].is_empty())
            .collect();
        let pick_of = |slot: usize| {
            let source = source_of(&self.slots, slot);
            let at = own.iter().position(|&s| s == source).unwrap_or(0);
            &self.options[source][picked[at]]
        };
        let chosen: Vec<&(String, f64)> = (0..self.slots.len()).map(pick_of).collect();
        Combination {
            parts: chosen.iter().map(|(name, _)| name.clone()).collect(),
            motor_mass_kg: chosen.iter().map(|(_, mass)| mass).sum(),
        }
    }

    /// The task JSON of `combination`: the file's, each slot a `name` in the catalogue its
    /// entry (or the entry its `same_as` names) gives, as written.
    pub fn text_of(&self, combination: &Combination) -> String {
        let mut value = self.value.clone();
        let parts: Vec<Value> = (0..self.slots.len())
            .map(|slot| {
                let catalogue = match &self.slots[source_of(&self.slots, slot)] {
                    PartSlot::Named(choice) => &choice.catalogue,
                    PartSlot::Candidates { catalogue, .. } => catalogue,
                    // `same_as` names no `same_as` slot (`read_slots`).
                    PartSlot::SameAs(_) => Path::new(""),
                };
                json!({"catalogue": catalogue, "name": combination.parts[slot]})
            })
            .collect();
        if let Some(slot) = value.pointer_mut("/motors/parts") {
            *slot = Value::Array(parts);
        }
        value.to_string()
    }

    /// The task of `combination`, read as the file with its parts named would be.
    pub fn task_of(&self, combination: &Combination) -> Result<TaskFile, TaskError> {
        TaskFile::from_text(
            &self.text_of(combination),
            &self.label_of(combination),
            &self.folder,
        )
    }

    /// How results name the task of `combination`: the file, then its parts
    /// (`t.json with motors.parts A, A, B, B`).
    pub fn label_of(&self, combination: &Combination) -> String {
        format!(
            "{} with motors.parts {}",
            self.label,
            combination.parts.join(", ")
        )
    }
}

/// Per slot of `slots`: the motors it may take with their masses, read from the catalogues
/// (joined to `folder`, each read once); none for a `same_as` slot. A motor the catalogue does
/// not list, or whose mass it does not give, is an error naming the entry.
fn read_options(slots: &[PartSlot], folder: &Path) -> Result<Vec<Vec<(String, f64)>>, String> {
    let mut catalogues: Vec<(PathBuf, Catalogue)> = Vec::new();
    let mut options = Vec::with_capacity(slots.len());
    for (slot, entry) in slots.iter().enumerate() {
        let field = format!("motors.parts[{slot}]");
        let (written, names, key) = match entry {
            PartSlot::Named(choice) => (&choice.catalogue, vec![choice.name.clone()], "name"),
            PartSlot::Candidates { catalogue, names } => (catalogue, names.clone(), "candidates"),
            PartSlot::SameAs(_) => {
                options.push(Vec::new());
                continue;
            }
        };
        let path = catalogue_path(&field, written, Some(folder))?;
        let index = match catalogues.iter().position(|(known, _)| *known == path) {
            Some(index) => index,
            None => {
                let catalogue =
                    Catalogue::load(&path).map_err(|e| format!("{field}.catalogue: {e}"))?;
                catalogues.push((path.clone(), catalogue));
                catalogues.len() - 1
            }
        };
        let catalogue = &catalogues[index].1;
        let mut masses = Vec::with_capacity(names.len());
        for (k, name) in names.into_iter().enumerate() {
            let at = match key {
                "name" => format!("{field}.name"),
                _ => format!("{field}.candidates[{k}]"),
            };
            let Some(motor) = catalogue.motor(&name) else {
                return Err(no_such_motor(&at, &name, &path, catalogue));
            };
            let Some(mass) = motor.mass_kg else {
                return Err(format!(
                    "{at} = '{}' of catalogue {} gives no mass_kg: a search over parts weighs \
                     every part",
                    shown(&name),
                    shown(&path.display().to_string())
                ));
            };
            masses.push((name, mass));
        }
        options.push(masses);
    }
    Ok(options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::identity::task_hash;
    use crate::testing;

    const SMALL: &str = "Allied Motion HT02501-A00";
    const LARGE: &str = "Allied Motion HT02502-A00";
    const OTHER: &str = "Allied Motion HT02003-A00";

    /// The shipped arm with parts (robots/tasks/pick_place_parts.json), its `motors.parts`
    /// replaced by `parts`, as text.
    fn with_parts(parts: Value) -> String {
        let path = testing::repository().join("robots/tasks/pick_place_parts.json");
        let mut task: Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        task["motors"]["parts"] = parts;
        task.to_string()
    }

    fn family(parts: Value) -> Result<PartsFamily, TaskError> {
        let folder = testing::repository().join("robots/tasks");
        PartsFamily::from_text(&with_parts(parts), "family.json", &folder)
    }

    fn part(name: &str) -> Value {
        json!({"catalogue": "../catalogue/parts.json", "name": name})
    }

    fn choice(names: &[&str]) -> Value {
        json!({"catalogue": "../catalogue/parts.json", "candidates": names})
    }

    /// Combinations come by increasing motor mass, `same_as` takes its slot's part, and each
    /// combination's task is the task written by hand with those names: equal, same hash.
    #[test]
    fn each_combination_is_the_task_written_by_hand() {
        let parts = json!([choice(&[LARGE, SMALL]), choice(&[SMALL, OTHER]), part(SMALL),
                           {"same_as": 2}]);
        let family = family(parts).unwrap();
        assert_eq!(family.choice_slots(), [0, 1]);
        let combinations = family.combinations();
        let masses: Vec<f64> = combinations.iter().map(|c| c.motor_mass_kg).collect();
        assert_eq!(combinations.len(), 4);
        assert!(masses.windows(2).all(|w| w[0] <= w[1]), "{masses:?}");
        assert_eq!(combinations[0].parts, [SMALL, SMALL, SMALL, SMALL]);
        assert!((masses[0] - 4.0 * 0.38).abs() < 1e-12);
        let last = &combinations[3];
        assert_eq!(last.parts, [LARGE, OTHER, SMALL, SMALL]);
        let by_hand = with_parts(json!([part(LARGE), part(OTHER), part(SMALL), part(SMALL)]));
        let folder = testing::repository().join("robots/tasks");
        let written = TaskFile::from_text(&by_hand, "by hand", &folder).unwrap();
        let derived = family.task_of(last).unwrap();
        assert_eq!(derived.task, written.task);
        let urdf = "0123";
        assert_eq!(
            task_hash(&derived.task, urdf),
            task_hash(&written.task, urdf)
        );
        assert!(family
            .label_of(last)
            .starts_with("family.json with motors.parts Allied"));
    }

    /// A task with candidates is refused by the reader of one task, naming the entry and the
    /// command that reads it; the family's errors name the entry, the catalogue and its motors.
    #[test]
    fn errors_name_the_entry_and_the_catalogue() {
        let folder = testing::repository().join("robots/tasks");
        let text = with_parts(json!([
            part(SMALL),
            choice(&[SMALL, LARGE]),
            part(SMALL),
            part(SMALL)
        ]));
        let error = TaskFile::from_text(&text, "t", &folder)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("task t: motors.parts[1].candidates offers a choice of parts")
                && error.contains("`codesign parts`"),
            "{error}"
        );
        let unknown = family(json!([
            part(SMALL),
            choice(&[SMALL, "HT9"]),
            part(SMALL),
            part(SMALL)
        ]));
        let error = unknown.unwrap_err().to_string();
        assert!(
            error.starts_with(
                "task family.json: motors.parts[1].candidates[1] = 'HT9' is no motor of catalogue "
            ) && error.contains("(its motors: Allied Motion HT02501-A00, "),
            "{error}"
        );
        let both = family(
            json!([{"catalogue": "../catalogue/parts.json", "name": SMALL,
                                  "candidates": [SMALL]}, part(SMALL), part(SMALL), part(SMALL)]),
        );
        assert!(both.unwrap_err().message.contains("not both"));
        let empty = family(json!([choice(&[]), part(SMALL), part(SMALL), part(SMALL)]));
        assert!(empty
            .unwrap_err()
            .message
            .starts_with("motors.parts[0].candidates is empty"));
        // Every combination's task is checked when the family is read.
        let short = family(json!([choice(&[SMALL, LARGE]), part(SMALL), part(SMALL)]));
        assert!(short
            .unwrap_err()
            .message
            .contains("has 3 parts but transmission.matrix has 4 rows"));
    }
}
