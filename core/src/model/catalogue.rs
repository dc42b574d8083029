//! A catalogue of parts a designer can buy (`codesign/catalogue`, version 1): motors, belt and
//! pulley series, and gearboxes, each with the public source of its numbers.
//!
//! A catalogue is a JSON file (e.g. `robots/catalogue/parts.json`), read strictly: an unknown
//! or repeated key, a number of the wrong sign or a name given twice is refused, the error
//! naming the file and the field (`catalogue parts.json: motors[2].rotor_inertia_kgm2 = -1
//! must be >= 0 ...`). Numbers a source does not give are left out; a task takes them from its
//! own fields or the ideal motor's ([`super::motor_parts`]). Units are SI, with the belts'
//! pitch and width in mm as their makers give them. docs/guide/catalogue.md describes every
//! field.

use super::ranges::{Bounds, FieldError};
use crate::input::{read_text, MAX_TASK_BYTES};
use crate::json_keys::{check_unique_keys, line_of, read_value};
use crate::text::shown;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::f64::consts::PI;
use std::fmt;
use std::path::Path;

/// The value of a catalogue's `schema`.
pub const SCHEMA: &str = "codesign/catalogue";

/// The catalogue version this build reads.
pub const VERSION: u32 = 1;

/// A whole catalogue file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Catalogue {
    /// Always [`SCHEMA`].
    pub schema: String,
    /// Always [`VERSION`].
    pub version: u32,
    /// What the catalogue holds, in words (no part of any problem).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The motors, each name given once.
    #[serde(default)]
    pub motors: Vec<CatalogueMotor>,
    /// The belt and pulley series.
    #[serde(default)]
    pub belts: Vec<BeltSeries>,
    /// The gearboxes, one ratio each.
    #[serde(default)]
    pub gearboxes: Vec<Gearbox>,
}

/// A motor as its datasheet (or MGDB's row) gives it; every number optional.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CatalogueMotor {
    /// The name a task chooses it by, unique in the catalogue.
    pub name: String,
    /// The maker.
    pub maker: String,
    /// The maker's part number.
    pub part_number: String,
    /// The nominal voltage of the winding, V.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nominal_voltage_v: Option<f64>,
    /// Mass, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    /// Rotor inertia about its axis, kg m^2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotor_inertia_kgm2: Option<f64>,
    /// Peak (intermittent) torque, N m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_torque_nm: Option<f64>,
    /// Continuous torque, N m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuous_torque_nm: Option<f64>,
    /// Continuous (rated, RMS) current, A.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuous_current_a: Option<f64>,
    /// No-load speed at the nominal voltage, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_load_speed_rad_s: Option<f64>,
    /// Largest permissible speed, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_speed_rad_s: Option<f64>,
    /// Torque constant k_t, N m/A.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_constant_nm_per_a: Option<f64>,
    /// Winding resistance R, terminal to terminal, ohm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resistance_ohm: Option<f64>,
    /// Coulomb friction torque, N m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coulomb_friction_nm: Option<f64>,
    /// Viscous friction, N m s/rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_friction_nm_s_per_rad: Option<f64>,
    /// Thermal resistance winding to housing (or the lumped one), K/W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermal_resistance_winding_k_per_w: Option<f64>,
    /// Thermal resistance housing to ambient, K/W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermal_resistance_housing_k_per_w: Option<f64>,
    /// Where the numbers come from: a datasheet's title, document number and page, or MGDB's
    /// file and row key.
    pub source: String,
}

/// A series of toothed belts with pulleys of one material, each pulley a solid disc of the
/// belt's width: pitch radius R = z p / (2 pi) for z teeth of pitch p, mass m = rho pi w R^2,
/// inertia m R^2 / 2 about its axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeltSeries {
    /// The name, unique among the belts.
    pub name: String,
    /// The belt's tooth pitch p, mm.
    pub pitch_mm: f64,
    /// The belt's (and pulley's) width w, mm.
    pub width_mm: f64,
    /// The density rho of the pulleys' material, kg/m^3 (0: massless pulleys).
    pub density_kg_m3: f64,
    /// The fewest teeth a pulley of the series may have.
    pub min_teeth: u32,
    /// Where the numbers come from.
    pub source: String,
}

/// A gearbox of one ratio, as its datasheet (or MGDB's row) gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gearbox {
    /// The name, unique among the gearboxes.
    pub name: String,
    /// The maker.
    pub maker: String,
    /// The maker's part number.
    pub part_number: String,
    /// Input to output speed ratio (> 1 reduces).
    pub ratio: f64,
    /// Reduction stages.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stages: Option<u32>,
    /// Mass, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    /// Inertia at the input, kg m^2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input_inertia_kgm2: Option<f64>,
    /// Efficiency at rated load, in (0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub efficiency: Option<f64>,
    /// Peak (intermittent) output torque, N m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_torque_nm: Option<f64>,
    /// Continuous output torque, N m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuous_torque_nm: Option<f64>,
    /// Where the numbers come from.
    pub source: String,
}

/// A catalogue that could not be read or makes no sense: its file, the field and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CatalogueError {
    /// The catalogue file, as given.
    pub file: String,
    /// The field at fault (`motors[2].mass_kg`); empty for the whole file.
    pub field: String,
    /// What is wrong, as it follows the field's name.
    pub problem: String,
}

impl fmt::Display for CatalogueError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.field.is_empty() {
            true => write!(f, "catalogue {}: {}", self.file, self.problem),
            false => write!(f, "catalogue {}: {}{}", self.file, self.field, self.problem),
        }
    }
}

impl std::error::Error for CatalogueError {}

/// A positive physical number of a part: mass, torque, speed, constant, density, length.
const POSITIVE: Bounds = Bounds {
    zero: false,
    least: f64::MIN_POSITIVE,
    most: 1e6,
    unit: "",
    why: "a part's number, positive and far below 1e6 in SI units",
};

/// A number of a part that may be 0: an inertia, a friction, a resistance.
const NON_NEGATIVE: Bounds = Bounds {
    zero: true,
    ..POSITIVE
};

/// An efficiency: a share of the power passed on.
const SHARE: Bounds = Bounds {
    zero: false,
    least: 1e-2,
    most: 1.0,
    unit: "",
    why: "a share of the power passed on, 1 for a lossless part",
};

impl Catalogue {
    /// Reads and checks the catalogue at `path`; errors name the file as given and the field.
    pub fn load(path: &Path) -> Result<Catalogue, CatalogueError> {
        let file = shown(&path.display().to_string());
        let whole = |problem: String| CatalogueError {
            file: file.clone(),
            field: String::new(),
            problem,
        };
        let text = read_text(path, MAX_TASK_BYTES).map_err(|e| whole(e.to_string()))?;
        Catalogue::from_text(&text, &file)
    }

    /// Reads and checks the JSON `text` of a catalogue named `file` in errors.
    pub fn from_text(text: &str, file: &str) -> Result<Catalogue, CatalogueError> {
        let error = |field: String, problem: String| CatalogueError {
            file: file.to_owned(),
            field,
            problem,
        };
        check_unique_keys(text).map_err(|e| error(String::new(), e))?;
        let value: Value =
            serde_json::from_str(text).map_err(|e| error(String::new(), e.to_string()))?;
        match (value.get("schema"), value.get("version")) {
            (Some(Value::String(s)), Some(v)) if s == SCHEMA && v.as_u64() == Some(u64::from(VERSION)) => {}
            _ => {
                return Err(error(
                    String::new(),
                    format!("is not a catalogue: it must say \"schema\": \"{SCHEMA}\", \"version\": {VERSION}"),
                ))
            }
        }
        let catalogue: Catalogue = read_value(&value).map_err(|e| {
            let at = line_of(text, &e.path).map_or(String::new(), |l| format!(" at line {l}"));
            error(e.field(""), format!("{at}: {}", e.message))
        })?;
        catalogue
            .validate()
            .map_err(|e| error(e.field, e.problem))?;
        Ok(catalogue)
    }

    /// The motor named `name`.
    pub fn motor(&self, name: &str) -> Option<&CatalogueMotor> {
        self.motors.iter().find(|motor| motor.name == name)
    }

    /// Checks every part: names present and unique per kind, sources given, numbers in range.
    pub fn validate(&self) -> Result<(), FieldError> {
        let motors = self.motors.iter().map(|m| (&m.name, &m.source));
        check_names("motors", motors)?;
        check_names("belts", self.belts.iter().map(|b| (&b.name, &b.source)))?;
        let gearboxes = self.gearboxes.iter().map(|g| (&g.name, &g.source));
        check_names("gearboxes", gearboxes)?;
        for (i, motor) in self.motors.iter().enumerate() {
            check_numbers(&format!("motors[{i}]"), &motor.numbers())?;
        }
        for (i, belt) in self.belts.iter().enumerate() {
            let at = format!("belts[{i}]");
            check_numbers(&at, &belt.numbers())?;
            if belt.min_teeth == 0 {
                return Err(FieldError::new(
                    format!("{at}.min_teeth"),
                    " = 0: a pulley has at least one tooth",
                ));
            }
        }
        for (i, gearbox) in self.gearboxes.iter().enumerate() {
            check_numbers(&format!("gearboxes[{i}]"), &gearbox.numbers())?;
        }
        Ok(())
    }
}

/// A named number of a part with its bounds; None where the source does not give it.
type Number = (&'static str, Option<f64>, Bounds);

impl CatalogueMotor {
    /// Every number with its field's name and bounds.
    fn numbers(&self) -> [Number; 14] {
        [
            ("nominal_voltage_v", self.nominal_voltage_v, POSITIVE),
            ("mass_kg", self.mass_kg, POSITIVE),
            ("rotor_inertia_kgm2", self.rotor_inertia_kgm2, NON_NEGATIVE),
            ("peak_torque_nm", self.peak_torque_nm, POSITIVE),
            ("continuous_torque_nm", self.continuous_torque_nm, POSITIVE),
            ("continuous_current_a", self.continuous_current_a, POSITIVE),
            ("no_load_speed_rad_s", self.no_load_speed_rad_s, POSITIVE),
            ("max_speed_rad_s", self.max_speed_rad_s, POSITIVE),
            (
                "torque_constant_nm_per_a",
                self.torque_constant_nm_per_a,
                POSITIVE,
            ),
            ("resistance_ohm", self.resistance_ohm, NON_NEGATIVE),
            (
                "coulomb_friction_nm",
                self.coulomb_friction_nm,
                NON_NEGATIVE,
            ),
            (
                "viscous_friction_nm_s_per_rad",
                self.viscous_friction_nm_s_per_rad,
                NON_NEGATIVE,
            ),
            (
                "thermal_resistance_winding_k_per_w",
                self.thermal_resistance_winding_k_per_w,
                POSITIVE,
            ),
            (
                "thermal_resistance_housing_k_per_w",
                self.thermal_resistance_housing_k_per_w,
                POSITIVE,
            ),
        ]
    }

    /// The continuous torque, N m: the datasheet's, else k_t times the continuous current.
    pub fn continuous_torque(&self) -> Option<f64> {
        let from_current = || Some(self.torque_constant_nm_per_a? * self.continuous_current_a?);
        self.continuous_torque_nm.or_else(from_current)
    }
}

impl BeltSeries {
    fn numbers(&self) -> [Number; 3] {
        [
            ("pitch_mm", Some(self.pitch_mm), POSITIVE),
            ("width_mm", Some(self.width_mm), POSITIVE),
            ("density_kg_m3", Some(self.density_kg_m3), NON_NEGATIVE),
        ]
    }

    /// The pitch radius of a pulley of `teeth` teeth, m: R = z p / (2 pi).
    pub fn pitch_radius_m(&self, teeth: u32) -> f64 {
        f64::from(teeth) * self.pitch_mm * 1e-3 / (2.0 * PI)
    }

    /// The mass of a pulley of radius `radius_m` m, kg: a solid disc, m = rho pi w R^2.
    pub fn pulley_mass_kg(&self, radius_m: f64) -> f64 {
        self.density_kg_m3 * PI * self.width_mm * 1e-3 * radius_m * radius_m
    }

    /// The inertia about its axis of a pulley of radius `radius_m` m, kg m^2: m R^2 / 2.
    pub fn pulley_inertia_kgm2(&self, radius_m: f64) -> f64 {
        0.5 * self.pulley_mass_kg(radius_m) * radius_m * radius_m
    }
}

impl Gearbox {
    fn numbers(&self) -> [Number; 6] {
        [
            ("ratio", Some(self.ratio), POSITIVE),
            ("mass_kg", self.mass_kg, POSITIVE),
            ("input_inertia_kgm2", self.input_inertia_kgm2, NON_NEGATIVE),
            ("efficiency", self.efficiency, SHARE),
            ("peak_torque_nm", self.peak_torque_nm, POSITIVE),
            ("continuous_torque_nm", self.continuous_torque_nm, POSITIVE),
        ]
    }
}

/// Checks the numbers of the part at `at` (`motors[2]`).
fn check_numbers(at: &str, numbers: &[Number]) -> Result<(), FieldError> {
    numbers
        .iter()
        .try_for_each(|(field, value, bounds)| match value {
            Some(value) => bounds.check(&format!("{at}.{field}"), *value),
            None => Ok(()),
        })
}

/// Checks the parts of `kind`: each has a name and a source, none empty, no name twice.
fn check_names<'a>(
    kind: &str,
    parts: impl Iterator<Item = (&'a String, &'a String)>,
) -> Result<(), FieldError> {
    let mut seen: Vec<&String> = Vec::new();
    for (i, (name, source)) in parts.enumerate() {
        if name.trim().is_empty() {
            return Err(FieldError::new(format!("{kind}[{i}].name"), " is empty"));
        }
        if source.trim().is_empty() {
            return Err(FieldError::new(
                format!("{kind}[{i}].source"),
                " is empty: every part cites where its numbers come from",
            ));
        }
        if let Some(first) = seen.iter().position(|other| *other == name) {
            return Err(FieldError::new(
                format!("{kind}[{i}].name"),
                format!(
                    " = '{}' is also the name of {kind}[{first}]: give each part its own",
                    shown(name)
                ),
            ));
        }
        seen.push(name);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn read(value: serde_json::Value) -> Result<Catalogue, String> {
        Catalogue::from_text(&value.to_string(), "c.json").map_err(|e| e.to_string())
    }

    fn motor() -> serde_json::Value {
        json!({"name": "m", "maker": "x", "part_number": "1", "peak_torque_nm": 2.0,
               "torque_constant_nm_per_a": 0.1, "continuous_current_a": 3.0, "source": "s"})
    }

    fn catalogue(motors: Vec<serde_json::Value>) -> serde_json::Value {
        json!({"schema": SCHEMA, "version": VERSION, "motors": motors})
    }

    #[test]
    fn reads_parts_and_leaves_out_what_is_not_given() {
        let read = read(catalogue(vec![motor()])).unwrap();
        let m = read.motor("m").unwrap();
        assert_eq!(m.peak_torque_nm, Some(2.0));
        assert_eq!(m.rotor_inertia_kgm2, None);
        assert!((m.continuous_torque().unwrap() - 0.3).abs() < 1e-15);
        assert!(read.motor("n").is_none());
        assert!(read.belts.is_empty() && read.gearboxes.is_empty());
    }

    #[test]
    fn errors_name_the_file_and_the_field() {
        let mut misspelt = motor();
        misspelt["rotor_inertia"] = json!(1e-5);
        let mut negative = motor();
        negative["mass_kg"] = json!(-1);
        let mut unsourced = motor();
        unsourced["source"] = json!(" ");
        let cases = [
            (catalogue(vec![misspelt]), "catalogue c.json: motors[0].rotor_inertia at line 1: unknown field `rotor_inertia`"),
            (catalogue(vec![negative]), "catalogue c.json: motors[0].mass_kg = -1 must be > 0"),
            (catalogue(vec![unsourced]), "catalogue c.json: motors[0].source is empty: every part cites"),
            (catalogue(vec![motor(), motor()]), "catalogue c.json: motors[1].name = 'm' is also the name of motors[0]"),
            (json!({"schema": "codesign/task", "version": 1}), "catalogue c.json: is not a catalogue"),
            (json!({"schema": SCHEMA, "version": 2}), "catalogue c.json: is not a catalogue"),
            (json!({"schema": SCHEMA, "version": 1, "motors": [{"name": "m"}]}), "catalogue c.json: motors[0] at line 1: missing field `maker`"),
            (json!({"schema": SCHEMA, "version": 1, "gearboxes": [{"name": "g", "maker": "x",
                "part_number": "1", "ratio": 4, "efficiency": 1.2, "source": "s"}]}),
                "catalogue c.json: gearboxes[0].efficiency = 1.2 must be > 0 and <= 1"),
            (json!({"schema": SCHEMA, "version": 1, "belts": [{"name": "b", "pitch_mm": 2,
                "width_mm": 6, "density_kg_m3": 2700, "min_teeth": 0, "source": "s"}]}),
                "catalogue c.json: belts[0].min_teeth = 0"),
        ];
        for (value, expected) in cases {
            let error = read(value).unwrap_err();
            assert!(error.starts_with(expected), "{error}");
        }
        let twice = r#"{"schema": "codesign/catalogue", "version": 1, "version": 1}"#;
        let error = Catalogue::from_text(twice, "c.json")
            .unwrap_err()
            .to_string();
        assert!(error.contains("`version` is given twice"), "{error}");
        let missing = Catalogue::load(Path::new("/nonexistent/c.json")).unwrap_err();
        assert!(missing
            .to_string()
            .starts_with("catalogue /nonexistent/c.json: cannot read"));
    }

    /// A pulley is a solid disc: m = rho pi w R^2 and I = m R^2 / 2, with R = z p / (2 pi).
    #[test]
    fn a_pulley_is_a_solid_disc() {
        let belt = BeltSeries {
            name: "b".into(),
            pitch_mm: 2.0,
            width_mm: 6.0,
            density_kg_m3: 2700.0,
            min_teeth: 12,
            source: "s".into(),
        };
        let radius = belt.pitch_radius_m(20);
        assert!((radius - 0.040 / (2.0 * PI)).abs() < 1e-15);
        let mass = 2700.0 * PI * 0.006 * radius * radius;
        assert!((belt.pulley_mass_kg(radius) - mass).abs() < 1e-15);
        assert!((belt.pulley_inertia_kgm2(radius) - mass * radius * radius / 2.0).abs() < 1e-18);
    }
}
