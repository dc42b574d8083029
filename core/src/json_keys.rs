//! JSON read strictly: a key given twice in one object is an error naming the key and its line,
//! where serde_json would keep the last value silently (`"steps": 10, "steps": 5000` would run
//! 5000 steps); a value of the wrong type is an error naming its field (`motion.steps`) and its
//! line, where serde names neither when it reads from a parsed [`Value`].

use serde::de::{self, DeserializeOwned, DeserializeSeed, Deserializer, IgnoredAny};
use serde::de::{MapAccess, SeqAccess, Visitor};
use serde::Serialize;
use serde_json::Value;
use serde_path_to_error::Segment;
use std::collections::HashSet;
use std::fmt;

/// One step of a path into a JSON value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// The value of this key of an object.
    Key(String),
    /// The element at this index (0-based) of an array.
    Index(usize),
}

/// A value that could not be read as the type asked for: where, and what serde said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathError {
    /// The path from the value read to the field at fault (empty: the value itself).
    pub path: Vec<Step>,
    /// serde's complaint, e.g. `invalid type: string "10", expected usize`.
    pub message: String,
}

impl PathError {
    /// The field's name below `prefix` (which may be empty), as errors spell it:
    /// `motion.steps`, `transmission.bounds[0][1]`.
    pub fn field(&self, prefix: &str) -> String {
        let mut field = prefix.to_owned();
        for step in &self.path {
            match step {
                Step::Key(key) if field.is_empty() => field.push_str(key),
                Step::Key(key) => {
                    field.push('.');
                    field.push_str(key);
                }
                Step::Index(index) => field.push_str(&format!("[{index}]")),
            }
        }
        field
    }
}

/// Reads `value` as a `T`; the error holds the path of the field at fault. An array where `T`
/// has an object is refused: serde's derived structs also read a sequence of their fields in
/// order, so `"motors": [0.6, 250]` would read as a torque and a speed limit. The value read is
/// written back and compared, shape by shape, with `value`.
pub fn read_value<T: DeserializeOwned + Serialize>(value: &Value) -> Result<T, PathError> {
    let read: T = serde_path_to_error::deserialize(value).map_err(|error| {
        // The path stops at a step that is neither a key nor an index (an enum's variant).
        let path = error
            .path()
            .iter()
            .map_while(|segment| match segment {
                Segment::Map { key } => Some(Step::Key(key.clone())),
                Segment::Seq { index } => Some(Step::Index(*index)),
                _ => None,
            })
            .collect();
        PathError {
            path,
            message: error.into_inner().to_string(),
        }
    })?;
    let written = serde_json::to_value(&read).map_err(|error| PathError {
        path: Vec::new(),
        message: error.to_string(),
    })?;
    match array_for_object(value, &written) {
        Some(path) => Err(PathError {
            path,
            message: "invalid type: an array, expected an object (write its fields by name)"
                .to_owned(),
        }),
        None => Ok(read),
    }
}

/// The path of the first array in `given` where `read` (the same value read and written back)
/// has an object; None where there is none.
fn array_for_object(given: &Value, read: &Value) -> Option<Vec<Step>> {
    let within = |step: Step, given: &Value, read: &Value| {
        array_for_object(given, read).map(|mut path| {
            path.insert(0, step);
            path
        })
    };
    match (given, read) {
        (Value::Array(_), Value::Object(_)) => Some(Vec::new()),
        (Value::Object(given), Value::Object(read)) => given
            .iter()
            .find_map(|(key, value)| within(Step::Key(key.clone()), value, read.get(key)?)),
        (Value::Array(given), Value::Array(read)) => (given.iter().zip(read).enumerate())
            .find_map(|(index, (given, read))| within(Step::Index(index), given, read)),
        _ => None,
    }
}

/// The line (1-based) of the JSON `text` where the value at `path` is named: the line of its
/// key, or of the element itself in an array. None where the path is empty (the whole text) or
/// leads nowhere, or the text is malformed before it.
pub fn line_of(text: &str, path: &[Step]) -> Option<usize> {
    if path.is_empty() {
        return None;
    }
    let mut deserializer = serde_json::Deserializer::from_str(text);
    match Find(path).deserialize(&mut deserializer) {
        // Find fails with a data error exactly where it finds the value; serde_json adds the line.
        Err(error) if error.is_data() => Some(error.line()),
        _ => None,
    }
}

/// Checks that no object in the JSON `text` has a key twice; the error names the key, and
/// serde_json adds its line and column. Malformed JSON is left to the parser that reads it.
pub fn check_unique_keys(text: &str) -> Result<(), String> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    match Unique.deserialize(&mut deserializer) {
        Err(error) if error.is_data() => Err(error.to_string()),
        _ => Ok(()),
    }
}

/// A visitor that walks any JSON value and fails on a repeated key.
#[derive(Clone, Copy)]
struct Unique;

impl<'de> DeserializeSeed<'de> for Unique {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Unique {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }

    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }

    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }

    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }

    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }

    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while seq.next_element_seed(self)?.is_some() {}
        Ok(())
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(de::Error::custom(format!(
                    "the key `{key}` is given twice in one object (only one value can count)"
                )));
            }
            map.next_value_seed(self)?;
        }
        Ok(())
    }
}

/// The error by which [`Find`] stops where it finds its value.
fn found<E: de::Error>() -> E {
    E::custom("found")
}

/// A visitor that walks a JSON value down `0` and fails where the path ends.
#[derive(Clone, Copy)]
struct Find<'a>(&'a [Step]);

impl<'de> DeserializeSeed<'de> for Find<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Find<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E: de::Error>(self, _: bool) -> Result<(), E> {
        self.scalar()
    }

    fn visit_i64<E: de::Error>(self, _: i64) -> Result<(), E> {
        self.scalar()
    }

    fn visit_u64<E: de::Error>(self, _: u64) -> Result<(), E> {
        self.scalar()
    }

    fn visit_f64<E: de::Error>(self, _: f64) -> Result<(), E> {
        self.scalar()
    }

    fn visit_str<E: de::Error>(self, _: &str) -> Result<(), E> {
        self.scalar()
    }

    fn visit_unit<E: de::Error>(self) -> Result<(), E> {
        self.scalar()
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let Some((Step::Index(wanted), rest)) = self.0.split_first() else {
            return if self.0.is_empty() {
                Err(found())
            } else {
                Ok(())
            };
        };
        let mut index = 0;
        while index < *wanted {
            if seq.next_element::<IgnoredAny>()?.is_none() {
                return Ok(());
            }
            index += 1;
        }
        seq.next_element_seed(Find(rest)).map(|_| ())
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let Some((Step::Key(wanted), rest)) = self.0.split_first() else {
            return if self.0.is_empty() {
                Err(found())
            } else {
                Ok(())
            };
        };
        while let Some(key) = map.next_key::<String>()? {
            if key == *wanted {
                return match rest.is_empty() {
                    true => Err(found()),
                    false => map.next_value_seed(Find(rest)),
                };
            }
            map.next_value::<IgnoredAny>()?;
        }
        Ok(())
    }
}

impl Find<'_> {
    /// A number, string, boolean or null: found if the path ends here.
    fn scalar<E: de::Error>(self) -> Result<(), E> {
        match self.0.is_empty() {
            true => Err(found()),
            false => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_repeated_key_is_named_with_its_line() {
        assert_eq!(
            check_unique_keys(r#"{"a": [1, {"b": 2}], "c": null}"#),
            Ok(())
        );
        let error =
            check_unique_keys("{\n \"motion\": {\"steps\": 10,\n \"steps\": 5000}\n}").unwrap_err();
        assert!(error.contains("the key `steps` is given twice"), "{error}");
        assert!(error.contains("line 3"), "{error}");
        // The same key in two objects is no repetition; malformed JSON is the parser's to name.
        assert_eq!(check_unique_keys(r#"[{"a": 1}, {"a": 2}]"#), Ok(()));
        assert_eq!(check_unique_keys("{\"a\": "), Ok(()));
    }

    #[test]
    fn a_type_error_names_the_path_and_its_line() {
        type Motion = std::collections::HashMap<String, Vec<[f64; 2]>>;
        let text =
            "{\n \"motion\": {\n  \"bounds\": [[1, 2],\n   [3, \"x\"]],\n  \"steps\": []\n }\n}";
        let value: Value = serde_json::from_str(text).unwrap();
        let error = read_value::<std::collections::HashMap<String, Motion>>(&value).unwrap_err();
        assert_eq!(error.field(""), "motion.bounds[1][1]");
        assert_eq!(error.field("task"), "task.motion.bounds[1][1]");
        assert!(error.message.contains("invalid type: string"), "{error:?}");
        assert_eq!(line_of(text, &error.path), Some(4));
        let key = |k: &str| Step::Key(k.to_owned());
        assert_eq!(line_of(text, &[key("motion"), key("steps")]), Some(5));
        assert_eq!(line_of(text, &[key("motion")]), Some(2));
        assert_eq!(line_of(text, &[key("motion"), key("absent")]), None);
        assert_eq!(
            line_of(text, &[key("motion"), key("bounds"), Step::Index(7)]),
            None
        );
        assert_eq!(line_of(text, &[]), None);
        assert_eq!(line_of("{\"a\": ", &[key("a")]), Some(1));
    }
}
