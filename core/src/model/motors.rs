//! The task's `motors` section: quantities given for all motors at once or one per motor.
//!
//! Motor i drives row i of the transmission matrix G (`transmission.matrix`), so a per-motor
//! list has one value per row of G, in that order.

pub use super::motor_parts::PartChoice;
use super::ranges::{Bounds, FieldError};
use crate::text::{number, numbers};
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A quantity of the motors: one number for every motor, or one per motor (row of G).
///
/// Written in a task file as a number (`1.7`) or as an array with one number per motor
/// (`[1.7, 1.7, 0.9, 0.9]`), and written back the same way.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PerMotor {
    /// The same value for every motor.
    All(f64),
    /// Motor i's value at index i (0-based, the rows of G).
    Each(Vec<f64>),
}

impl PerMotor {
    /// Motor `motor`'s value (0-based); None past the end of a per-motor list.
    pub fn get(&self, motor: usize) -> Option<f64> {
        match self {
            PerMotor::All(value) => Some(*value),
            PerMotor::Each(values) => values.get(motor).copied(),
        }
    }

    /// The values of `motors` motors, motor i's at index i. A per-motor list is returned as
    /// written: [`PerMotor::check`] holds it to `motors` values.
    pub fn values(&self, motors: usize) -> Vec<f64> {
        match self {
            PerMotor::All(value) => vec![*value; motors],
            PerMotor::Each(values) => values.clone(),
        }
    }

    /// The mean over the motors, computed as v_0 + sum_i (v_i - v_0) / n so that equal values
    /// give exactly that value (and a single number itself); NaN for an empty list, which
    /// [`PerMotor::check`] refuses.
    pub fn mean(&self) -> f64 {
        match self {
            PerMotor::All(value) => *value,
            PerMotor::Each(values) => {
                let Some(&first) = values.first() else {
                    return f64::NAN;
                };
                let n = values.len() as f64;
                first + values.iter().map(|v| (v - first) / n).sum::<f64>()
            }
        }
    }

    /// Checks the quantity `field` (e.g. `motors.torque_limit_nm`) for `motors` motors: a list
    /// has one value per motor, and every value is within `bounds`. The error names the value
    /// at fault, e.g. `motors.torque_limit_nm[2] = -1 must be > 0 and <= ...`.
    pub fn check(&self, field: &str, motors: usize, bounds: &Bounds) -> Result<(), FieldError> {
        match self {
            PerMotor::All(value) => bounds.check(field, *value),
            PerMotor::Each(values) if values.len() != motors => Err(FieldError::new(
                field,
                format!(
                    " has {} values but transmission.matrix has {motors} rows: give one number \
                     for every motor or one per motor (row of G)",
                    values.len()
                ),
            )),
            PerMotor::Each(values) => values
                .iter()
                .enumerate()
                .try_for_each(|(i, &value)| bounds.check(&format!("{field}[{i}]"), value)),
        }
    }
}

/// The limits of the motors' quantities: physically generous, and small enough that no product
/// of the task's numbers overflows the dynamics; none may be subnormal.
const TORQUE_LIMIT: Bounds = Bounds {
    zero: false,
    least: f64::MIN_POSITIVE,
    most: 1e6,
    unit: "N m",
    why: "far beyond any robot joint's torque; beyond that, or below 2.2e-308, products of the \
          task's numbers overflow",
};
const SPEED_LIMIT: Bounds = Bounds {
    zero: false,
    least: f64::MIN_POSITIVE,
    most: 1e6,
    unit: "rad/s",
    why: "a hundred times the fastest motor's; beyond that, or below 2.2e-308, products of the \
          task's numbers overflow",
};
const ROTOR_INERTIA: Bounds = Bounds {
    zero: true,
    least: f64::MIN_POSITIVE,
    most: 1.0,
    unit: "kg m^2",
    why: "ten times the rotor of a large industrial motor; reflected through ratios up to 1e6 \
          a larger one overflows the dynamics, and positive ones below 2.2e-308 are subnormal",
};
const FRICTION: Bounds = Bounds {
    zero: true,
    least: f64::MIN_POSITIVE,
    most: 1e3,
    unit: "N m s/rad",
    why: "far beyond any motor's; reflected through ratios up to 1e6 a larger one overflows the \
          dynamics, and positive ones below 2.2e-308 are subnormal",
};
const NO_LOAD_SPEED: Bounds = Bounds {
    zero: false,
    least: 1e-3,
    most: 1e6,
    unit: "rad/s",
    why: "from a turn in under two hours to a hundred times the fastest motor's; the envelope's \
          slope, the torque limit over it, overflows below",
};

const TORQUE_CONSTANT: Bounds = Bounds {
    zero: false,
    least: 1e-6,
    most: 1e3,
    unit: "N m/A",
    why: "from a micro-motor's 1e-6 to far beyond a large torque motor's 100",
};
const RESISTANCE: Bounds = Bounds {
    zero: true,
    least: f64::MIN_POSITIVE,
    most: 1e6,
    unit: "ohm",
    why: "from a superconducting winding's 0 to far beyond any motor winding's kilo-ohms; \
          positive ones below 2.2e-308 are subnormal",
};
const EFFICIENCY: Bounds = Bounds {
    zero: false,
    least: 1e-2,
    most: 1.0,
    unit: "",
    why: "a share of the power the transmission passes on, 1 for a lossless one; below 0.01 \
          the loss would be a hundred times the torque the links take",
};

impl fmt::Display for PerMotor {
    /// As written in a task file: `1.7`, or `[1.7, 2, 0.9, 0.9]`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PerMotor::All(value) => write!(f, "{}", number(*value)),
            PerMotor::Each(values) => write!(f, "[{}]", numbers(values)),
        }
    }
}

impl<'de> Deserialize<'de> for PerMotor {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<PerMotor, D::Error> {
        deserializer.deserialize_any(PerMotorVisitor)
    }
}

/// Reads a number or an array of numbers, with an error that says which it expects.
struct PerMotorVisitor;

impl<'de> Visitor<'de> for PerMotorVisitor {
    type Value = PerMotor;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a number (every motor) or an array with one number per motor")
    }

    fn visit_f64<E: de::Error>(self, value: f64) -> Result<PerMotor, E> {
        Ok(PerMotor::All(value))
    }

    fn visit_i64<E: de::Error>(self, value: i64) -> Result<PerMotor, E> {
        Ok(PerMotor::All(value as f64))
    }

    fn visit_u64<E: de::Error>(self, value: u64) -> Result<PerMotor, E> {
        Ok(PerMotor::All(value as f64))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PerMotor, A::Error> {
        let mut values = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(64));
        while let Some(value) = seq.next_element::<f64>()? {
            values.push(value);
        }
        Ok(PerMotor::Each(values))
    }
}

/// The limits of the motors and, optionally, their own dynamics (docs/model.md, section 3),
/// each for every motor at once or one per motor. Without the optional keys the motors are
/// ideal torque sources, as in the paper.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motors {
    /// |tau_u,i| limit of motor i, N m.
    pub torque_limit_nm: PerMotor,
    /// |qd_u,i| limit of motor i, rad/s.
    pub speed_limit_rad_s: PerMotor,
    /// Rotor and input-side inertia J_m of motor i, kg m^2, on the motor's side of G.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotor_inertia_kgm2: Option<PerMotor>,
    /// Viscous friction b_m of motor i, N m s/rad, on the motor speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_friction_nm_s_per_rad: Option<PerMotor>,
    /// No-load speed omega_0 of motor i, rad/s: the speed at which its linear torque-speed
    /// envelope |tau_u| <= tau_max (1 - |qd_u|/omega_0) leaves it no torque. Absent: no
    /// envelope, only the torque and speed limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_load_speed_rad_s: Option<PerMotor>,
    /// Torque constant k_t of motor i, N m/A: its current is tau_u / k_t. Given with
    /// `resistance_ohm`, results report the copper losses and the electrical energy.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_constant_nm_per_a: Option<PerMotor>,
    /// Winding resistance R of motor i (terminal to terminal), ohm: its copper losses are
    /// R (tau_u / k_t)^2. Given with `torque_constant_nm_per_a`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resistance_ohm: Option<PerMotor>,
    /// Efficiency eta of motor i's transmission, in (0, 1]: a Coulomb-like loss proportional to
    /// the torque it transmits, so that a motor driving its load gives 1/eta times the torque
    /// (docs/model.md, section 3). Absent: lossless transmissions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub efficiency: Option<PerMotor>,
    /// The motors' names in plots, motor i's at index i; absent: `motor 1` to `motor m`. Labels
    /// only: no part of the problem or of the task hash.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub names: Option<Vec<String>>,
    /// The catalogue motor of each motor, motor i's at index i: when the task is read, each
    /// sets its motor's figures above ([`super::motor_parts`]); absent: the figures as written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parts: Option<Vec<PartChoice>>,
}

impl Motors {
    /// Ideal motors (no rotor inertia, friction or torque-speed envelope) with these limits, N m
    /// and rad/s.
    pub fn ideal(torque_limit_nm: PerMotor, speed_limit_rad_s: PerMotor) -> Motors {
        Motors {
            torque_limit_nm,
            speed_limit_rad_s,
            rotor_inertia_kgm2: None,
            viscous_friction_nm_s_per_rad: None,
            no_load_speed_rad_s: None,
            torque_constant_nm_per_a: None,
            resistance_ohm: None,
            efficiency: None,
            names: None,
            parts: None,
        }
    }

    /// Each motor's torque constant (N m/A) and winding resistance (ohm), for `motors` motors,
    /// when the task gives both (checked by [`Motors::validate`]).
    pub fn electrical(&self, motors: usize) -> Option<Vec<(f64, f64)>> {
        let (k_t, r) = (
            self.torque_constant_nm_per_a.as_ref()?,
            self.resistance_ohm.as_ref()?,
        );
        Some(
            (k_t.values(motors).into_iter())
                .zip(r.values(motors))
                .collect(),
        )
    }

    /// Checks every quantity for `motors` motors (the rows of G): one value per motor where a
    /// list is given, each within its bounds: the limits and the no-load speed > 0, the rotor
    /// inertia and the friction >= 0, the efficiency in (0, 1], none above its largest value or
    /// subnormal.
    pub fn validate(&self, motors: usize) -> Result<(), FieldError> {
        self.torque_limit_nm
            .check("motors.torque_limit_nm", motors, &TORQUE_LIMIT)?;
        self.speed_limit_rad_s
            .check("motors.speed_limit_rad_s", motors, &SPEED_LIMIT)?;
        let optional = [
            (
                &self.rotor_inertia_kgm2,
                "motors.rotor_inertia_kgm2",
                ROTOR_INERTIA,
            ),
            (
                &self.viscous_friction_nm_s_per_rad,
                "motors.viscous_friction_nm_s_per_rad",
                FRICTION,
            ),
            (
                &self.no_load_speed_rad_s,
                "motors.no_load_speed_rad_s",
                NO_LOAD_SPEED,
            ),
            (
                &self.torque_constant_nm_per_a,
                "motors.torque_constant_nm_per_a",
                TORQUE_CONSTANT,
            ),
            (&self.resistance_ohm, "motors.resistance_ohm", RESISTANCE),
            (&self.efficiency, "motors.efficiency", EFFICIENCY),
        ];
        optional
            .into_iter()
            .try_for_each(|(quantity, field, bounds)| match quantity {
                Some(quantity) => quantity.check(field, motors, &bounds),
                None => Ok(()),
            })?;
        let electrical = match (&self.torque_constant_nm_per_a, &self.resistance_ohm) {
            (Some(_), None) => Err(FieldError::new(
                "motors.resistance_ohm",
                " is missing: the copper losses need the torque constant and the winding \
                 resistance; give both or neither",
            )),
            (None, Some(_)) => Err(FieldError::new(
                "motors.torque_constant_nm_per_a",
                " is missing: the copper losses need the torque constant and the winding \
                 resistance; give both or neither",
            )),
            _ => Ok(()),
        };
        electrical?;
        if let Some(parts) = self.parts.as_ref().filter(|parts| parts.len() != motors) {
            return Err(FieldError::new(
                "motors.parts",
                format!(
                    " has {} parts but transmission.matrix has {motors} rows: name one \
                     catalogue motor per motor (row of G)",
                    parts.len()
                ),
            ));
        }
        self.names
            .as_deref()
            .map_or(Ok(()), |names| check_names(names, motors))
    }
}

/// Checks `motors.names` for `motors` motors: one name per motor, none empty (or only spaces),
/// no two alike.
fn check_names(names: &[String], motors: usize) -> Result<(), FieldError> {
    const FIELD: &str = "motors.names";
    if names.len() != motors {
        return Err(FieldError::new(
            FIELD,
            format!(
                " has {} names but transmission.matrix has {motors} rows: give one name per \
                 motor (row of G)",
                names.len()
            ),
        ));
    }
    for (i, name) in names.iter().enumerate() {
        if name.trim().is_empty() {
            return Err(FieldError::new(
                format!("{FIELD}[{i}]"),
                " is empty: give each motor a name",
            ));
        }
        if let Some(first) = names[..i].iter().position(|other| other == name) {
            return Err(FieldError::new(
                format!("{FIELD}[{i}]"),
                format!(
                    " = '{}' is also the name of {FIELD}[{first}]: give each motor its own",
                    crate::text::shown(name)
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn motors(value: serde_json::Value) -> Result<Motors, String> {
        serde_json::from_value(value).map_err(|e| e.to_string())
    }

    #[test]
    fn a_number_is_every_motors_and_a_list_each_motors() {
        let all = motors(json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100})).unwrap();
        assert_eq!(all.torque_limit_nm, PerMotor::All(1.7));
        assert_eq!(all.speed_limit_rad_s, PerMotor::All(100.0));
        assert_eq!(all.torque_limit_nm.get(3), Some(1.7));
        assert_eq!(all.torque_limit_nm.values(2), vec![1.7, 1.7]);
        assert!(all.validate(4).is_ok());
        let each = motors(json!({
            "torque_limit_nm": [1.7, 2, 0.5, 0.5],
            "speed_limit_rad_s": 100.0
        }))
        .unwrap();
        assert_eq!(
            each.torque_limit_nm,
            PerMotor::Each(vec![1.7, 2.0, 0.5, 0.5])
        );
        assert_eq!(each.torque_limit_nm.get(1), Some(2.0));
        assert_eq!(each.torque_limit_nm.get(4), None);
        assert_eq!(each.torque_limit_nm.values(4), vec![1.7, 2.0, 0.5, 0.5]);
        assert!(each.validate(4).is_ok());
    }

    /// A number is written back as a number, a list as a list: a recorded task reads as written.
    #[test]
    fn written_back_as_read() {
        for text in [
            r#"{"torque_limit_nm":1.7,"speed_limit_rad_s":100.0}"#,
            r#"{"torque_limit_nm":[1.7,2.0],"speed_limit_rad_s":[100.0,50.0]}"#,
        ] {
            let read: Motors = serde_json::from_str(text).unwrap();
            assert_eq!(serde_json::to_string(&read).unwrap(), text);
        }
    }

    #[test]
    fn shown_as_written() {
        assert_eq!(PerMotor::All(1.7).to_string(), "1.7");
        assert_eq!(
            PerMotor::Each(vec![1.7, 2.0, 1e-9]).to_string(),
            "[1.7, 2, 1e-9]"
        );
    }

    #[test]
    fn mean_of_equal_values_is_that_value() {
        assert_eq!(PerMotor::Each(vec![1.7; 4]).mean(), 1.7);
        assert_eq!(PerMotor::All(1.7).mean(), 1.7);
        assert!((PerMotor::Each(vec![1.0, 2.0, 3.0, 6.0]).mean() - 3.0).abs() < 1e-15);
    }

    #[test]
    fn errors_name_the_field_and_the_motor() {
        let cases = [
            (
                json!({"torque_limit_nm": [1.7, 1.7, 1.7], "speed_limit_rad_s": 100}),
                "motors.torque_limit_nm has 3 values but transmission.matrix has 4 rows",
            ),
            (
                json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": [100, 100, -5, 100]}),
                "motors.speed_limit_rad_s[2] = -5 must be > 0",
            ),
            (
                json!({"torque_limit_nm": [1.7, 0, 1.7, 1.7], "speed_limit_rad_s": 100}),
                "motors.torque_limit_nm[1] = 0 must be > 0",
            ),
            (
                json!({"torque_limit_nm": -1.7, "speed_limit_rad_s": 100}),
                "motors.torque_limit_nm = -1.7 must be > 0",
            ),
            (
                json!({"torque_limit_nm": [], "speed_limit_rad_s": 100}),
                "motors.torque_limit_nm has 0 values",
            ),
        ];
        for (value, expected) in cases {
            let error = motors(value).unwrap().validate(4).unwrap_err().to_string();
            assert!(error.starts_with(expected), "{error}");
        }
        let infinite = Motors::ideal(PerMotor::Each(vec![1.0, f64::INFINITY]), PerMotor::All(1.0));
        let error = infinite.validate(2).unwrap_err().to_string();
        assert!(
            error.starts_with("motors.torque_limit_nm[1] = inf must be > 0 and <= 1000000 N m"),
            "{error}"
        );
    }

    #[test]
    fn other_values_are_refused_saying_what_is_expected() {
        let refused = |value: serde_json::Value| {
            motors(json!({"torque_limit_nm": value, "speed_limit_rad_s": 1})).unwrap_err()
        };
        let expected = "expected a number (every motor) or an array with one number per motor";
        for value in [json!("1.7"), json!({"a": 1}), json!(null), json!(true)] {
            let error = refused(value);
            assert!(error.contains(expected), "{error}");
        }
        for value in [json!([1.7, "x"]), json!([[1.7]])] {
            let error = refused(value);
            assert!(error.contains("expected f64"), "{error}");
        }
    }

    /// The motor model's keys: absent in the built-in task (ideal motors) and not written back
    /// then; a number or one per motor when given, read and written back as given.
    #[test]
    fn motor_model_keys_are_optional_and_read_as_written() {
        let limits = json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100});
        let ideal = motors(limits.clone()).unwrap();
        assert_eq!(
            ideal,
            Motors::ideal(PerMotor::All(1.7), PerMotor::All(100.0))
        );
        assert_eq!(
            serde_json::to_value(&ideal).unwrap(),
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100.0})
        );
        let text = r#"{"torque_limit_nm":1.7,"speed_limit_rad_s":100.0,"rotor_inertia_kgm2":[0.00001,0.00002,0.0,0.00003],"viscous_friction_nm_s_per_rad":0.001,"no_load_speed_rad_s":[150.0,150.0,200.0,200.0]}"#;
        let read: Motors = serde_json::from_str(text).unwrap();
        assert_eq!(
            read.rotor_inertia_kgm2,
            Some(PerMotor::Each(vec![1e-5, 2e-5, 0.0, 3e-5]))
        );
        assert_eq!(
            read.viscous_friction_nm_s_per_rad,
            Some(PerMotor::All(1e-3))
        );
        assert_eq!(
            read.no_load_speed_rad_s,
            Some(PerMotor::Each(vec![150.0, 150.0, 200.0, 200.0]))
        );
        assert!(read.validate(4).is_ok());
        assert_eq!(serde_json::to_string(&read).unwrap(), text);
        let mut misspelt = limits;
        misspelt["rotor_inertia"] = json!(1e-5);
        assert!(motors(misspelt.clone())
            .unwrap_err()
            .contains("unknown field `rotor_inertia`"));
        misspelt.as_object_mut().unwrap().remove("rotor_inertia");
        misspelt["no_load_speed"] = json!(150);
        assert!(motors(misspelt)
            .unwrap_err()
            .contains("unknown field `no_load_speed`"));
    }

    /// Rotor inertia and friction may be 0, not negative, and the no-load speed must be
    /// positive; each error names the key and the motor.
    #[test]
    fn motor_model_errors_name_the_key_and_the_motor() {
        let base = json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100});
        let cases = [
            (
                "rotor_inertia_kgm2",
                json!([1e-5, -1e-5, 0, 0]),
                "motors.rotor_inertia_kgm2[1] = -1e-5 must be >= 0",
            ),
            (
                "viscous_friction_nm_s_per_rad",
                json!(-0.5),
                "motors.viscous_friction_nm_s_per_rad = -0.5 must be >= 0",
            ),
            (
                "viscous_friction_nm_s_per_rad",
                json!([1e-3, 1e-3, 1e-3]),
                "motors.viscous_friction_nm_s_per_rad has 3 values",
            ),
            (
                "no_load_speed_rad_s",
                json!(0),
                "motors.no_load_speed_rad_s = 0 must be > 0",
            ),
            (
                "no_load_speed_rad_s",
                json!([150, 150, -1, 150]),
                "motors.no_load_speed_rad_s[2] = -1 must be > 0",
            ),
            (
                "no_load_speed_rad_s",
                json!([150, 150]),
                "motors.no_load_speed_rad_s has 2 values but transmission.matrix has 4 rows",
            ),
        ];
        for (key, value, expected) in cases {
            let mut given = base.clone();
            given[key] = value;
            let error = motors(given).unwrap().validate(4).unwrap_err().to_string();
            assert!(error.starts_with(expected), "{error}");
        }
        let mut zero = base;
        zero["rotor_inertia_kgm2"] = json!(0);
        zero["viscous_friction_nm_s_per_rad"] = json!([0, 0, 0, 0]);
        assert!(motors(zero).unwrap().validate(4).is_ok());
        let mut infinite = Motors::ideal(PerMotor::All(1.7), PerMotor::All(100.0));
        infinite.no_load_speed_rad_s = Some(PerMotor::Each(vec![150.0, f64::INFINITY]));
        let error = infinite.validate(2).unwrap_err().to_string();
        assert!(
            error.starts_with("motors.no_load_speed_rad_s[1] = inf must be > 0"),
            "{error}"
        );
    }

    /// The efficiency: optional, not written back when absent; in (0, 1], one number or one per
    /// motor, each error naming the field and the motor.
    #[test]
    fn efficiency_is_a_share_of_one_per_motor() {
        let limits = json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100.0});
        assert_eq!(motors(limits.clone()).unwrap().efficiency, None);
        let mut given = limits;
        given["efficiency"] = json!([0.95, 0.95, 0.9, 1]);
        let read = motors(given.clone()).unwrap();
        assert_eq!(read.validate(4), Ok(()));
        assert_eq!(
            read.efficiency,
            Some(PerMotor::Each(vec![0.95, 0.95, 0.9, 1.0]))
        );
        for (value, expected) in [
            (
                json!(0),
                "motors.efficiency = 0 must be > 0 and <= 1 (a share",
            ),
            (json!(1.01), "motors.efficiency = 1.01 must be > 0 and <= 1"),
            (
                json!([0.9, 0.9, 0.9, -0.5]),
                "motors.efficiency[3] = -0.5 must be > 0",
            ),
            (
                json!(0.001),
                "motors.efficiency = 0.001 must be at least 0.01",
            ),
            (json!([0.9, 0.9]), "motors.efficiency has 2 values"),
        ] {
            given["efficiency"] = value;
            let error = motors(given.clone()).unwrap().validate(4).unwrap_err();
            assert!(error.to_string().starts_with(expected), "{error}");
        }
    }

    /// Values that overflow the dynamics (1e308), or that are subnormal (1e-320), are refused
    /// naming the field, the limit and why; the largest and the least values are accepted.
    #[test]
    fn motor_quantities_are_bounded_and_never_subnormal() {
        let base = json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100});
        let cases = [
            (
                "torque_limit_nm",
                json!(1e308),
                "motors.torque_limit_nm = 1e308 must be > 0 and <= 1000000 N m (far beyond any",
            ),
            (
                "torque_limit_nm",
                json!(1e-320),
                "motors.torque_limit_nm = 1e-320 must be at least 2.2250738585072014e-308 N m",
            ),
            (
                "speed_limit_rad_s",
                json!([100, 1e7, 100, 100]),
                "motors.speed_limit_rad_s[1] = 10000000 must be > 0 and <= 1000000 rad/s",
            ),
            (
                "rotor_inertia_kgm2",
                json!(1e308),
                "motors.rotor_inertia_kgm2 = 1e308 must be >= 0 and <= 1 kg m^2",
            ),
            (
                "rotor_inertia_kgm2",
                json!(1e-320),
                "motors.rotor_inertia_kgm2 = 1e-320 must be 0 or at least 2.2250738585072014e-308 kg m^2",
            ),
            (
                "viscous_friction_nm_s_per_rad",
                json!(1e4),
                "motors.viscous_friction_nm_s_per_rad = 10000 must be >= 0 and <= 1000 N m s/rad",
            ),
            (
                "no_load_speed_rad_s",
                json!(1e-320),
                "motors.no_load_speed_rad_s = 1e-320 must be at least 0.001 rad/s",
            ),
            (
                "no_load_speed_rad_s",
                json!(1e308),
                "motors.no_load_speed_rad_s = 1e308 must be > 0 and <= 1000000 rad/s",
            ),
        ];
        for (key, value, expected) in cases {
            let mut given = base.clone();
            given[key] = value;
            let error = motors(given).unwrap().validate(4).unwrap_err().to_string();
            assert!(error.starts_with(expected), "{error}");
        }
        let mut largest = base;
        largest["torque_limit_nm"] = json!(1e6);
        largest["speed_limit_rad_s"] = json!(1e6);
        largest["rotor_inertia_kgm2"] = json!([1, 0, 2.3e-308, 1]);
        largest["viscous_friction_nm_s_per_rad"] = json!(1e3);
        largest["no_load_speed_rad_s"] = json!([1e6, 1e-3, 1, 1]);
        assert_eq!(motors(largest).unwrap().validate(4), Ok(()));
    }

    /// `motors.names`: optional, not written back when absent; one name per motor, none
    /// empty, no two alike, each error naming the field.
    #[test]
    fn motor_names_are_one_per_motor_and_distinct() {
        let limits = json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100.0});
        assert_eq!(motors(limits.clone()).unwrap().names, None);
        let mut named = limits;
        named["names"] = json!(["shoulder", "elbow", "wrist 1", "wrist 2"]);
        let read = motors(named.clone()).unwrap();
        assert_eq!(read.validate(4), Ok(()));
        assert_eq!(read.names.as_ref().unwrap()[2], "wrist 1");
        assert_eq!(serde_json::to_value(&read).unwrap(), named);
        let cases = [
            (
                json!(["a", "b", "c"]),
                "motors.names has 3 names but transmission.matrix has 4 rows",
            ),
            (json!(["a", "b", " ", "d"]), "motors.names[2] is empty"),
            (
                json!(["a", "b", "a", "d"]),
                "motors.names[2] = 'a' is also the name of motors.names[0]",
            ),
        ];
        for (names, expected) in cases {
            let mut given = named.clone();
            given["names"] = names;
            let error = motors(given).unwrap().validate(4).unwrap_err().to_string();
            assert!(error.starts_with(expected), "{error}");
        }
        named["names"] = json!("shoulder");
        assert!(motors(named).unwrap_err().contains("expected a sequence"));
    }

    /// A task checks its motors against the rows of its G.
    #[test]
    fn a_task_holds_its_lists_to_the_rows_of_g() {
        let mut task = crate::testing::task();
        task.motors.speed_limit_rad_s = PerMotor::Each(vec![100.0, 90.0, 80.0, 70.0]);
        assert!(task.validate().is_ok());
        task.transmission.matrix.pop();
        assert_eq!(
            task.validate().unwrap_err().field,
            "motors.speed_limit_rad_s"
        );
    }
}
