//! A jet's coefficients, held inline up to [`INLINE`] monomials (a linkage over one or two joints
//! to the third order, as the trajectory problem reads them) so that the arithmetic of small jets
//! allocates nothing, and on the heap beyond (the design sensitivities, once per solve). Every
//! operation moves the whole inline array: ten values keep those moves short (sixteen made them a
//! quarter of a crank-rod solve's time, `perf`).

use std::ops::{Deref, DerefMut};

/// The most coefficients held inline.
const INLINE: usize = 10;

/// The coefficients of one jet, one per monomial of its shape.
#[derive(Clone, Debug)]
pub(super) enum Coefficients {
    /// `len` values at the front of the array.
    Inline {
        values: [f64; INLINE],
        len: usize,
    },
    Heap(Vec<f64>),
}

impl Coefficients {
    /// `len` zeros.
    pub(super) fn zeros(len: usize) -> Coefficients {
        if len <= INLINE {
            Coefficients::Inline {
                values: [0.0; INLINE],
                len,
            }
        } else {
            Coefficients::Heap(vec![0.0; len])
        }
    }

    /// The values of `values`.
    pub(super) fn of(values: Vec<f64>) -> Coefficients {
        let mut coefficients = Coefficients::zeros(values.len());
        coefficients.copy_from_slice(&values);
        coefficients
    }

    /// `f` of each value of `values`.
    pub(super) fn mapped(values: &[f64], f: impl Fn(f64) -> f64) -> Coefficients {
        let mut coefficients = Coefficients::zeros(values.len());
        for (c, &v) in coefficients.iter_mut().zip(values) {
            *c = f(v);
        }
        coefficients
    }
}

impl Deref for Coefficients {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        match self {
            Coefficients::Inline { values, len } => &values[..*len],
            Coefficients::Heap(values) => values,
        }
    }
}

impl DerefMut for Coefficients {
    fn deref_mut(&mut self) -> &mut [f64] {
        match self {
            Coefficients::Inline { values, len } => &mut values[..*len],
            Coefficients::Heap(values) => values,
        }
    }
}
