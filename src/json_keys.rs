//! JSON read strictly: a key given twice in one object is an error naming the key and its line,
//! where serde_json would keep the last value silently (`"steps": 10, "steps": 5000` would run
//! 5000 steps).

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

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

#[cfg(test)]
mod tests {
    use super::check_unique_keys;

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
}
