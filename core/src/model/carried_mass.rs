//! The parts a task's links carry (`super::carried`) as mass on the robot's bodies:
//! [`CarriedModel`] places them and gives their mass properties at a design r and their
//! derivatives in r; [`CarriedMassAt`] is a part's mass at a design as results record it, and
//! [`motor_parts_mass_kg`] the mass of the motors a task chooses from catalogues.
//!
//! A pulley is a solid disc of the belt's width w about its axis n, of pitch radius
//! R = r_l c (c = z_d p / (2 pi)): mass m = rho pi w R^2, inertia about its centre
//! I = I_axis n n^T + I_diam (E - n n^T) with I_axis = m R^2 / 2 and
//! I_diam = m (3 R^2 + w^2) / 12. A motor or a gearbox is a point mass (docs/model.md,
//! section 18).

use super::carried::{teeth_ratio, CarriedPart};
use super::catalogue::Catalogue;
use super::chain::{Chain, MassProperties};
use super::motor_parts::PartChoice;
use crate::text::shown;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A carried part's mass at one design, as results and `check` record it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriedMassAt {
    /// The link it is fixed to.
    pub link: String,
    /// `pulley`, `motor` or `gearbox`.
    pub kind: String,
    /// The belt series' or the part's name.
    pub name: String,
    /// Its mass at the design, kg.
    pub mass_kg: f64,
}

/// The mass of the motors a task chooses from catalogues (`motors.parts`), kg: None without
/// parts, or where a catalogue cannot be read (a task of another machine) or gives no mass.
pub fn motor_parts_mass_kg(parts: Option<&[PartChoice]>) -> Option<f64> {
    let mut total = 0.0;
    for part in parts? {
        let catalogue = Catalogue::load(&part.catalogue).ok()?;
        total += catalogue.motor(&part.name)?.mass_kg?;
    }
    Some(total)
}

/// How a part's mass follows the design.
#[derive(Clone, Debug, PartialEq)]
enum Mass {
    /// A point mass, kg.
    Fixed(f64),
    /// A disc of radius R = r_l * `radius_per_ratio` (m), width `width_m` and density
    /// `density` (kg/m^3) about the unit `axis` (body frame).
    Pulley {
        ratio: usize,
        radius_per_ratio: f64,
        width_m: f64,
        density: f64,
        axis: Vector3<f64>,
    },
}

/// A part placed on a body of the chain.
#[derive(Clone, Debug, PartialEq)]
struct PartOnBody {
    body: usize,
    /// Its centre in the body's frame, m.
    centre: Vector3<f64>,
    mass: Mass,
}

/// The task's carried parts on the robot's bodies: their mass properties at a design and
/// their derivatives in it. Empty for a task without `carried`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CarriedModel {
    parts: Vec<PartOnBody>,
}

impl CarriedModel {
    /// Places `parts` (as read) on the bodies of `chain`: an error names a link the chain does
    /// not have or one fixed to the base, where a part moves nothing.
    pub fn on_chain(
        parts: &[CarriedPart],
        chain: &Chain,
        ratios: usize,
    ) -> Result<CarriedModel, String> {
        let mut placed = Vec::with_capacity(parts.len());
        for (i, part) in parts.iter().enumerate() {
            let field = format!("carried[{i}]");
            let frame = chain.links.iter().find(|l| l.name == part.link);
            let Some(frame) = frame else {
                return Err(format!(
                    "{field}.link = '{}' is no link of the robot",
                    shown(&part.link)
                ));
            };
            let Some(body) = frame.body else {
                return Err(format!(
                    "{field}.link = '{}' is fixed to the base: a part there moves nothing; \
                     leave it out",
                    shown(&part.link)
                ));
            };
            let centre = frame.placement.apply(&Vector3::from(part.at));
            let mass = match (&part.pulley, &part.motor, &part.gearbox) {
                (Some(p), _, _) => {
                    let given = p.axis.map(|a| frame.placement.rotation * Vector3::from(a));
                    let axis = given.unwrap_or(chain.bodies[body].axis).normalize();
                    let read = |n: Option<f64>| n.ok_or_else(|| format!("{field}: not read"));
                    let (ratio, factor) = teeth_ratio(&p.teeth_of, ratios)
                        .ok_or_else(|| format!("{field}.pulley.teeth_of names no ratio"))?;
                    let teeth_per_ratio = factor * p.driver_teeth;
                    Mass::Pulley {
                        ratio,
                        radius_per_ratio: teeth_per_ratio * read(p.pitch_mm)? * 1e-3 / (2.0 * PI),
                        width_m: read(p.width_mm)? * 1e-3,
                        density: read(p.density_kg_m3)?,
                        axis,
                    }
                }
                (None, Some(m), _) | (None, None, Some(m)) => {
                    Mass::Fixed(m.mass_kg.ok_or_else(|| format!("{field}: not read"))?)
                }
                (None, None, None) => return Err(format!("{field} gives no part")),
            };
            placed.push(PartOnBody { body, centre, mass });
        }
        Ok(CarriedModel { parts: placed })
    }

    /// Whether there are no parts.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty()
    }

    /// Each part's mass at design r, kg, in the task's order.
    pub fn masses(&self, r: &[f64]) -> Vec<f64> {
        (self.parts.iter())
            .map(|part| part.properties(r, None).mass)
            .collect()
    }

    /// Each of `parts` (the task's, which this model places) with its mass at design r.
    pub fn masses_at(&self, parts: &[CarriedPart], r: &[f64]) -> Vec<CarriedMassAt> {
        (parts.iter().zip(self.masses(r)))
            .map(|(part, mass_kg)| CarriedMassAt {
                link: part.link.clone(),
                kind: part.kind().to_owned(),
                name: part.name().to_owned(),
                mass_kg,
            })
            .collect()
    }

    /// Each part's body and mass properties (in the body's frame) at design r.
    pub fn mass_properties(&self, r: &[f64]) -> Vec<(usize, MassProperties)> {
        (self.parts.iter())
            .map(|part| (part.body, part.properties(r, None)))
            .collect()
    }

    /// The derivative in r_l of the parts' mass properties at design r, for the parts that
    /// depend on r_l (empty if none): the mass and inertia fields hold dm/dr_l and dI/dr_l at
    /// the unchanged centre, as the spatial inertia is linear in them.
    pub fn derivative(&self, r: &[f64], l: usize) -> Vec<(usize, MassProperties)> {
        (self.parts.iter())
            .filter(|part| matches!(part.mass, Mass::Pulley { ratio, .. } if ratio == l))
            .map(|part| (part.body, part.properties(r, Some(l))))
            .collect()
    }
}

impl PartOnBody {
    /// Its mass properties at r, or with `derivative` their derivative in that r_l.
    fn properties(&self, r: &[f64], derivative: Option<usize>) -> MassProperties {
        let (mass, inertia) = match &self.mass {
            Mass::Fixed(mass) => match derivative {
                None => (*mass, Matrix3::zeros()),
                Some(_) => (0.0, Matrix3::zeros()),
            },
            Mass::Pulley {
                ratio,
                radius_per_ratio: c,
                width_m: w,
                density,
                axis,
            } => {
                let radius = r[*ratio] * c;
                let m = density * PI * w * radius * radius;
                let (axial, diametral) = (
                    m * radius * radius / 2.0,
                    m * (3.0 * radius * radius + w * w) / 12.0,
                );
                let (m, axial, diametral) = match derivative {
                    None => (m, axial, diametral),
                    Some(_) => {
                        // dR/dr_l = c.
                        let dm = 2.0 * density * PI * w * radius * c;
                        let d_axial = (dm * radius * radius + 2.0 * m * radius * c) / 2.0;
                        let d_diametral =
                            (dm * (3.0 * radius * radius + w * w) + 6.0 * m * radius * c) / 12.0;
                        (dm, d_axial, d_diametral)
                    }
                };
                let along = axis * axis.transpose();
                let inertia = along * axial + (Matrix3::identity() - along) * diametral;
                (m, inertia)
            }
        };
        MassProperties {
            mass,
            com: self.centre,
            inertia,
        }
    }
}
