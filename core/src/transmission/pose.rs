//! Transmissions with pose-dependent rows (docs/model.md, section 17): G(q; r), whose linkage
//! rows are the gradients G_i(q) of their motor angles gamma_i(q), and whose constant rows are
//! those of G(r). The trajectory problem reads G with each linkage row's derivatives at every
//! node ([`PoseCoupling`]), and dG/dr_l there for the design sensitivity.

use super::design_space::invertible;
use super::linkage::{Linkage, LinkageError, RowDerivatives, RowSensitivity, RowShape};
use super::{Coupling, DesignError, Transmission};
use crate::dynamics::{Dynamics, Workspace};
use nalgebra::{DMatrix, DVector};
use std::fmt;
use std::ops::Range;

/// A linkage row of G with the symbolic parts of its derivatives.
#[derive(Clone, Debug)]
pub struct PoseRow {
    /// The row of G (motor), 0-based.
    pub motor: usize,
    /// The linkage that drives the motor.
    pub linkage: Linkage,
    /// Its derivatives to the first order (G_i), the third and the fourth.
    first: RowShape,
    third: RowShape,
    fourth: RowShape,
}

impl PoseRow {
    /// Row `motor` of G, driven by `linkage`.
    pub fn new(motor: usize, linkage: Linkage) -> PoseRow {
        PoseRow {
            motor,
            first: RowShape::new(&linkage, 1),
            third: RowShape::new(&linkage, 3),
            fourth: RowShape::new(&linkage, 4),
            linkage,
        }
    }

    /// The joints it spans: the only non-zero columns of its row of G.
    pub fn joints(&self) -> Range<usize> {
        self.linkage.joints()
    }
}

/// How far the rows' derivatives are taken at a pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depth {
    /// gamma_i and G_i: values.
    First,
    /// Also the Hessian of gamma_i and its third derivatives: the Jacobians and the
    /// Lagrangian's Hessian.
    Third,
    /// Also the fourth derivatives: the Lagrangian's Hessian where the motors' rotor inertia
    /// takes the speed term dG/dt v = v^T (d^2 gamma_i/dq^2) v.
    Fourth,
}

/// G at one pose and design, with its inverse and each linkage row's derivatives.
#[derive(Clone, Debug)]
pub struct PoseCoupling {
    /// G(q; r) and G^-1.
    pub coupling: Coupling,
    /// Each linkage row's motor (row of G) and derivatives in q.
    pub rows: Vec<(usize, RowDerivatives)>,
}

/// The derivatives of a transmission at a pose with respect to one design parameter r_l.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignDerivativeAt {
    /// dG/dr_l (row = motor, column = joint).
    pub matrix: DMatrix<f64>,
    /// d gamma_i/dr_l of each linkage row, zero for the constant rows, rad per unit of r_l.
    pub angles: DVector<f64>,
    /// d(d^2 gamma_i/dq^2)/dr_l of each linkage row that depends on r_l, with its motor.
    pub hessians: Vec<(usize, DMatrix<f64>)>,
}

/// Why a transmission has no G at a pose.
#[derive(Clone, Debug, PartialEq)]
pub enum PoseError {
    /// A linkage does not close (or a number of it is not positive) at the pose.
    Linkage {
        /// The motor (row of G), 0-based.
        motor: usize,
        /// What its geometry lacks.
        error: LinkageError,
    },
    /// G(q) is singular at the pose (some joint motion turns no motor), or it or its inverse
    /// is not finite.
    Singular,
}

impl fmt::Display for PoseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PoseError::Linkage { motor, error } => {
                write!(
                    f,
                    "the linkage of motor {} (transmission.matrix[{motor}]): {error}",
                    motor + 1
                )
            }
            PoseError::Singular => f.write_str("G(q) is singular or not finite: it has no inverse"),
        }
    }
}

impl std::error::Error for PoseError {}

impl Transmission {
    /// The linkage rows, in the order of their motors; empty for a constant G(r).
    pub fn linkages(&self) -> &[PoseRow] {
        &self.linkages
    }

    /// Whether some row of G depends on the pose.
    pub fn is_pose_dependent(&self) -> bool {
        !self.linkages.is_empty()
    }

    /// G(q; r) with its inverse and the linkage rows' derivatives to `depth`, at pose `q` (rad)
    /// and design `r` (not checked), on the chain of `dynamics`.
    pub fn at_pose(
        &self,
        r: &[f64],
        (dynamics, data): (&Dynamics, &mut Workspace),
        q: &[f64],
        depth: Depth,
    ) -> Result<PoseCoupling, PoseError> {
        let mut matrix = self.matrix(r);
        let mut rows = Vec::with_capacity(self.linkages.len());
        for row in &self.linkages {
            let shape = match depth {
                Depth::First => &row.first,
                Depth::Third => &row.third,
                Depth::Fourth => &row.fourth,
            };
            let derivatives = RowDerivatives::of(&row.linkage, shape, dynamics, data, (q, r))
                .map_err(|error| PoseError::Linkage {
                    motor: row.motor,
                    error,
                })?;
            matrix.set_row(row.motor, &derivatives.gradient.transpose());
            rows.push((row.motor, derivatives));
        }
        let coupling = Coupling::new(matrix).ok_or(PoseError::Singular)?;
        Ok(PoseCoupling { coupling, rows })
    }

    /// Each motor's angle at pose `q` (rad) and design `r`: gamma_i(q) for a linkage row, G_i q
    /// for a constant one (zero at q = 0).
    pub fn motor_angles(
        &self,
        r: &[f64],
        (dynamics, data): (&Dynamics, &mut Workspace),
        q: &[f64],
    ) -> Result<Vec<f64>, PoseError> {
        let mut angles: Vec<f64> = (self.matrix(r) * nalgebra::DVector::from_column_slice(q))
            .iter()
            .copied()
            .collect();
        let at = self.at_pose(r, (dynamics, data), q, Depth::First)?;
        for (motor, row) in at.rows {
            angles[motor] = row.angle;
        }
        Ok(angles)
    }

    /// dG/dr_l at pose `q` and design `r` for every design parameter l: the constant rows'
    /// derivatives and the linkage rows' sensitivities there; with each linkage row's
    /// d gamma_i/dr_l (zero for the constant rows).
    pub fn design_derivatives_at(
        &self,
        r: &[f64],
        (dynamics, data): (&Dynamics, &mut Workspace),
        q: &[f64],
    ) -> Result<Vec<DesignDerivativeAt>, PoseError> {
        let mut derivatives: Vec<DesignDerivativeAt> = (0..self.num_ratios())
            .map(|l| DesignDerivativeAt {
                matrix: self.matrix_derivative(l),
                angles: DVector::zeros(self.dof),
                hessians: Vec::new(),
            })
            .collect();
        for row in &self.linkages {
            let sensitivity =
                RowSensitivity::of(&row.linkage, dynamics, data, (q, r)).map_err(|error| {
                    PoseError::Linkage {
                        motor: row.motor,
                        error,
                    }
                })?;
            let parameters = sensitivity.parameters.iter().enumerate();
            for (p, &l) in parameters {
                let derivative = &mut derivatives[l];
                (derivative.matrix).set_row(row.motor, &sensitivity.gradient[p].transpose());
                derivative.angles[row.motor] = sensitivity.angle[p];
                (derivative.hessians).push((row.motor, sensitivity.hessian[p].clone()));
            }
        }
        Ok(derivatives)
    }

    /// The coupling at a valid design `r` and pose `q`: G(r) itself for a constant
    /// transmission, G(q; r) for a pose-dependent one; the error names the motor whose linkage
    /// does not close or whose screw leaves its stroke, at `pose` (words such as "the start").
    pub fn coupling_at(
        &self,
        r: &[f64],
        (dynamics, q): (&Dynamics, &[f64]),
        pose: &str,
    ) -> Result<Coupling, DesignError> {
        if !self.is_pose_dependent() {
            return self.coupling(r);
        }
        self.check_design(r)?;
        let mut data = dynamics.workspace();
        let at = self
            .at_pose(r, (dynamics, &mut data), q, Depth::First)
            .map_err(|error| DesignError::new(format!("at {pose}, {error}")))?;
        invertible(at.coupling.matrix(), &format!("G(q) at {pose}"))?;
        for (motor, row) in &at.rows {
            let linkage = &self.linkages.iter().find(|l| l.motor == *motor);
            let Some(linkage) = linkage.map(|l| &l.linkage) else {
                continue;
            };
            let (Some([min, max]), Some(scale)) = (linkage.stroke(), linkage.length_per_angle(r))
            else {
                continue;
            };
            let length = row.angle * scale;
            if !(min..=max).contains(&length) {
                return Err(DesignError::new(format!(
                    "at {pose}, the screw of motor {} (transmission.matrix[{motor}]) is {length:.6} m \
                     long, outside its stroke [{min}, {max}] m",
                    motor + 1
                )));
            }
        }
        Ok(at.coupling)
    }
}
