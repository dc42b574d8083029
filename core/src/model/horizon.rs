//! [`Horizon`]: the duration T of a motion, fixed or free within bounds. A task file writes
//! `motion.horizon_s` as a number of seconds or as `{"free": [T_min, T_max]}`; a free T is a
//! variable of the trajectory problem (docs/model.md, section 6).

use super::ranges::{check_horizon, FieldError};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;

/// The duration of a motion, s.
///
/// ```
/// use codesign_core::model::task::Horizon;
/// let fixed: Horizon = serde_json::from_str("0.8").unwrap();
/// assert_eq!(fixed, Horizon::Fixed(0.8));
/// let free: Horizon = serde_json::from_str(r#"{"free": [0.3, 1.2]}"#).unwrap();
/// assert_eq!(free, Horizon::Free { min_s: 0.3, max_s: 1.2 });
/// assert_eq!(free.initial_s(), 1.2);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Horizon {
    /// A fixed duration T, s.
    Fixed(f64),
    /// A free duration T in [min_s, max_s], s: a variable of the trajectory problem.
    Free {
        /// T_min, s.
        min_s: f64,
        /// T_max, s.
        max_s: f64,
    },
}

impl Horizon {
    /// The fixed duration, s; None for a free one.
    pub fn fixed_s(self) -> Option<f64> {
        match self {
            Horizon::Fixed(seconds) => Some(seconds),
            Horizon::Free { .. } => None,
        }
    }

    /// The duration the standard initial guess takes, s: the fixed T, or a free one's T_max
    /// (the slowest motion allowed, the one most likely within the limits).
    pub fn initial_s(self) -> f64 {
        match self {
            Horizon::Fixed(seconds) => seconds,
            Horizon::Free { max_s, .. } => max_s,
        }
    }

    /// Whether T is a variable.
    pub fn is_free(self) -> bool {
        matches!(self, Horizon::Free { .. })
    }

    /// Checks each duration against the range a task accepts, and T_min < T_max; `field` names
    /// the field in errors (`motion.horizon_s`).
    pub(super) fn validate(self, field: &str) -> Result<(), FieldError> {
        let check = |name: String, seconds: f64| {
            check_horizon(seconds).map_err(|why| FieldError::out_of_range(&name, seconds, why))
        };
        match self {
            Horizon::Fixed(seconds) => check(field.to_owned(), seconds),
            Horizon::Free { min_s, max_s } => {
                check(format!("{field}.free[0]"), min_s)?;
                check(format!("{field}.free[1]"), max_s)?;
                if min_s < max_s {
                    Ok(())
                } else {
                    Err(FieldError::new(
                        field,
                        format!(
                            ".free = [{min_s}, {max_s}] must give T_min < T_max (a fixed duration is \
                             written as a number)"
                        ),
                    ))
                }
            }
        }
    }
}

/// A fixed duration as its number of seconds, a free one as `free in [T_min, T_max]`.
impl std::fmt::Display for Horizon {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Horizon::Fixed(seconds) => write!(f, "{seconds}"),
            Horizon::Free { min_s, max_s } => write!(f, "free in [{min_s}, {max_s}]"),
        }
    }
}

impl Serialize for Horizon {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match *self {
            Horizon::Fixed(seconds) => serializer.serialize_f64(seconds),
            Horizon::Free { min_s, max_s } => {
                use serde::ser::SerializeMap;
                let mut map = serializer.serialize_map(Some(1))?;
                map.serialize_entry("free", &[min_s, max_s])?;
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Horizon {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let refuse = || {
            serde::de::Error::custom(
                "a duration in s (0.8) or a free duration {\"free\": [T_min, T_max]} in s",
            )
        };
        match Value::deserialize(deserializer)? {
            Value::Number(number) => number.as_f64().map(Horizon::Fixed).ok_or_else(refuse),
            Value::Object(fields) if fields.len() == 1 => {
                let bounds = fields
                    .get("free")
                    .and_then(Value::as_array)
                    .ok_or_else(refuse)?;
                match bounds.iter().map(Value::as_f64).collect::<Option<Vec<_>>>() {
                    Some(pair) if pair.len() == 2 => Ok(Horizon::Free {
                        min_s: pair[0],
                        max_s: pair[1],
                    }),
                    _ => Err(refuse()),
                }
            }
            _ => Err(refuse()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_horizon_reads_and_writes_as_the_task_file_spells_it() {
        for text in ["0.8", r#"{"free":[0.3,1.2]}"#] {
            let horizon: Horizon = serde_json::from_str(text).unwrap();
            assert_eq!(serde_json::to_string(&horizon).unwrap(), text);
        }
        for bad in [
            r#""0.8""#,
            r#"{"free": [0.3]}"#,
            r#"{"free": [0.3, "1"]}"#,
            r#"{"free": [0.3, 1.2], "x": 1}"#,
            r#"{"fixed": 0.8}"#,
            "[0.3, 1.2]",
        ] {
            let error = serde_json::from_str::<Horizon>(bad).unwrap_err();
            assert!(
                error.to_string().contains("free duration"),
                "{bad}: {error}"
            );
        }
    }

    #[test]
    fn a_free_horizon_needs_ordered_durations_in_range() {
        let free = |min_s, max_s| Horizon::Free { min_s, max_s }.validate("motion.horizon_s");
        assert!(free(0.3, 1.2).is_ok());
        assert!(free(1.2, 0.3)
            .unwrap_err()
            .to_string()
            .contains("T_min < T_max"));
        assert!(free(0.3, 0.3).is_err());
        let low = free(0.001, 1.0).unwrap_err().to_string();
        assert!(low.contains("motion.horizon_s.free[0]"), "{low}");
        assert!(Horizon::Fixed(1e9).validate("motion.horizon_s").is_err());
    }
}
