//! One linkage row's derivatives at a pose, as the trajectory problem reads them: the motor angle
//! gamma_i(q), its gradient G_i(q) (the row of G), its Hessian, and its third and fourth
//! derivatives contracted along given joint vectors, dense over every joint (zero outside the
//! joints the linkage spans).

use super::{Linkage, LinkageError, Variables};
use crate::dynamics::{Dynamics, Workspace};
use crate::jet::{JetShape, MAX_ORDER};
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// gamma_i and its derivatives in q at one pose and design (rad, rad per rad, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct RowDerivatives {
    /// The motor angle gamma_i(q), rad.
    pub angle: f64,
    /// G_i(q) = d gamma_i / dq, one entry per joint.
    pub gradient: DVector<f64>,
    /// d^2 gamma_i / dq^2, n x n.
    pub hessian: DMatrix<f64>,
    /// The joints the linkage spans, and its third and fourth derivatives over them, dense
    /// (span^3 and span^4 values, the first index fastest); empty below order 3 and 4.
    span: Range<usize>,
    third: Vec<f64>,
    fourth: Vec<f64>,
}

/// The symbolic part of a row's derivatives, made once per linkage and order: its jets'
/// variables (the joints it spans) and their shape.
#[derive(Clone, Debug)]
pub struct RowShape {
    variables: Variables,
    shape: JetShape,
    /// For each monomial of three or four joints, the indices of the dense tensor its
    /// derivative fills: every ordering of its joints.
    placements: Vec<Vec<usize>>,
}

impl RowShape {
    /// The shape of `linkage`'s derivatives up to `order` (1 to 4; the Hessian is zero below 2).
    ///
    /// # Panics
    /// If `order` is not 1, 2, 3 or 4.
    pub fn new(linkage: &Linkage, order: usize) -> RowShape {
        assert!((1..=MAX_ORDER).contains(&order), "orders 1 to 4");
        let variables = Variables {
            joints: linkage.joints(),
            parameters: Vec::new(),
        };
        let shape = variables.shape(order);
        let width = variables.joints.len();
        let placements = (shape.monomials().iter())
            .map(|monomial| match monomial.len() {
                3 | 4 => (orderings(monomial).iter())
                    .map(|ordering| ordering.iter().rev().fold(0, |acc, &i| acc * width + i))
                    .collect(),
                _ => Vec::new(),
            })
            .collect();
        RowShape {
            variables,
            shape,
            placements,
        }
    }
}

impl RowDerivatives {
    /// The derivatives of `linkage`'s motor angle at pose `q` and design `r` to the order of
    /// `shape` (made for this linkage), on the chain of `dynamics`.
    pub fn of(
        linkage: &Linkage,
        RowShape {
            variables,
            shape,
            placements,
        }: &RowShape,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
    ) -> Result<RowDerivatives, LinkageError> {
        let order = shape.order();
        let jet = linkage.angle(dynamics, data, (q, r), variables, shape)?;
        let (n, span) = (q.len(), variables.joints.clone());
        let width = span.len();
        let mut derivatives = RowDerivatives {
            angle: jet.value(),
            gradient: DVector::zeros(n),
            hessian: DMatrix::zeros(n, n),
            span,
            third: vec![0.0; if order >= 3 { width.pow(3) } else { 0 }],
            fourth: vec![0.0; if order >= 4 { width.pow(4) } else { 0 }],
        };
        for (m, monomial) in shape.monomials().iter().enumerate() {
            let value = jet.coefficients()[m] * shape.multiplicity_factorial(m);
            derivatives.place(monomial, &placements[m], value);
        }
        Ok(derivatives)
    }

    /// Puts the derivative of sorted local joints `monomial` at every ordering of its indices
    /// (`placements` in the dense tensors of three or four joints).
    fn place(&mut self, monomial: &[usize], placements: &[usize], value: f64) {
        let start = self.span.start;
        match *monomial {
            [i] => self.gradient[start + i] = value,
            [i, j] => {
                self.hessian[(start + i, start + j)] = value;
                self.hessian[(start + j, start + i)] = value;
            }
            [_, _, _] | [_, _, _, _] => {
                let tensor = if monomial.len() == 3 {
                    &mut self.third
                } else {
                    &mut self.fourth
                };
                for &index in placements {
                    tensor[index] = value;
                }
            }
            _ => {}
        }
    }

    /// Sum_l x_l d^3 gamma / dq_j dq_k dq_l, n x n: the Hessian's derivative along the joint
    /// vector `x` (zero if the derivatives were taken to order 2 only).
    pub fn third_along(&self, x: &[f64]) -> DMatrix<f64> {
        let (start, width) = (self.span.start, self.span.len());
        let mut result = DMatrix::zeros(x.len(), x.len());
        if self.third.is_empty() {
            return result;
        }
        for l in 0..width {
            let along = x[start + l];
            for k in 0..width {
                for j in 0..width {
                    let value = self.third[j + width * (k + width * l)];
                    result[(start + j, start + k)] += along * value;
                }
            }
        }
        result
    }

    /// Sum_{l,m} x_l y_m d^4 gamma / dq_j dq_k dq_l dq_m, n x n (zero below order 4).
    pub fn fourth_along(&self, x: &[f64], y: &[f64]) -> DMatrix<f64> {
        let (start, width) = (self.span.start, self.span.len());
        let mut result = DMatrix::zeros(x.len(), x.len());
        if self.fourth.is_empty() {
            return result;
        }
        for m in 0..width {
            for l in 0..width {
                let along = x[start + l] * y[start + m];
                for k in 0..width {
                    for j in 0..width {
                        let value = self.fourth[j + width * (k + width * (l + width * m))];
                        result[(start + j, start + k)] += along * value;
                    }
                }
            }
        }
        result
    }

    /// The motor's speed G_i(q) v, rad/s, for joint speeds `v`.
    pub fn speed(&self, v: &[f64]) -> f64 {
        self.gradient.iter().zip(v).map(|(g, v)| g * v).sum()
    }

    /// The motor's acceleration G_i q-ddot + v^T (d^2 gamma / dq^2) v, rad/s^2: the joint
    /// accelerations `a` through G and the speed term dG_i/dt v.
    pub fn acceleration(&self, v: &[f64], a: &[f64]) -> f64 {
        let v = DVector::from_column_slice(v);
        self.speed(a) + v.dot(&(&self.hessian * &v))
    }
}

/// The derivatives of a row's angle, G_i and Hessian with respect to its design parameters, at a
/// pose: what the design sensitivity dJ*/dr needs of a linkage row.
#[derive(Clone, Debug, PartialEq)]
pub struct RowSensitivity {
    /// The design parameters' indices in r, one per entry of the lists below.
    pub parameters: Vec<usize>,
    /// d gamma_i / dr_p, rad per unit of r_p.
    pub angle: Vec<f64>,
    /// d G_i / dr_p, one vector of n joints each.
    pub gradient: Vec<DVector<f64>>,
    /// d (d^2 gamma_i / dq^2) / dr_p, n x n each.
    pub hessian: Vec<DMatrix<f64>>,
}

impl RowSensitivity {
    /// The first derivatives in its design parameters of `linkage`'s angle, row of G and
    /// Hessian at pose `q` and design `r`.
    pub fn of(
        linkage: &Linkage,
        dynamics: &Dynamics,
        data: &mut Workspace,
        (q, r): (&[f64], &[f64]),
    ) -> Result<RowSensitivity, LinkageError> {
        let variables = Variables {
            joints: linkage.joints(),
            parameters: linkage.parameters(),
        };
        let shape = variables.shape(3);
        let jet = linkage.angle(dynamics, data, (q, r), &variables, &shape)?;
        let (n, span, count) = (
            q.len(),
            variables.joints.clone(),
            variables.parameters.len(),
        );
        let mut sensitivity = RowSensitivity {
            parameters: variables.parameters.clone(),
            angle: vec![0.0; count],
            gradient: vec![DVector::zeros(n); count],
            hessian: vec![DMatrix::zeros(n, n); count],
        };
        for (m, monomial) in shape.monomials().iter().enumerate() {
            let Some((&last, joints)) = monomial.split_last() else {
                continue;
            };
            let Some(p) = last.checked_sub(span.len()) else {
                continue;
            };
            let value = jet.coefficients()[m] * shape.multiplicity_factorial(m);
            match *joints {
                [] => sensitivity.angle[p] = value,
                [i] => sensitivity.gradient[p][span.start + i] = value,
                [i, j] => {
                    sensitivity.hessian[p][(span.start + i, span.start + j)] = value;
                    sensitivity.hessian[p][(span.start + j, span.start + i)] = value;
                }
                _ => {}
            }
        }
        Ok(sensitivity)
    }
}

/// Every distinct ordering of a sorted multiset of indices.
fn orderings(sorted: &[usize]) -> Vec<Vec<usize>> {
    let mut all = vec![sorted.to_vec()];
    let mut current = sorted.to_vec();
    // Next permutation in lexicographic order, from the sorted (smallest) one.
    loop {
        let Some(i) = (1..current.len())
            .rev()
            .find(|&i| current[i - 1] < current[i])
        else {
            return all;
        };
        let j = (i..current.len())
            .rev()
            .find(|&j| current[j] > current[i - 1])
            .unwrap_or(i);
        current.swap(i - 1, j);
        current[i..].reverse();
        all.push(current.clone());
    }
}
