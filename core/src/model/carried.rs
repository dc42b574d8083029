//! Parts carried by links (the task's `carried`): a pulley of a catalogue belt series whose
//! teeth follow a ratio of the design, and a catalogue motor or gearbox of fixed mass, each
//! fixed at a point of a link (docs/model.md, section 18; docs/guide/catalogue.md).
//!
//! The section is read when the task is read ([`resolve`]): each catalogue path is joined to
//! the task file's folder, each part is read from its catalogue and the numbers the problem
//! uses are written into the entry (`pitch_mm`, `width_mm`, `density_kg_m3` of a pulley,
//! `mass_kg` of a motor or gearbox), so that a task written back reads back and the task hash
//! counts the numbers, not where the catalogue lies. [`CarriedModel`] (`super::carried_mass`)
//! places the parts on the robot's bodies and gives their mass properties at a design r, and
//! their derivatives in r.
//!
//! A pulley is a solid disc of the belt's width w about its axis n: z = r_l z_d teeth (the
//! ratio its design parameter r_l makes with a driver of z_d teeth, taken continuously), pitch
//! radius R = z p / (2 pi), mass m = rho pi w R^2, inertia about its centre
//! I = I_axis n n^T + I_diam (E - n n^T) with I_axis = m R^2 / 2 and
//! I_diam = m (3 R^2 + w^2) / 12. A motor or a gearbox is a point mass: a catalogue gives no
//! housing's dimensions (a motor's rotor inertia is the motor model's, reflected by G).

pub use super::carried_mass::{motor_parts_mass_kg, CarriedMassAt, CarriedModel};
use super::catalogue::Catalogue;
use super::motor_parts::PartChoice;
use super::ranges::{check_finite, check_norm, FieldError, MAX_POINT_M};
use crate::json_keys::read_value;
use crate::text::{number, shown};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// One part carried by a link: where it sits and what it is (exactly one of `pulley`,
/// `motor`, `gearbox`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriedPart {
    /// The URDF link it is fixed to.
    pub link: String,
    /// Its centre in the link's frame, m.
    pub at: [f64; 3],
    /// A pulley whose teeth follow a ratio of the design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pulley: Option<CarriedPulley>,
    /// A catalogue motor (a point mass).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motor: Option<CarriedMass>,
    /// A catalogue gearbox (a point mass).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gearbox: Option<CarriedMass>,
}

/// A pulley of a catalogue belt series, its teeth z = c r_l z_d.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriedPulley {
    /// The catalogue file (relative to the task file's folder when written; joined when read).
    pub catalogue: PathBuf,
    /// The belt series' `name` in that catalogue.
    pub series: String,
    /// The entry of G its teeth follow: `r<l>` (1-based, as in `transmission.matrix`) or
    /// `c*r<l>` (c > 0, such as `2*r2`).
    pub teeth_of: String,
    /// The driver pulley's teeth z_d: the pulley has c r_l z_d teeth.
    pub driver_teeth: f64,
    /// Its axis in the link's frame (normalised); absent: the axis of the joint that moves the
    /// link.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<[f64; 3]>,
    /// The series' tooth pitch, mm (set from the catalogue when read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch_mm: Option<f64>,
    /// The series' width, mm (set from the catalogue when read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_mm: Option<f64>,
    /// The pulleys' density, kg/m^3 (set from the catalogue when read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density_kg_m3: Option<f64>,
}

/// A catalogue motor or gearbox carried as a point mass.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriedMass {
    /// The catalogue file (relative to the task file's folder when written; joined when read;
    /// for `of_motor`, that motor's, set when read).
    #[serde(default)]
    pub catalogue: PathBuf,
    /// The part's `name` in that catalogue (for `of_motor`, that motor's, set when read).
    #[serde(default)]
    pub name: String,
    /// A motor of the task's own: entry K (from 0) of `motors.parts`, whose part this is, so
    /// that a search over candidates carries the part it chose, and its mass counts once.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub of_motor: Option<usize>,
    /// Its mass, kg (set from the catalogue when read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
}

impl CarriedPart {
    /// What it is, in words: `pulley`, `motor` or `gearbox`.
    pub fn kind(&self) -> &'static str {
        match (&self.pulley, &self.motor) {
            (Some(_), _) => "pulley",
            (None, Some(_)) => "motor",
            (None, None) => "gearbox",
        }
    }

    /// Its name: the belt series' or the part's.
    pub fn name(&self) -> &str {
        match (&self.pulley, &self.motor, &self.gearbox) {
            (Some(pulley), _, _) => &pulley.series,
            (None, Some(part), _) | (None, None, Some(part)) => &part.name,
            (None, None, None) => "",
        }
    }
}

/// What a pulley's `teeth_of` names: the 0-based index of the ratio r_l among `count`, and the
/// factor c of `c*r<l>` (1 for `r<l>`), an entry of G: the pulley has c r_l times its driver's
/// teeth. None if it names no ratio or c is not a positive number.
pub(super) fn teeth_ratio(name: &str, count: usize) -> Option<(usize, f64)> {
    let (factor, ratio) = match name.split_once('*') {
        Some((factor, ratio)) => (factor.trim().parse::<f64>().ok()?, ratio),
        None => (1.0, name),
    };
    let sane = factor.is_finite() && factor > 0.0 && factor <= MAX_TEETH_FACTOR;
    Some((ratio_index(ratio, count)?, factor)).filter(|_| sane)
}

/// The largest factor c of a `teeth_of` of the form `c*r<l>`.
const MAX_TEETH_FACTOR: f64 = 1e3;

/// The 0-based index of the ratio `r<i>` among `count`, None if it names none.
fn ratio_index(name: &str, count: usize) -> Option<usize> {
    let digits = name.trim().strip_prefix('r')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let i: usize = digits.parse().ok()?;
    (1..=count).contains(&i).then(|| i - 1)
}

/// A number set from the catalogue: the catalogue's, unless the task gives another.
fn set_from(field: String, given: &mut Option<f64>, part: f64) -> Result<(), String> {
    match *given {
        Some(value) if value != part => Err(format!(
            "{field} = {} conflicts with the catalogue's {}",
            number(value),
            number(part)
        )),
        _ => {
            *given = Some(part);
            Ok(())
        }
    }
}

/// Reads the catalogue at `path` joined to `folder` (None: absolute paths only).
fn catalogue_at(
    field: &str,
    path: &mut PathBuf,
    folder: Option<&Path>,
) -> Result<Catalogue, String> {
    if path.is_relative() {
        let Some(folder) = folder else {
            return Err(format!(
                "{field}.catalogue = {} is relative, and this task has no folder: give an \
                 absolute path",
                shown(&path.display().to_string())
            ));
        };
        *path = folder.join(&*path);
    }
    Catalogue::load(path).map_err(|e| format!("{field}.catalogue: {e}"))
}

/// Resolves the `carried` section of the task JSON `task` in place (see the module's
/// documentation); without it the task is left as it is. The error names the field.
pub fn resolve(task: &mut Value, folder: Option<&Path>) -> Result<(), String> {
    let Some(given) = task.get("carried") else {
        return Ok(());
    };
    let mut parts: Vec<CarriedPart> =
        read_value(given).map_err(|e| format!("{}: {}", e.field("carried"), e.message))?;
    let bounds = design_bounds(task);
    for (i, part) in parts.iter_mut().enumerate() {
        let field = format!("carried[{i}]");
        let kinds = [
            part.pulley.is_some(),
            part.motor.is_some(),
            part.gearbox.is_some(),
        ];
        if kinds.iter().filter(|&&k| k).count() != 1 {
            return Err(format!(
                "{field} must give exactly one of pulley, motor and gearbox"
            ));
        }
        if let Some(pulley) = &mut part.pulley {
            resolve_pulley(
                &format!("{field}.pulley"),
                pulley,
                folder,
                bounds.as_deref(),
            )?;
        }
        let (kind, part) = match (&mut part.motor, &mut part.gearbox) {
            (Some(motor), _) => ("motor", motor),
            (None, Some(gearbox)) => ("gearbox", gearbox),
            (None, None) => continue,
        };
        let at = format!("{field}.{kind}");
        let catalogue = match part.of_motor {
            Some(entry) if kind == "motor" => motor_of(&at, part, entry, task)?,
            Some(_) => return Err(format!("{at}.of_motor names a motor: carry it as `motor`")),
            None => catalogue_at(&at, &mut part.catalogue, folder)?,
        };
        let mass = match kind {
            "motor" => catalogue.motor(&part.name).map(|m| m.mass_kg),
            _ => (catalogue.gearboxes.iter().find(|g| g.name == part.name)).map(|g| g.mass_kg),
        };
        let Some(mass) = mass else {
            return Err(format!(
                "{at}.name = '{}' is no {kind} of catalogue {}",
                shown(&part.name),
                shown(&part.catalogue.display().to_string())
            ));
        };
        let Some(mass) = mass else {
            return Err(format!(
                "{at}: the catalogue gives no mass_kg of '{}'",
                shown(&part.name)
            ));
        };
        set_from(format!("{at}.mass_kg"), &mut part.mass_kg, mass)?;
    }
    let written = serde_json::to_value(parts).map_err(|e| e.to_string())?;
    task["carried"] = written;
    Ok(())
}

/// Sets `part`, at `at`, to the part of entry `entry` of the task's `motors.parts` (already
/// read, its catalogue's path joined), and reads that catalogue. A catalogue or name the entry
/// also gives (a task written back) must be the motor's.
fn motor_of(
    at: &str,
    part: &mut CarriedMass,
    entry: usize,
    task: &Value,
) -> Result<Catalogue, String> {
    let parts = task.get("motors").and_then(|m| m.get("parts"));
    let chosen = parts.and_then(|p| p.get(entry)).cloned();
    let Some(chosen) = chosen.and_then(|c| serde_json::from_value::<PartChoice>(c).ok()) else {
        return Err(format!(
            "{at}.of_motor = {entry} names no entry of motors.parts (counted from 0)"
        ));
    };
    let given = (!part.name.is_empty() || !part.catalogue.as_os_str().is_empty())
        .then(|| (part.name.clone(), part.catalogue.clone()));
    if given.is_some_and(|(name, _)| name != chosen.name) {
        return Err(format!(
            "{at}.name = '{}' is not the part of motors.parts[{entry}], '{}': give of_motor \
             alone",
            shown(&part.name),
            shown(&chosen.name)
        ));
    }
    part.catalogue = chosen.catalogue;
    part.name = chosen.name;
    Catalogue::load(&part.catalogue).map_err(|e| format!("{at}.catalogue: {e}"))
}

/// The design space's bounds `[lower, upper]` of the task JSON `task`, one per ratio; None
/// where `transmission.bounds` is absent or not a list of pairs of numbers, which the task's
/// reader refuses naming it.
fn design_bounds(task: &Value) -> Option<Vec<[f64; 2]>> {
    let bounds = task.get("transmission")?.get("bounds")?;
    serde_json::from_value(bounds.clone()).ok()
}

/// Sets `pulley`'s numbers from its belt series in its catalogue, `at` naming it
/// (`carried[0].pulley`); the catalogue's path is joined to `folder`. Its teeth are checked
/// over the design space `bounds` (None: not read, left to the task's reader): its driver has
/// at least the series' `min_teeth`, and so has the pulley at the lower bound of its ratio.
fn resolve_pulley(
    at: &str,
    pulley: &mut CarriedPulley,
    folder: Option<&Path>,
    bounds: Option<&[[f64; 2]]>,
) -> Result<(), String> {
    let catalogue = catalogue_at(at, &mut pulley.catalogue, folder)?;
    let Some(series) = catalogue.belts.iter().find(|b| b.name == pulley.series) else {
        return Err(format!(
            "{at}.series = '{}' is no belt series of catalogue {}",
            shown(&pulley.series),
            shown(&pulley.catalogue.display().to_string())
        ));
    };
    let teeth = f64::from(series.min_teeth)..=1e4;
    if !teeth.contains(&pulley.driver_teeth) {
        return Err(format!(
            "{at}.driver_teeth = {} must be at least the series' {} teeth (and at most \
                 1e4)",
            number(pulley.driver_teeth),
            series.min_teeth
        ));
    }
    if let Some(bounds) = bounds {
        check_teeth_over_bounds(at, pulley, series.min_teeth, bounds)?;
    }
    set_from(
        format!("{at}.pitch_mm"),
        &mut pulley.pitch_mm,
        series.pitch_mm,
    )?;
    set_from(
        format!("{at}.width_mm"),
        &mut pulley.width_mm,
        series.width_mm,
    )?;
    let density = series.density_kg_m3;
    set_from(
        format!("{at}.density_kg_m3"),
        &mut pulley.density_kg_m3,
        density,
    )?;
    Ok(())
}

/// Checks that `pulley` (named `at`) has at least `min_teeth` teeth over the design space
/// `bounds`: z = c r_l z_d is least at the lower bound of r_l. A ratio `teeth_of` does not name,
/// or a lower bound that is not a positive number, is left to the task's checks, which name
/// them.
fn check_teeth_over_bounds(
    at: &str,
    pulley: &CarriedPulley,
    min_teeth: u32,
    bounds: &[[f64; 2]],
) -> Result<(), String> {
    let Some((l, factor)) = teeth_ratio(&pulley.teeth_of, bounds.len()) else {
        return Ok(());
    };
    let lower = bounds[l][0];
    if !(lower.is_finite() && lower > 0.0) {
        return Ok(());
    }
    let per_ratio = factor * pulley.driver_teeth;
    let (least, min) = (lower * per_ratio, f64::from(min_teeth));
    if least >= min {
        return Ok(());
    }
    let product = match factor {
        1.0 => format!("{} x {}", number(lower), number(pulley.driver_teeth)),
        _ => format!(
            "{} x {} x {}",
            number(lower),
            number(factor),
            number(pulley.driver_teeth)
        ),
    };
    Err(format!(
        "{at}.driver_teeth = {} makes too few teeth at the lower bound of r{}: \
         transmission.bounds[{l}] = [{}, {}] gives the pulley {product} = {} teeth, fewer than \
         the series' {min_teeth}; raise that lower bound to at least {}, or driver_teeth to at \
         least {}",
        number(pulley.driver_teeth),
        l + 1,
        number(lower),
        number(bounds[l][1]),
        number(least),
        number(min / per_ratio),
        number(min / (lower * factor)),
    ))
}

/// Checks the parts of a task of `ratios` design parameters, as read ([`resolve`] set their
/// numbers): points finite and within [`MAX_POINT_M`] of their link's origin, axes finite and
/// non-zero, `teeth_of` a ratio, numbers set.
pub fn validate(parts: &[CarriedPart], ratios: usize) -> Result<(), FieldError> {
    for (i, part) in parts.iter().enumerate() {
        let field = format!("carried[{i}]");
        let at = format!("{field}.at");
        check_finite(&at, &part.at)?;
        check_norm(
            &at,
            &part.at,
            MAX_POINT_M,
            "m from its link: beyond any robot's reach",
        )?;
        if let Some(pulley) = &part.pulley {
            let at = format!("{field}.pulley");
            if teeth_ratio(&pulley.teeth_of, ratios).is_none() {
                return Err(FieldError::new(
                    format!("{at}.teeth_of"),
                    format!(
                        " = '{}' names no ratio: give r1 to r{ratios}, or c*r<l> with c a \
                         positive number up to {}",
                        shown(&pulley.teeth_of),
                        number(MAX_TEETH_FACTOR)
                    ),
                ));
            }
            let axis = pulley.axis.unwrap_or([0.0, 0.0, 1.0]);
            check_finite(&format!("{at}.axis"), &axis)?;
            let norm = Vector3::from(axis).norm();
            if !(norm.is_finite() && norm > 1e-9) {
                return Err(FieldError::new(
                    format!("{at}.axis"),
                    " must be a non-zero direction",
                ));
            }
            let numbers = [pulley.pitch_mm, pulley.width_mm, pulley.density_kg_m3];
            if numbers
                .iter()
                .any(|n| !n.is_some_and(|n| n.is_finite() && n >= 0.0))
            {
                return Err(FieldError::new(
                    at,
                    " has no pitch_mm, width_mm and density_kg_m3: the task was not read",
                ));
            }
        }
        let mass = (part.motor.as_ref().or(part.gearbox.as_ref())).map(|m| m.mass_kg);
        if mass.is_some_and(|m| !m.is_some_and(|m| m.is_finite() && m >= 0.0)) {
            return Err(FieldError::new(
                field,
                " has no mass_kg: the task was not read",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::model::task::TaskFile;
    use crate::testing;
    use serde_json::{json, Value};

    /// The example with carried parts, `carried[0]` changed by `edit`, read from its folder.
    fn read(edit: impl FnOnce(&mut Value)) -> Result<TaskFile, String> {
        read_task(|task| edit(&mut task["carried"][0]))
    }

    /// The example with carried parts changed by `edit`, read from its folder.
    fn read_task(edit: impl FnOnce(&mut Value)) -> Result<TaskFile, String> {
        let path = testing::repository().join("robots/examples/planar_2dof/carried_pulley.json");
        let mut value: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        edit(&mut value);
        let folder = path.parent().unwrap();
        TaskFile::from_text(&value.to_string(), "t", folder).map_err(|e| e.to_string())
    }

    /// A pulley has at least its series' teeth over the whole design space: its driver has
    /// them, and so has the pulley at the lower bound of its ratio (the example's 2 r2 teeth per
    /// driver tooth, r2 of [0.25, 40] and a 12-tooth driver make 6 of the GT2 series' 12; r1
    /// of [0.5, 100] with `r1` would too); equal counts are accepted.
    #[test]
    fn a_pulley_has_its_series_teeth_over_the_design_space() {
        let driver = read(|p| p["pulley"]["driver_teeth"] = json!(11)).unwrap_err();
        let expected = "carried[0].pulley.driver_teeth = 11 must be at least the series' 12";
        assert!(driver.contains(expected), "{driver}");
        let low = |task: &mut Value| task["transmission"]["bounds"][1] = json!([0.25, 40]);
        let error = read_task(low).unwrap_err();
        let expected = "task t: carried[0].pulley.driver_teeth = 12 makes too few teeth at the \
                        lower bound of r2: transmission.bounds[1] = [0.25, 40] gives the pulley \
                        0.25 x 2 x 12 = 6 teeth, fewer than the series' 12; raise that lower \
                        bound to at least 0.5, or driver_teeth to at least 24";
        assert_eq!(error, expected);
        let plain = read_task(|task| {
            task["carried"][0]["pulley"]["teeth_of"] = json!("r1");
            task["transmission"]["bounds"][0] = json!([0.5, 100]);
        });
        let expected = "gives the pulley 0.5 x 12 = 6 teeth, fewer than the series' 12; raise \
                        that lower bound to at least 1, or driver_teeth to at least 24";
        assert!(plain.as_ref().unwrap_err().contains(expected), "{plain:?}");
        let even = |task: &mut Value| task["transmission"]["bounds"][1] = json!([0.5, 40]);
        assert!(read_task(even).is_ok());
        let read = read_task(|task| {
            low(task);
            task["carried"][0]["pulley"]["driver_teeth"] = json!(24);
        });
        let pulley = read.unwrap().task.carried[0].pulley.clone().unwrap();
        assert_eq!(pulley.driver_teeth, 24.0);
        // A ratio the pulley does not follow may go below 1.
        let other = |task: &mut Value| task["transmission"]["bounds"][0] = json!([0.1, 100]);
        assert!(read_task(other).is_ok());
    }

    /// `c*r<l>` gives the pulley c times the teeth of `r<l>`: at 2, twice the radius and four
    /// times the mass (a disc of the belt's width); ` 2 * r2 ` reads as `2*r2`.
    #[test]
    fn a_factor_of_the_ratio_scales_the_pulleys_teeth() {
        use crate::model::Robot;
        use crate::problem::{Formulation, Space};
        let mass = |teeth_of: &str| {
            let task = read(|p| p["pulley"]["teeth_of"] = json!(teeth_of))
                .unwrap()
                .task;
            let robot = Robot::load(&task).unwrap();
            let f = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
            f.setting().carried().masses(&task.transmission.original)[0]
        };
        let (one, two) = (mass("r2"), mass("2*r2"));
        assert!((two - 4.0 * one).abs() <= 1e-12 * two, "{one} {two}");
        assert_eq!(mass(" 2 * r2 "), two);
    }

    /// A carried motor of the task's own (`of_motor`) is the part its `motors.parts` entry
    /// chooses, its mass counted once in the actuator mass; written back it reads back; an
    /// entry that names no motor, or another part, is refused naming the field.
    #[test]
    fn a_carried_motor_of_the_tasks_own_is_its_part() {
        use crate::model::Robot;
        use crate::problem::{Formulation, Space};
        let own = |task: &mut Value| {
            let part =
                |name: &str| json!({"catalogue": "../../catalogue/parts.json", "name": name});
            let parts = [
                part("Allied Motion HT02501-A00"),
                part("Allied Motion HT02003-A00"),
            ];
            task["motors"] = json!({"speed_limit_rad_s": 100.0, "parts": parts});
            task["carried"][1]["motor"] = json!({"of_motor": 1});
        };
        let task = read_task(own).unwrap().task;
        let motor = task.carried[1].motor.as_ref().unwrap();
        assert_eq!(motor.name, "Allied Motion HT02003-A00");
        assert_eq!(motor.mass_kg, Some(0.43));
        let written = serde_json::to_string(&task).unwrap();
        let folder = std::path::Path::new("/");
        let again = crate::model::task::TaskFile::from_text(&written, "t", folder).unwrap();
        assert_eq!(again.task, task);
        let robot = Robot::load(&task).unwrap();
        let f = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
        let r = &task.transmission.original;
        let pulley = f.setting().carried().masses(r)[0];
        let total = f.setting().actuator_mass_kg(r).unwrap();
        assert!((total - (0.38 + 0.43 + pulley)).abs() < 1e-12, "{total}");
        let none = read_task(|task| {
            own(task);
            task["carried"][1]["motor"]["of_motor"] = json!(2);
        });
        let expected = "carried[1].motor.of_motor = 2 names no entry of motors.parts";
        assert!(none.as_ref().unwrap_err().contains(expected), "{none:?}");
        let other = read_task(|task| {
            own(task);
            task["carried"][1]["motor"]["name"] = json!("Allied Motion HT02501-A00");
        });
        let expected = "carried[1].motor.name = 'Allied Motion HT02501-A00' is not the part of \
                        motors.parts[1], 'Allied Motion HT02003-A00'";
        assert!(other.as_ref().unwrap_err().contains(expected), "{other:?}");
    }

    /// Reading sets the series' numbers and the motor's mass; the hash leaves the catalogue's
    /// path out; bad entries are refused naming the field.
    #[test]
    fn parts_are_read_from_their_catalogues_and_checked() {
        let task = read(|_| {}).unwrap().task;
        let pulley = task.carried[0].pulley.as_ref().unwrap();
        assert_eq!(pulley.pitch_mm, Some(2.0));
        assert_eq!(pulley.density_kg_m3, Some(2700.0));
        assert_eq!(task.carried[1].motor.as_ref().unwrap().mass_kg, Some(0.38));
        let written = serde_json::to_string(&task).unwrap();
        let again: crate::model::task::Task = serde_json::from_str(&written).unwrap();
        assert_eq!(again, task);
        let mut moved = task.clone();
        moved.carried[0].pulley.as_mut().unwrap().catalogue = "/elsewhere/parts.json".into();
        let hash = |t| crate::model::identity::task_hash(t, "u");
        assert_eq!(hash(&moved), hash(&task));
        type Edit = fn(&mut Value);
        let cases: [(Edit, &str); 8] = [
            (
                |p| p["pulley"]["teeth_of"] = json!("r3"),
                "carried[0].pulley.teeth_of = 'r3' names no ratio",
            ),
            (
                |p| p["pulley"]["teeth_of"] = json!("0*r2"),
                "carried[0].pulley.teeth_of = '0*r2' names no ratio: give r1 to r2, or c*r<l> \
                 with c a positive number up to 1000",
            ),
            (
                |p| p["pulley"]["teeth_of"] = json!("2*r3"),
                "carried[0].pulley.teeth_of = '2*r3' names no ratio",
            ),
            (
                |p| p["pulley"]["teeth_of"] = json!("r2*2"),
                "carried[0].pulley.teeth_of = 'r2*2' names no ratio",
            ),
            (
                |p| p["pulley"]["driver_teeth"] = json!(8),
                "carried[0].pulley.driver_teeth = 8 must be at least the series' 12 teeth",
            ),
            (
                |p| p["pulley"]["series"] = json!("HTD"),
                "carried[0].pulley.series = 'HTD' is no belt series",
            ),
            (
                |p| p["pulley"]["width_mm"] = json!(9),
                "carried[0].pulley.width_mm = 9 conflicts with the catalogue's 6",
            ),
            (
                |p| p["motor"] = json!({"catalogue": "x.json", "name": "m"}),
                "carried[0] must give exactly one of pulley, motor and gearbox",
            ),
        ];
        for (edit, expected) in cases {
            let error = read(edit).unwrap_err();
            assert!(error.contains(expected), "{error}");
        }
    }
}
