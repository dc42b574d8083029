//! Numbers keyed by name, in order: the largest violation of each constraint family at a
//! solution ([`Violations`]), and the terms a formulation adds to its cost.

use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The largest violation of each constraint family at the returned point (0 when satisfied),
/// in the order the problem lists its families, each under its name: a family added to a
/// formulation (`Formulation::with_constraint`) appears under its own. Written as a JSON object.
///
/// The built-in names and units: `dynamics` |RNEA(q, v, a) - tau| (N m), `integration` the
/// semi-implicit Euler residuals (rad/s or rad), `boundary` the start and goal states (rad or
/// rad/s), `joint_position` the joints' position limits (rad), `speed_limits` the problem's
/// speed limits in its speed mode (rad/s), `control_limits` its control bounds in its torque
/// mode (N m), `cartesian_box` the soft box (penalised, not enforced; m), and, where the motors
/// have a torque-speed envelope, `motor_envelope` (N m, docs/model.md, section 5); where the
/// task has them, `via_joints` (rad) and `via_tcp` (m), how far the via points' nodes lie beyond
/// their tolerances, `goal_tcp` (m), how far a TCP goal's last node lies beyond its ball, and
/// `upright` (rad), how far the upright link tilts beyond its own.
pub type Violations = Keyed;

/// Numbers keyed by name, in the order they were pushed; written as a JSON object in that order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Keyed(Vec<(String, f64)>);

impl Keyed {
    /// The value of `name`, None where there is none.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0
            .iter()
            .find(|(key, _)| key == name)
            .map(|&(_, value)| value)
    }

    /// Every name with its value, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, f64)> {
        self.0.iter().map(|(name, value)| (name.as_str(), *value))
    }

    /// Appends `value` under `name`.
    pub fn push(&mut self, name: impl Into<String>, value: f64) {
        self.0.push((name.into(), value));
    }

    /// Whether it holds nothing.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl Serialize for Keyed {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, value) in &self.0 {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Keyed {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Keyed, D::Error> {
        deserializer.deserialize_map(InOrder)
    }
}

/// Reads the object's entries in the order written.
struct InOrder;

impl<'de> Visitor<'de> for InOrder {
    type Value = Keyed;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an object of numbers")
    }

    fn visit_map<M: MapAccess<'de>>(self, mut map: M) -> Result<Keyed, M::Error> {
        let mut keyed = Keyed::default();
        while let Some((name, value)) = map.next_entry::<String, f64>()? {
            if keyed.get(&name).is_some() {
                return Err(serde::de::Error::custom(format!("{name} given twice")));
            }
            keyed.push(name, value);
        }
        Ok(keyed)
    }
}

#[cfg(test)]
mod tests {
    use super::Violations;

    #[test]
    fn violations_read_back_in_their_order() {
        let text = r#"{"dynamics":1e-9,"integration":0.0,"height":0.25}"#;
        let violations: Violations = serde_json::from_str(text).unwrap();
        assert_eq!(violations.get("height"), Some(0.25));
        assert_eq!(violations.get("envelope"), None);
        assert_eq!(serde_json::to_string(&violations).unwrap(), text);
        let twice = r#"{"dynamics":1.0,"dynamics":2.0}"#;
        assert!(serde_json::from_str::<Violations>(twice).is_err());
    }
}
