//! Checks of a URDF's numbers: mass properties and origins.

use crate::model::chain::{MassProperties, Placement};
use crate::model::error::ModelError;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// The heaviest link, kg: beyond any robot (a large excavator weighs 1e5 kg), so that gravity
/// and inertia terms stay finite in the dynamics (a mass of 1e308 gave NaN torques).
pub const MAX_LINK_MASS_KG: f64 = 1e6;

/// The largest entry of a link's inertia, kg m^2.
pub const MAX_INERTIA_KGM2: f64 = 1e9;

/// The farthest an origin lies from its frame, m: beyond any robot's link.
pub const MAX_ORIGIN_M: f64 = 1e3;

/// The mass properties of `link` (of `file`) in the link's frame, checked. A massless link's
/// inertia is ignored, with a note in `notes` when it is not zero.
pub(super) fn mass_properties(
    link: &urdf_rs::Link,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<MassProperties, ModelError> {
    let element = |tag: &str| format!("link '{}' <{tag}>", link.name);
    let error = |tag: &str, message: String| ModelError::new(file, element(tag), message);
    let inertial = &link.inertial;
    let origin = pose(&inertial.origin).ok_or_else(|| error("inertial><origin", not_finite()))?;
    let mass = inertial.mass.value;
    if !(mass.is_finite() && (0.0..=MAX_LINK_MASS_KG).contains(&mass)) {
        return Err(error(
            "mass",
            format!(
                "value = {mass} must be a finite mass >= 0 kg, at most {MAX_LINK_MASS_KG} kg \
                 (beyond any robot's link, and the dynamics stay finite)"
            ),
        ));
    }
    let i = &inertial.inertia;
    let inertia = Matrix3::new(
        i.ixx, i.ixy, i.ixz, //
        i.ixy, i.iyy, i.iyz, //
        i.ixz, i.iyz, i.izz,
    );
    if !inertia.iter().all(|v| v.abs() <= MAX_INERTIA_KGM2) {
        return Err(error(
            "inertia",
            format!("has a value that is not a finite number of at most {MAX_INERTIA_KGM2} kg m^2"),
        ));
    }
    if mass == 0.0 {
        if inertia != Matrix3::zeros() {
            notes.push(format!(
                "link '{}' has mass 0 and a nonzero inertia: its inertia is ignored (a massless \
                 link has none)",
                link.name
            ));
        }
        return Ok(MassProperties::zero());
    }
    if inertia.cholesky().is_none() {
        return Err(error(
            "inertia",
            format!(
                "ixx = {}, ixy = {}, ixz = {}, iyy = {}, iyz = {}, izz = {} is not positive definite",
                i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz
            ),
        ));
    }
    if !principal_moments_physical(&inertia) {
        return Err(error(
            "inertia",
            format!(
                "ixx = {}, iyy = {}, izz = {} (ixy = {}, ixz = {}, iyz = {}) is not the inertia of a body: a principal moment exceeds the sum of the other two",
                i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz
            ),
        ));
    }
    Ok(MassProperties {
        mass,
        com: Vector3::zeros(),
        inertia,
    }
    .transformed(&origin))
}

/// Whether the principal moments of a positive definite `inertia` satisfy the triangle
/// inequality that every mass distribution does (each at most the sum of the other two, up to
/// rounding).
fn principal_moments_physical(inertia: &Matrix3<f64>) -> bool {
    let moments = inertia.symmetric_eigen().eigenvalues;
    let sum = moments.sum();
    moments.iter().all(|&m| m <= sum - m + 1e-9 * sum)
}

/// The placement of a URDF `<origin>` (rotation R = Rz(yaw) Ry(pitch) Rx(roll)), if its
/// angles are finite and its position at most [`MAX_ORIGIN_M`] from its frame.
pub(super) fn pose(origin: &urdf_rs::Pose) -> Option<Placement> {
    let [roll, pitch, yaw] = origin.rpy.0;
    let translation = Vector3::from(origin.xyz.0);
    let rotation = Rotation3::from_euler_angles(roll, pitch, yaw).into_inner();
    let angles = origin.rpy.0.iter().all(|v| v.is_finite());
    let near = translation.iter().all(|v| v.abs() <= MAX_ORIGIN_M);
    (angles && near).then_some(Placement {
        rotation,
        translation,
    })
}

/// The message for an origin with a value that is not finite or too far.
pub(super) fn not_finite() -> String {
    format!(
        "has a value that is not a finite number (a position at most {MAX_ORIGIN_M} m from its \
         frame)"
    )
}
