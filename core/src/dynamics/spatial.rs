//! Spatial (6D) vector algebra in Plücker coordinates, after Featherstone, "Rigid Body Dynamics
//! Algorithms" (2008), with the angular part first.
//!
//! Everything here is expressed in one frame, at its origin; the dynamics use the world frame.
//! A motion (twist) is (angular velocity, velocity of the body point at the origin); a force
//! (wrench) is (moment about the origin, force). A rigid-body inertia is stored as its mass, first
//! moment and rotational inertia about the origin, which is also how the time derivative of an
//! inertia is stored (with mass 0).

use crate::model::chain::{MassProperties, Placement};
use nalgebra::{Matrix3, Vector3};
use std::ops::{Add, AddAssign, Mul, Sub};

/// A spatial motion vector: angular part (rad/s, or rad/s^2 for accelerations) and linear part
/// (m/s, m/s^2), in one frame at its origin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Angular part.
    pub ang: Vector3<f64>,
    /// Linear part: of the body point at the origin.
    pub lin: Vector3<f64>,
}

/// A spatial force vector: moment about the origin (N m) and force (N), in one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Force {
    /// Moment about the origin.
    pub ang: Vector3<f64>,
    /// Force.
    pub lin: Vector3<f64>,
}

/// A rigid-body inertia (or a time derivative of one) in one frame, about its origin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inertia {
    /// Mass, kg.
    pub mass: f64,
    /// First moment: mass times centre of mass, kg m.
    pub first_moment: Vector3<f64>,
    /// Rotational inertia about the origin, kg m^2 (symmetric).
    pub rotational: Matrix3<f64>,
}

impl Motion {
    /// The motion with angular part `ang` and linear part `lin`.
    pub fn new(ang: Vector3<f64>, lin: Vector3<f64>) -> Motion {
        Motion { ang, lin }
    }

    /// The spatial cross product `self x m` of two motions (Featherstone's crm).
    #[inline]
    pub fn cross(&self, m: &Motion) -> Motion {
        Motion {
            ang: self.ang.cross(&m.ang),
            lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang),
        }
    }

    /// The spatial cross product `self x* f` of a motion and a force (Featherstone's crf).
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force {
            ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin),
            lin: self.ang.cross(&f.lin),
        }
    }

    /// The power-like scalar product `self . f`.
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        self.ang.dot(&f.ang) + self.lin.dot(&f.lin)
    }
}

impl Add for Motion {
    type Output = Motion;
    #[inline]
    fn add(self, m: Motion) -> Motion {
        Motion::new(self.ang + m.ang, self.lin + m.lin)
    }
}

impl Mul<f64> for Motion {
    type Output = Motion;
    #[inline]
    fn mul(self, s: f64) -> Motion {
        Motion::new(self.ang * s, self.lin * s)
    }
}

impl Add for Force {
    type Output = Force;
    #[inline]
    fn add(self, f: Force) -> Force {
        Force {
            ang: self.ang + f.ang,
            lin: self.lin + f.lin,
        }
    }
}

impl Sub for Force {
    type Output = Force;
    #[inline]
    fn sub(self, f: Force) -> Force {
        Force {
            ang: self.ang - f.ang,
            lin: self.lin - f.lin,
        }
    }
}

impl Mul<f64> for Force {
    type Output = Force;
    #[inline]
    fn mul(self, s: f64) -> Force {
        Force {
            ang: self.ang * s,
            lin: self.lin * s,
        }
    }
}

impl Inertia {
    /// The spatial inertia of `body` (mass properties in the body frame), about the body frame's
    /// origin and in its axes.
    pub fn of_body(body: &MassProperties) -> Inertia {
        let c = body.com;
        Inertia {
            mass: body.mass,
            first_moment: c * body.mass,
            rotational: body.inertia + skew_square(&c) * (-body.mass),
        }
    }

    /// A point mass of `mass` kg at `point` (m).
    pub fn point_mass(mass: f64, point: &Vector3<f64>) -> Inertia {
        Inertia {
            mass,
            first_moment: point * mass,
            rotational: skew_square(point) * (-mass),
        }
    }

    /// This inertia, given in a body frame, expressed in the parent frame of `placement` (the
    /// body frame's pose in it).
    #[inline]
    pub fn transformed(&self, placement: &Placement) -> Inertia {
        let r = &placement.rotation;
        let p = &placement.translation;
        let h = r * self.first_moment;
        // Parallel axis from the body origin to the parent origin, at -p from it.
        let hp = h.dot(p);
        let shift = Matrix3::from_diagonal_element(2.0 * hp + self.mass * p.norm_squared())
            - h * p.transpose()
            - p * h.transpose()
            - p * p.transpose() * self.mass;
        Inertia {
            mass: self.mass,
            first_moment: h + p * self.mass,
            rotational: r * self.rotational * r.transpose() + shift,
        }
    }

    /// The spatial momentum (force-like) `I m` of motion `m`.
    #[inline]
    pub fn apply(&self, m: &Motion) -> Force {
        let h = &self.first_moment;
        Force {
            ang: self.rotational * m.ang + h.cross(&m.lin),
            lin: m.lin * self.mass - h.cross(&m.ang),
        }
    }

    /// The rate of change `m x* I - I m x` of this inertia when its body moves with motion `m`:
    /// an inertia-shaped value of mass 0 (symmetric as a 6x6 matrix).
    #[inline]
    pub fn rate(&self, m: &Motion) -> Inertia {
        let h = &self.first_moment;
        let w = &m.ang;
        let u = &m.lin;
        let wi = w.cross_matrix() * self.rotational;
        Inertia {
            mass: 0.0,
            first_moment: w.cross(h) + u * self.mass,
            rotational: wi + wi.transpose() + Matrix3::from_diagonal_element(2.0 * h.dot(u))
                - u * h.transpose()
                - h * u.transpose(),
        }
    }
}

impl AddAssign for Inertia {
    #[inline]
    fn add_assign(&mut self, other: Inertia) {
        self.mass += other.mass;
        self.first_moment += other.first_moment;
        self.rotational += other.rotational;
    }
}

/// `[c x]^2 = c c^T - |c|^2 1`.
fn skew_square(c: &Vector3<f64>) -> Matrix3<f64> {
    c * c.transpose() - Matrix3::from_diagonal_element(c.norm_squared())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix6, Rotation3, Vector6};

    fn motion(x: [f64; 6]) -> Motion {
        Motion::new(
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]),
        )
    }

    fn m6(m: &Motion) -> Vector6<f64> {
        Vector6::new(m.ang.x, m.ang.y, m.ang.z, m.lin.x, m.lin.y, m.lin.z)
    }

    fn f6(f: &Force) -> Vector6<f64> {
        Vector6::new(f.ang.x, f.ang.y, f.ang.z, f.lin.x, f.lin.y, f.lin.z)
    }

    /// The 6x6 matrix of an inertia, column by column from `apply`.
    fn matrix(inertia: &Inertia) -> Matrix6<f64> {
        let mut out = Matrix6::zeros();
        for k in 0..6 {
            let mut e = [0.0; 6];
            e[k] = 1.0;
            out.set_column(k, &f6(&inertia.apply(&motion(e))));
        }
        out
    }

    fn crm(m: &Motion) -> Matrix6<f64> {
        let mut out = Matrix6::zeros();
        out.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&m.ang.cross_matrix());
        out.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&m.ang.cross_matrix());
        out.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&m.lin.cross_matrix());
        out
    }

    fn body() -> MassProperties {
        MassProperties {
            mass: 1.7,
            com: Vector3::new(0.1, -0.2, 0.3),
            inertia: Matrix3::new(0.05, 0.001, -0.002, 0.001, 0.04, 0.003, -0.002, 0.003, 0.03),
        }
    }

    #[test]
    fn cross_products_match_the_matrix_forms() {
        let a = motion([0.3, -1.2, 0.5, 2.0, 0.1, -0.7]);
        let b = motion([-0.4, 0.9, 1.1, -0.3, 0.8, 0.2]);
        let f = Force {
            ang: Vector3::new(1.0, -2.0, 0.5),
            lin: Vector3::new(0.3, 0.2, -1.5),
        };
        assert!((m6(&a.cross(&b)) - crm(&a) * m6(&b)).norm() < 1e-14);
        // crf = -crm^T
        assert!((f6(&a.cross_force(&f)) + crm(&a).transpose() * f6(&f)).norm() < 1e-14);
    }

    #[test]
    fn inertia_is_symmetric_and_rate_is_its_derivative() {
        let inertia = Inertia::of_body(&body());
        let matrix_i = matrix(&inertia);
        assert!((matrix_i - matrix_i.transpose()).norm() < 1e-15);
        let m = motion([0.3, -1.2, 0.5, 2.0, 0.1, -0.7]);
        let expected = -crm(&m).transpose() * matrix_i - matrix_i * crm(&m);
        let rate = matrix(&inertia.rate(&m));
        assert!((rate - expected).norm() < 1e-14, "{rate} vs {expected}");
    }

    #[test]
    fn transformed_inertia_is_the_plucker_transform() {
        let rotation = Rotation3::from_euler_angles(0.3, -0.8, 2.1).into_inner();
        let translation = Vector3::new(0.4, -0.1, 0.25);
        let placement = Placement {
            rotation,
            translation,
        };
        // The parent-from-body motion transform X = [E 0; p x E, E].
        let mut x = Matrix6::zeros();
        x.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
        x.fixed_view_mut::<3, 3>(3, 3).copy_from(&rotation);
        x.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(translation.cross_matrix() * rotation));
        let inverse = x.try_inverse().unwrap();
        let body_matrix = matrix(&Inertia::of_body(&body()));
        let expected = inverse.transpose() * body_matrix * inverse;
        let got = matrix(&Inertia::of_body(&body()).transformed(&placement));
        assert!((got - expected).norm() < 1e-14);
        let direct = matrix(&Inertia::of_body(&body().transformed(&placement)));
        assert!((got - direct).norm() < 1e-14);
    }
}
