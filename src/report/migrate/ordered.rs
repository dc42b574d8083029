//! JSON whose objects keep their keys in the order written. serde_json's `Value` sorts them,
//! and some documents' objects are read in their order (`solve::Keyed`: the violations and the
//! cost's terms), so an upgraded document is put back in its file's order before it is read as
//! its type.

use serde::de::{MapAccess, SeqAccess, Visitor};
use serde::ser::{SerializeMap, SerializeSeq};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;
use std::fmt;

/// A JSON value whose objects keep their order.
#[derive(Clone, Debug, PartialEq)]
pub enum Ordered {
    /// A number, string, bool or null.
    Leaf(Value),
    /// An array.
    Array(Vec<Ordered>),
    /// An object, its entries in order.
    Object(Vec<(String, Ordered)>),
}

impl Ordered {
    /// `value` with its objects' keys in the order of the same objects in `like` (the document
    /// as read); keys `like` lacks come after, in `value`'s order.
    pub fn like(value: Value, like: Option<&Ordered>) -> Ordered {
        match value {
            Value::Array(items) => Ordered::Array(
                (items.into_iter().enumerate())
                    .map(|(i, item)| match like {
                        Some(Ordered::Array(old)) => Ordered::like(item, old.get(i)),
                        _ => Ordered::like(item, None),
                    })
                    .collect(),
            ),
            Value::Object(map) => {
                let old: &[(String, Ordered)] = match like {
                    Some(Ordered::Object(entries)) => entries,
                    _ => &[],
                };
                let rank = |key: &str| old.iter().position(|(k, _)| k == key);
                let mut entries: Vec<(String, Value)> = map.into_iter().collect();
                entries.sort_by_key(|(key, _)| rank(key).unwrap_or(usize::MAX));
                Ordered::Object(
                    (entries.into_iter())
                        .map(|(key, item)| {
                            let before = rank(&key).map(|i| &old[i].1);
                            (key, Ordered::like(item, before))
                        })
                        .collect(),
                )
            }
            leaf => Ordered::Leaf(leaf),
        }
    }
}

impl Serialize for Ordered {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Ordered::Leaf(value) => value.serialize(serializer),
            Ordered::Array(items) => {
                let mut seq = serializer.serialize_seq(Some(items.len()))?;
                for item in items {
                    seq.serialize_element(item)?;
                }
                seq.end()
            }
            Ordered::Object(entries) => {
                let mut map = serializer.serialize_map(Some(entries.len()))?;
                for (key, item) in entries {
                    map.serialize_entry(key, item)?;
                }
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Ordered {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Ordered, D::Error> {
        deserializer.deserialize_any(InOrder)
    }
}

/// Reads any JSON, objects in order.
struct InOrder;

impl<'de> Visitor<'de> for InOrder {
    type Value = Ordered;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("JSON")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::Bool(v)))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::from(v)))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::from(v)))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::from(v)))
    }

    fn visit_str<E>(self, v: &str) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::from(v)))
    }

    fn visit_unit<E>(self) -> Result<Ordered, E> {
        Ok(Ordered::Leaf(Value::Null))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Ordered, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(Ordered::Array(items))
    }

    fn visit_map<M: MapAccess<'de>>(self, mut map: M) -> Result<Ordered, M::Error> {
        let mut entries = Vec::new();
        while let Some(entry) = map.next_entry()? {
            entries.push(entry);
        }
        Ok(Ordered::Object(entries))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys come back in the order read, new ones after; arrays keep theirs.
    #[test]
    fn objects_keep_the_order_read() {
        let read: Ordered = serde_json::from_str(r#"{"b": 1, "a": [{"z": 0, "y": 1}]}"#).unwrap();
        let value = serde_json::json!({"a": [{"y": 1, "z": 0, "x": 2}], "b": 1, "c": null});
        let text = serde_json::to_string(&Ordered::like(value, Some(&read))).unwrap();
        assert_eq!(text, r#"{"b":1,"a":[{"z":0,"y":1,"x":2}],"c":null}"#);
    }
}
