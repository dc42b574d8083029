//! The entries of a task's `motors.parts` as written, one per motor slot (row of G): a part
//! chosen by `name`, a discrete choice among `candidates`, or `same_as` another slot (the same
//! part as that slot carries, e.g. the two motors of a wrist differential).
//!
//! A task whose slots are all chosen by name (or the same as one that is) is one task, read by
//! [`super::motor_parts::resolve`]; a task with candidates is a family of tasks, one per
//! combination of parts ([`super::part_family::PartsFamily`]), which only `codesign parts`
//! reads. This module reads and checks the entries; it reads no catalogue.

use crate::json_keys::read_value;
use crate::text::shown;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::PathBuf;

/// One motor's part: a motor of a catalogue file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartChoice {
    /// The catalogue file, relative to the task file's folder (resolved when the task is read).
    pub catalogue: PathBuf,
    /// The motor's `name` in that catalogue.
    pub name: String,
}

/// One entry of `motors.parts` as written; exactly one of `name`, `candidates` and `same_as`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct Written {
    catalogue: Option<PathBuf>,
    name: Option<String>,
    candidates: Option<Vec<String>>,
    same_as: Option<usize>,
}

/// A motor slot's entry, checked.
#[derive(Clone, Debug, PartialEq)]
pub enum PartSlot {
    /// One part: a motor of a catalogue.
    Named(PartChoice),
    /// A choice among motors of one catalogue, in the order written, none twice.
    Candidates {
        /// The catalogue file, as written.
        catalogue: PathBuf,
        /// The motors' names.
        names: Vec<String>,
    },
    /// The same part as the slot of this index in `motors.parts`, itself named or a choice.
    SameAs(usize),
}

/// The parts of `motors.parts` (its JSON `given`), checked: each entry one of the three kinds,
/// a catalogue with a name or candidates and none with `same_as`, candidates neither empty nor
/// repeated, `same_as` naming another slot that is not itself `same_as`. The error names the
/// field (`motors.parts[1].candidates is empty: ...`).
pub fn read_slots(given: &Value) -> Result<Vec<PartSlot>, String> {
    let written: Vec<Written> =
        read_value(given).map_err(|e| format!("{}: {}", e.field("motors.parts"), e.message))?;
    if written.is_empty() {
        return Err(
            "motors.parts is empty: name one catalogue motor per motor (row of G), \
                    or leave the key out"
                .to_owned(),
        );
    }
    let slots = (written.iter().enumerate())
        .map(|(slot, entry)| read_slot(slot, entry.clone()))
        .collect::<Result<Vec<_>, _>>()?;
    for (slot, entry) in slots.iter().enumerate() {
        let PartSlot::SameAs(other) = *entry else {
            continue;
        };
        let field = format!("motors.parts[{slot}].same_as = {other}");
        match slots.get(other) {
            _ if other == slot => return Err(format!("{field} names its own slot")),
            None => {
                return Err(format!(
                    "{field}: motors.parts has {} entries (0 to {})",
                    slots.len(),
                    slots.len() - 1
                ))
            }
            Some(PartSlot::SameAs(_)) => {
                return Err(format!(
                    "{field} names a slot that is itself `same_as` another: name the slot \
                     that gives `name` or `candidates`"
                ))
            }
            Some(_) => {}
        }
    }
    Ok(slots)
}

/// The slot `slot`'s entry checked.
fn read_slot(slot: usize, entry: Written) -> Result<PartSlot, String> {
    let field = format!("motors.parts[{slot}]");
    match (entry.catalogue, entry.name, entry.candidates, entry.same_as) {
        (Some(catalogue), Some(name), None, None) => {
            Ok(PartSlot::Named(PartChoice { catalogue, name }))
        }
        (Some(catalogue), None, Some(names), None) => {
            if names.is_empty() {
                return Err(format!(
                    "{field}.candidates is empty: list at least one motor of the catalogue"
                ));
            }
            if let Some(twice) = (names.iter().enumerate())
                .find(|(i, name)| names[..*i].contains(name))
                .map(|(_, name)| name)
            {
                return Err(format!("{field}.candidates lists '{}' twice", shown(twice)));
            }
            Ok(PartSlot::Candidates { catalogue, names })
        }
        (None, None, None, Some(other)) => Ok(PartSlot::SameAs(other)),
        (Some(_), _, _, Some(_)) => Err(format!(
            "{field}: give `same_as` alone: the slot takes the catalogue of the slot it names"
        )),
        (_, Some(_), Some(_), _) => Err(format!(
            "{field}: give either `name` (one part) or `candidates` (a choice), not both"
        )),
        (_, _, _, Some(_)) => Err(format!(
            "{field}: give `same_as` alone, without `name` or `candidates`"
        )),
        (None, _, _, None) => Err(format!(
            "{field}.catalogue is missing: name the catalogue file of its motor"
        )),
        (Some(_), None, None, None) => Err(format!(
            "{field}: give `name` (one motor of the catalogue) or `candidates` (a choice among \
             several)"
        )),
    }
}

/// The slot whose entry gives slot `slot`'s part: the one its `same_as` names, else itself.
pub fn source_of(slots: &[PartSlot], slot: usize) -> usize {
    match slots[slot] {
        PartSlot::SameAs(other) => other,
        _ => slot,
    }
}

/// The one part of every slot of `slots`, `same_as` copied from the slot it names; refused
/// where a slot offers candidates: such a task is a family of tasks, which `codesign parts`
/// reads.
pub fn one_task(slots: &[PartSlot]) -> Result<Vec<PartChoice>, String> {
    (0..slots.len())
        .map(|slot| match &slots[source_of(slots, slot)] {
            PartSlot::Named(choice) => Ok(choice.clone()),
            // `same_as` names no `same_as` slot (`read_slots`): a choice is left.
            _ => Err(format!(
                "motors.parts[{}].candidates offers a choice of parts: the task is a family of \
                 tasks, one per combination of parts, which `codesign parts` co-designs \
                 (Python: codesign.parts); give `name` instead to choose one part",
                source_of(slots, slot)
            )),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn refused(parts: Value) -> String {
        read_slots(&parts).unwrap_err()
    }

    #[test]
    fn each_kind_of_entry_is_read() {
        let parts = json!([
            {"catalogue": "c.json", "name": "A"},
            {"catalogue": "c.json", "candidates": ["A", "B"]},
            {"same_as": 1},
        ]);
        let slots = read_slots(&parts).unwrap();
        assert_eq!(slots[2], PartSlot::SameAs(1));
        assert!(matches!(&slots[1], PartSlot::Candidates { names, .. } if names.len() == 2));
        let error = one_task(&slots).unwrap_err();
        assert!(
            error.starts_with("motors.parts[1].candidates offers a choice of parts")
                && error.contains("`codesign parts`"),
            "{error}"
        );
        let one = read_slots(&json!([{"catalogue": "c.json", "name": "A"}, {"same_as": 0}]));
        let choices = one_task(&one.unwrap()).unwrap();
        assert_eq!(choices[1].name, "A");
    }

    #[test]
    fn errors_name_the_entry() {
        let cases = [
            (json!([]), "motors.parts is empty"),
            (
                json!([{"catalogue": "c", "candidates": []}]),
                "motors.parts[0].candidates is empty",
            ),
            (
                json!([{"catalogue": "c", "name": "A", "candidates": ["A"]}]),
                "motors.parts[0]: give either `name` (one part) or `candidates`",
            ),
            (
                json!([{"catalogue": "c", "candidates": ["A", "A"]}]),
                "motors.parts[0].candidates lists 'A' twice",
            ),
            (json!([{"catalogue": "c"}]), "motors.parts[0]: give `name`"),
            (
                json!([{"name": "A"}]),
                "motors.parts[0].catalogue is missing",
            ),
            (
                json!([{"catalogue": "c", "name": "A"}, {"same_as": 1}]),
                "motors.parts[1].same_as = 1 names its own slot",
            ),
            (
                json!([{"catalogue": "c", "name": "A"}, {"same_as": 4}]),
                "motors.parts[1].same_as = 4: motors.parts has 2 entries",
            ),
            (
                json!([{"same_as": 1}, {"same_as": 0}]),
                "motors.parts[0].same_as = 1 names a slot that is itself `same_as`",
            ),
            (
                json!([{"catalogue": "c", "same_as": 0}]),
                "motors.parts[0]: give `same_as` alone",
            ),
            (
                json!([{"catalogue": "c", "motor": "A"}]),
                "motors.parts[0].motor: unknown field `motor`",
            ),
        ];
        for (parts, expected) in cases {
            let error = refused(parts);
            assert!(error.starts_with(expected), "{error}");
        }
    }
}
