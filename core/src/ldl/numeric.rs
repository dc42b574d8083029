//! The numeric LDLᵀ of an analysed structure and solves with it.
//!
//! Up-looking and simplicial: row `k` of L is the solution of a sparse triangular system whose
//! pattern (the row subtree) was computed by the analysis, so a factorisation streams through
//! fixed index arrays and allocates nothing. Pivots are 1x1 in the analysed order, so the inertia
//! read off the signs of D is that of the matrix itself (Sylvester's law of inertia).
//!
//! A pivot lost to cancellation, no larger than [`CANCELLATION`] times the sum of the magnitudes
//! it was computed from, is rounding error of either sign: it is replaced by that bound with the
//! sign its row should have (negative for a constraint row, positive otherwise), a change of the
//! matrix far below its rounding level that IPOPT's iterative refinement corrects. This happens
//! where a fixed order meets a nearly singular leading block that pivoting would have avoided,
//! e.g. two constraint rows that differ only in variables pinned by huge barrier terms. Only a
//! pivot built from nothing at all (an empty row) makes the matrix singular.

use super::symbolic::Symbolic;
use super::LdlError;

/// A pivot `d_k = a_kk - sum_j l_kj y_j` with `|d_k| <= CANCELLATION * (|a_kk| + sum_j |l_kj
/// y_j|)` is zero to working precision: what is left after cancellation is rounding error (a few
/// hundred units in the last place, as for a sum of a few hundred terms). The test is invariant
/// to the scaling of the matrix, so tiny but exact pivots, such as `-J²/W` of a constraint row
/// whose primal neighbour carries a large barrier term, are kept.
pub const CANCELLATION: f64 = 1e-13;

/// Numbers of positive and negative pivots: the inertia of the factorised matrix.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inertia {
    /// Positive eigenvalues.
    pub positive: usize,
    /// Negative eigenvalues.
    pub negative: usize,
}

/// The values of an LDLᵀ factorisation of one structure, with its workspace.
#[derive(Clone, Debug)]
pub struct Numeric {
    /// Strictly lower L, stored by columns as the analysis laid it out.
    l: Vec<f64>,
    /// The pivots.
    d: Vec<f64>,
    /// A dense vector of length n, all zeros between calls.
    work: Vec<f64>,
    /// Inertia of the last factorisation.
    inertia: Inertia,
    /// Pivots of the last factorisation lost to cancellation and set to the rounding bound.
    regularised: usize,
}

impl Numeric {
    /// Storage for the factors of `symbolic`'s structure.
    pub fn new(symbolic: &Symbolic) -> Numeric {
        Numeric {
            l: vec![0.0; symbolic.factor_entries()],
            d: vec![0.0; symbolic.n()],
            work: vec![0.0; symbolic.n()],
            inertia: Inertia::default(),
            regularised: 0,
        }
    }

    /// Factorises the matrix whose structure `symbolic` analysed, with the values `values` in
    /// the order of that structure's entries.
    pub fn factorise(&mut self, symbolic: &Symbolic, values: &[f64]) -> Result<Inertia, LdlError> {
        if values.len() < symbolic.entries() {
            return Err(LdlError::Structure(format!(
                "{} values for {} entries",
                values.len(),
                symbolic.entries()
            )));
        }
        let (mut positive, mut regularised) = (0, 0);
        for k in 0..symbolic.n() {
            let (mut pivot, scale) = self.eliminate_row(symbolic, values, k);
            if !pivot.is_finite() {
                self.clear_work();
                return Err(LdlError::NotFinite { pivot: k });
            }
            if scale == 0.0 {
                self.clear_work();
                return Err(LdlError::Singular { pivot: k });
            }
            if pivot.abs() <= CANCELLATION * scale {
                pivot = symbolic.sign[k] * CANCELLATION * scale;
                regularised += 1;
            }
            positive += usize::from(pivot > 0.0);
            self.d[k] = pivot;
        }
        self.regularised = regularised;
        self.inertia = Inertia {
            positive,
            negative: symbolic.n() - positive,
        };
        Ok(self.inertia)
    }

    /// Computes row `k` of L into its column slots and returns the pivot `d_k` with the sum of
    /// the magnitudes of the terms it was computed from.
    fn eliminate_row(&mut self, symbolic: &Symbolic, values: &[f64], k: usize) -> (f64, f64) {
        let y = &mut self.work;
        let entries = symbolic.upper_ptr[k]..symbolic.upper_ptr[k + 1];
        for (&i, &index) in symbolic.upper_row[entries.clone()]
            .iter()
            .zip(&symbolic.upper_value[entries])
        {
            y[i] += values[index];
        }
        let mut pivot = symbolic.diagonal_value[k].map_or(0.0, |index| values[index]);
        let mut scale = pivot.abs();
        let row = symbolic.row_ptr[k]..symbolic.row_ptr[k + 1];
        for (&j, &slot) in symbolic.row_col[row.clone()]
            .iter()
            .zip(&symbolic.row_slot[row])
        {
            let yj = y[j];
            y[j] = 0.0;
            // The entries of column j above row k were computed for earlier rows.
            let above = symbolic.l_ptr[j]..slot;
            for (&i, &l_ij) in symbolic.l_row[above.clone()].iter().zip(&self.l[above]) {
                y[i] -= l_ij * yj;
            }
            let l_kj = yj / self.d[j];
            pivot -= l_kj * yj;
            scale += (l_kj * yj).abs();
            self.l[slot] = l_kj;
        }
        (pivot, scale)
    }

    /// Zeros the workspace after a factorisation stopped part-way (a row's scatter is consumed
    /// by its own elimination, so a completed row leaves it clean).
    fn clear_work(&mut self) {
        self.work.fill(0.0);
    }

    /// Inertia of the last factorisation.
    pub fn inertia(&self) -> Inertia {
        self.inertia
    }

    /// Pivots of the last factorisation that were lost to cancellation and replaced by the
    /// rounding bound with their row's sign (see the module's documentation).
    pub fn regularised_pivots(&self) -> usize {
        self.regularised
    }

    /// Solves `A x = b` in place for each of the right-hand sides stored one after the other in
    /// `rhs` (column-major, `n` rows each).
    pub fn solve_in_place(&mut self, symbolic: &Symbolic, rhs: &mut [f64]) {
        let n = symbolic.n();
        for b in rhs.chunks_exact_mut(n) {
            let x = &mut self.work;
            for (k, &row) in symbolic.order.iter().enumerate() {
                x[k] = b[row];
            }
            for j in 0..n {
                let xj = x[j];
                let column = symbolic.l_ptr[j]..symbolic.l_ptr[j + 1];
                for (&i, &l_ij) in symbolic.l_row[column.clone()].iter().zip(&self.l[column]) {
                    x[i] -= l_ij * xj;
                }
            }
            for (xk, dk) in x.iter_mut().zip(&self.d) {
                *xk /= dk;
            }
            for j in (0..n).rev() {
                let column = symbolic.l_ptr[j]..symbolic.l_ptr[j + 1];
                let mut xj = x[j];
                for (&i, &l_ij) in symbolic.l_row[column.clone()].iter().zip(&self.l[column]) {
                    xj -= l_ij * x[i];
                }
                x[j] = xj;
            }
            for (k, &row) in symbolic.order.iter().enumerate() {
                b[row] = x[k];
                x[k] = 0.0;
            }
        }
    }
}
