//! G(r) and dG/dr_i (docs/model.md, section 3), and [`Coupling`]: G with its inverse at one
//! design, mapping torques (N m) and speeds (rad/s) between motors and joints.

use super::design_space::DesignError;
use super::entry::Entry;
use super::Transmission;
use nalgebra::{DMatrix, DVector};

impl Transmission {
    /// G(r) (row = motor, column = joint). Does not check the design.
    ///
    /// # Panics
    /// If `r` has fewer values than the transmission has ratios (a programming error: designs
    /// from outside are checked with [`Transmission::check_design`] first).
    pub fn matrix(&self, r: &[f64]) -> DMatrix<f64> {
        assert!(
            r.len() >= self.num_ratios(),
            "Transmission::matrix: {} ratios given, {} needed",
            r.len(),
            self.num_ratios()
        );
        DMatrix::from_row_iterator(
            self.dof,
            self.dof,
            self.entries.iter().map(|entry| entry.value(r)),
        )
    }

    /// dG/dr_i for the 0-based ratio index i: constant, since G is affine in r (entries +-1 where
    /// r_i appears, 0 elsewhere; all zero for an index past the last ratio).
    pub fn matrix_derivative(&self, i: usize) -> DMatrix<f64> {
        DMatrix::from_row_iterator(
            self.dof,
            self.dof,
            self.entries.iter().map(|entry| match *entry {
                Entry::Ratio { index, scale } if index == i => scale,
                _ => 0.0,
            }),
        )
    }

    /// The coupling at a valid design: G(r) and its inverse, computed once.
    pub fn coupling(&self, r: &[f64]) -> Result<Coupling, DesignError> {
        self.check_design(r)?;
        Coupling::new(self.matrix(r)).ok_or_else(|| {
            DesignError::new(
                "G(r) is not invertible: its LU factorisation failed or gave no finite inverse"
                    .to_owned(),
            )
        })
    }
}

/// G at one design with its inverse: maps torques and speeds between motors and joints.
#[derive(Clone, Debug)]
pub struct Coupling {
    matrix: DMatrix<f64>,
    inverse: DMatrix<f64>,
}

impl Coupling {
    /// G with its inverse, None where G is singular or either is not finite (G is checked
    /// before it is factorised).
    pub fn new(matrix: DMatrix<f64>) -> Option<Coupling> {
        let finite = |m: &DMatrix<f64>| m.iter().all(|v| v.is_finite());
        if !finite(&matrix) {
            return None;
        }
        let inverse = matrix.clone().try_inverse().filter(finite)?;
        Some(Coupling { matrix, inverse })
    }

    /// G (row = motor, column = joint).
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.matrix
    }

    /// G^-1.
    pub fn inverse(&self) -> &DMatrix<f64> {
        &self.inverse
    }

    /// Joint torques tau = G^T tau_u, N m.
    ///
    /// # Panics
    /// If the length is not the number of motors.
    pub fn joint_torques(&self, motor_torques: &[f64]) -> Vec<f64> {
        let tau_u = DVector::from_column_slice(motor_torques);
        (self.matrix.tr_mul(&tau_u)).as_slice().to_vec()
    }

    /// Motor torques tau_u = G^-T tau, N m.
    ///
    /// # Panics
    /// If the length is not the number of joints.
    pub fn motor_torques(&self, joint_torques: &[f64]) -> Vec<f64> {
        let tau = DVector::from_column_slice(joint_torques);
        (self.inverse.tr_mul(&tau)).as_slice().to_vec()
    }

    /// Motor speeds qd_u = G qd, rad/s.
    ///
    /// # Panics
    /// If the length is not the number of joints.
    pub fn motor_speeds(&self, joint_speeds: &[f64]) -> Vec<f64> {
        let qd = DVector::from_column_slice(joint_speeds);
        (&self.matrix * qd).as_slice().to_vec()
    }
}

#[cfg(test)]
mod tests {
    use crate::transmission::fixtures::belt_arm;
    use nalgebra::DMatrix;

    #[test]
    fn matrix_derivative_matches_finite_differences() {
        let t = belt_arm();
        let r = [7.3, 4.4, 2.1, 1.7];
        let h = 1e-6;
        for i in 0..t.num_ratios() {
            let (mut plus, mut minus) = (r, r);
            plus[i] += h;
            minus[i] -= h;
            let fd = (t.matrix(&plus) - t.matrix(&minus)) / (2.0 * h);
            assert!((fd - t.matrix_derivative(i)).amax() < 1e-8, "ratio {i}");
        }
        assert_eq!(t.matrix_derivative(3)[(3, 3)], -1.0);
        assert_eq!(t.matrix_derivative(4), DMatrix::zeros(4, 4));
    }

    #[test]
    fn coupling_maps_torques_and_speeds_both_ways() {
        let coupling = belt_arm().coupling(&[7.0, 5.0, 2.0, 2.5]).unwrap();
        let identity = coupling.matrix() * coupling.inverse();
        assert!((identity - DMatrix::identity(4, 4)).norm() < 1e-14);
        let tau_u = [0.3, -1.2, 0.7, 1.5];
        let back = coupling.motor_torques(&coupling.joint_torques(&tau_u));
        assert!(back.iter().zip(&tau_u).all(|(a, b)| (a - b).abs() < 1e-12));
        let qd = [0.5, -0.25, 2.0, 1.0];
        let w = coupling.motor_speeds(&qd);
        assert_eq!(w[0], 7.0 * 0.5);
        assert_eq!(w[1], 5.0 * (0.5 - 0.25));
    }
}
