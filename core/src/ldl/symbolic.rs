//! The analysis of one sparsity structure, done once: the elimination order, the elimination
//! tree, the pattern of L and every index map the numeric factorisation needs, so that it only
//! streams through precomputed arrays.

use super::ordering::{elimination_order, Pattern, RowKind};
use super::LdlError;

/// An upper triangle in compressed sparse rows with 1-based indices, as IPOPT hands it to a
/// Pardiso-style solver: row `i` holds the columns `ja[ia[i] - 1 .. ia[i + 1] - 1]`, each `>= i`.
#[derive(Clone, Copy, Debug)]
pub struct UpperCsr<'a> {
    /// Row starts, length `n + 1`, 1-based.
    pub ia: &'a [i32],
    /// Column of each entry, 1-based.
    pub ja: &'a [i32],
}

/// Everything about a structure that does not depend on the values.
#[derive(Clone, Debug, PartialEq)]
pub struct Symbolic {
    /// `order[k]`: the original row of pivot `k`.
    pub(super) order: Vec<usize>,
    /// What the order assumed of each original row's diagonal.
    kinds: Vec<RowKind>,
    /// The sign each pivot should have: -1 for constraint rows, +1 for the others.
    pub(super) sign: Vec<f64>,
    /// Upper triangle of the permuted matrix by columns: rows `< k` of column `k` ...
    pub(super) upper_ptr: Vec<usize>,
    pub(super) upper_row: Vec<usize>,
    /// ... and the index of each entry's value in the caller's value array.
    pub(super) upper_value: Vec<usize>,
    /// Index of each pivot's diagonal value in the caller's array, when the structure has one.
    pub(super) diagonal_value: Vec<Option<usize>>,
    /// The diagonal value of each row the order took for non-zero, in elimination order (none:
    /// no diagonal in the structure).
    regular_diagonals: Vec<Option<usize>>,
    /// Column starts of the strictly lower factor L (length `n + 1`) and the row of each entry.
    pub(super) l_ptr: Vec<usize>,
    pub(super) l_row: Vec<usize>,
    /// Row `k` of L: the columns of its entries in increasing order and where each is stored.
    pub(super) row_ptr: Vec<usize>,
    pub(super) row_col: Vec<usize>,
    pub(super) row_slot: Vec<usize>,
    /// Entries in the caller's structure.
    pub(super) entries: usize,
}

impl Symbolic {
    /// Analyses the structure of a symmetric matrix given by its upper triangle, with `values`
    /// (one per entry) telling which diagonals are zero. Constraint rows (zero diagonal until
    /// IPOPT regularises them) are the trailing rows whose upper triangle holds only the
    /// diagonal: IPOPT orders its KKT matrix as primal variables and slacks first, then the rows
    /// of the equality and inequality constraints.
    pub fn analyse(n: usize, matrix: UpperCsr<'_>, values: &[f64]) -> Result<Symbolic, LdlError> {
        let (kinds, entries) = Symbolic::assumed_kinds(n, matrix, values)?;
        Symbolic::analyse_as(n, matrix, kinds, entries)
    }

    /// What [`Symbolic::analyse`] assumes of each row of a checked structure, with the number of
    /// its entries: the result depends on the structure and these kinds alone.
    pub(super) fn assumed_kinds(
        n: usize,
        matrix: UpperCsr<'_>,
        values: &[f64],
    ) -> Result<(Vec<RowKind>, usize), LdlError> {
        let entries = check_structure(n, matrix)?;
        check_values(entries, values)?;
        let mut kinds = constraint_rows(n, matrix);
        mark_zero_diagonals(matrix, values, &mut kinds);
        Ok((kinds, entries))
    }

    /// Whether a new matrix of this structure has a zero diagonal where the analysis assumed a
    /// non-zero one, so that its order may hit an exactly zero pivot.
    /// Allocates nothing.
    pub fn needs_reanalysis(&self, values: &[f64]) -> bool {
        self.regular_diagonals
            .iter()
            .any(|&index| index.map_or(0.0, |i| values.get(i).copied().unwrap_or(1.0)) == 0.0)
    }

    /// Analyses again with the zero diagonals of `values` added to those assumed before.
    pub fn reanalyse(&self, matrix: UpperCsr<'_>, values: &[f64]) -> Result<Symbolic, LdlError> {
        let kinds = self.kinds_with_zeros_of(matrix, values)?;
        Symbolic::analyse_as(self.n(), matrix, kinds, self.entries)
    }

    /// What [`Symbolic::reanalyse`] assumes of each row: this analysis's kinds with the zero
    /// diagonals of `values` added.
    pub(super) fn kinds_with_zeros_of(
        &self,
        matrix: UpperCsr<'_>,
        values: &[f64],
    ) -> Result<Vec<RowKind>, LdlError> {
        check_values(self.entries, values)?;
        let mut kinds = self.kinds.clone();
        mark_zero_diagonals(matrix, values, &mut kinds);
        Ok(kinds)
    }

    /// The analysis of a checked structure of `entries` entries under the assumed `kinds`.
    pub(super) fn analyse_as(
        n: usize,
        matrix: UpperCsr<'_>,
        kinds: Vec<RowKind>,
        entries: usize,
    ) -> Result<Symbolic, LdlError> {
        let pattern = symmetric_pattern(n, matrix);
        let order = elimination_order(&pattern, &kinds);
        let sign = order
            .iter()
            .map(|&row| {
                if kinds[row] == RowKind::Constraint {
                    -1.0
                } else {
                    1.0
                }
            })
            .collect();
        let mut position = vec![0usize; n];
        for (k, &row) in order.iter().enumerate() {
            position[row] = k;
        }
        let mut symbolic = Symbolic {
            order,
            kinds,
            sign,
            upper_ptr: Vec::new(),
            upper_row: Vec::new(),
            upper_value: Vec::new(),
            diagonal_value: vec![None; n],
            regular_diagonals: Vec::new(),
            l_ptr: Vec::new(),
            l_row: Vec::new(),
            row_ptr: Vec::new(),
            row_col: Vec::new(),
            row_slot: Vec::new(),
            entries,
        };
        symbolic.permute(matrix, &position);
        symbolic.regular_diagonals = symbolic
            .order
            .iter()
            .zip(&symbolic.diagonal_value)
            .filter(|&(&row, _)| symbolic.kinds[row] == RowKind::Regular)
            .map(|(_, &index)| index)
            .collect();
        symbolic.factor_pattern();
        Ok(symbolic)
    }

    /// What the analysis assumed of each original row's diagonal.
    pub(super) fn kinds(&self) -> &[RowKind] {
        &self.kinds
    }

    /// Dimension of the matrix.
    pub fn n(&self) -> usize {
        self.order.len()
    }

    /// Entries of the strictly lower factor L.
    pub fn factor_entries(&self) -> usize {
        self.l_row.len()
    }

    /// Entries of the analysed structure (the length its value arrays must have).
    pub fn entries(&self) -> usize {
        self.entries
    }

    /// The permuted upper triangle by columns, each entry pointing at its value.
    fn permute(&mut self, matrix: UpperCsr<'_>, position: &[usize]) {
        let n = position.len();
        let mut columns: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for_each_entry(matrix, |row, col, value| {
            let (i, j) = (position[row], position[col]);
            match i.cmp(&j) {
                std::cmp::Ordering::Equal => self.diagonal_value[i] = Some(value),
                std::cmp::Ordering::Less => columns[j].push((i, value)),
                std::cmp::Ordering::Greater => columns[i].push((j, value)),
            }
        });
        self.upper_ptr = Vec::with_capacity(n + 1);
        self.upper_ptr.push(0);
        for column in columns {
            for (row, value) in column {
                self.upper_row.push(row);
                self.upper_value.push(value);
            }
            self.upper_ptr.push(self.upper_row.len());
        }
    }

    /// The elimination tree and, row by row, the pattern of L (the row subtrees) with the slot of
    /// every entry in L's column storage.
    fn factor_pattern(&mut self) {
        let n = self.n();
        let parent = self.elimination_tree();
        let mut mark = vec![usize::MAX; n];
        let mut count = vec![0usize; n];
        let mut row_col = Vec::new();
        let mut row_ptr = vec![0usize];
        for k in 0..n {
            mark[k] = k;
            let start = row_col.len();
            for &i in &self.upper_row[self.upper_ptr[k]..self.upper_ptr[k + 1]] {
                let mut j = i;
                while mark[j] != k {
                    mark[j] = k;
                    row_col.push(j);
                    count[j] += 1;
                    j = parent[j].expect("a row subtree climbs to k through its ancestors");
                }
            }
            row_col[start..].sort_unstable();
            row_ptr.push(row_col.len());
        }
        let mut l_ptr = Vec::with_capacity(n + 1);
        l_ptr.push(0);
        for &c in &count {
            l_ptr.push(l_ptr.last().copied().unwrap_or(0) + c);
        }
        let mut filled = l_ptr[..n].to_vec();
        let mut l_row = vec![0usize; row_col.len()];
        let mut row_slot = vec![0usize; row_col.len()];
        for k in 0..n {
            for t in row_ptr[k]..row_ptr[k + 1] {
                let j = row_col[t];
                row_slot[t] = filled[j];
                l_row[filled[j]] = k;
                filled[j] += 1;
            }
        }
        (self.l_ptr, self.l_row) = (l_ptr, l_row);
        (self.row_ptr, self.row_col, self.row_slot) = (row_ptr, row_col, row_slot);
    }

    /// Parent of each column in the elimination tree (Liu's algorithm with path compression).
    fn elimination_tree(&self) -> Vec<Option<usize>> {
        let n = self.n();
        let mut parent = vec![None; n];
        let mut ancestor: Vec<Option<usize>> = vec![None; n];
        for k in 0..n {
            for &i in &self.upper_row[self.upper_ptr[k]..self.upper_ptr[k + 1]] {
                let mut j = i;
                while let Some(next) = ancestor[j] {
                    if next == k {
                        break;
                    }
                    ancestor[j] = Some(k);
                    j = next;
                }
                if ancestor[j].is_none() {
                    ancestor[j] = Some(k);
                    parent[j] = Some(k);
                }
            }
        }
        parent
    }
}

/// Checks the arrays' lengths, that the row starts increase from 1, and that every column lies
/// in `row..=n`; returns the number of entries.
fn check_structure(n: usize, matrix: UpperCsr<'_>) -> Result<usize, LdlError> {
    let bad = |what: String| Err(LdlError::Structure(what));
    if matrix.ia.len() != n + 1 || matrix.ia.first() != Some(&1) {
        return bad(format!("{} row starts for {n} rows", matrix.ia.len()));
    }
    let entries = usize::try_from(matrix.ia[n] - 1).unwrap_or(usize::MAX);
    if entries > matrix.ja.len() {
        return bad(format!("{entries} entries but {} columns", matrix.ja.len()));
    }
    for row in 0..n {
        let (start, end) = (matrix.ia[row], matrix.ia[row + 1]);
        if end < start {
            return bad(format!("row {} ends before it starts", row + 1));
        }
        for &col in &matrix.ja[(start - 1) as usize..(end - 1) as usize] {
            if col < 1 || col as usize > n || (col as usize) < row + 1 {
                return bad(format!("row {} holds column {col}", row + 1));
            }
        }
    }
    Ok(entries)
}

/// Checks that there is a value for every entry.
fn check_values(entries: usize, values: &[f64]) -> Result<(), LdlError> {
    if values.len() < entries {
        return Err(LdlError::Structure(format!(
            "{} values for {entries} entries",
            values.len()
        )));
    }
    Ok(())
}

/// Marks the regular rows whose diagonal value is zero (or absent) as zero primal rows.
fn mark_zero_diagonals(matrix: UpperCsr<'_>, values: &[f64], kinds: &mut [RowKind]) {
    let mut diagonal = vec![0.0; kinds.len()];
    for_each_entry(matrix, |row, col, index| {
        if row == col {
            diagonal[row] += values[index];
        }
    });
    for (kind, value) in kinds.iter_mut().zip(diagonal) {
        if *kind == RowKind::Regular && value == 0.0 {
            *kind = RowKind::ZeroPrimal;
        }
    }
}

/// Calls `visit(row, col, value_index)` for every entry, 0-based.
fn for_each_entry(matrix: UpperCsr<'_>, mut visit: impl FnMut(usize, usize, usize)) {
    for row in 0..matrix.ia.len() - 1 {
        for index in (matrix.ia[row] - 1) as usize..(matrix.ia[row + 1] - 1) as usize {
            visit(row, (matrix.ja[index] - 1) as usize, index);
        }
    }
}

/// The symmetric pattern without the diagonal.
fn symmetric_pattern(n: usize, matrix: UpperCsr<'_>) -> Pattern {
    let mut entries = Vec::with_capacity(matrix.ja.len());
    for_each_entry(matrix, |row, col, _| entries.push((row, col)));
    Pattern::from_entries(n, entries)
}

/// Every row regular but the trailing run of rows whose upper triangle holds nothing but the
/// diagonal: those are constraint rows.
fn constraint_rows(n: usize, matrix: UpperCsr<'_>) -> Vec<RowKind> {
    let only_diagonal = |row: usize| {
        let (start, end) = (matrix.ia[row] - 1, matrix.ia[row + 1] - 1);
        matrix.ja[start as usize..end as usize]
            .iter()
            .all(|&col| col as usize == row + 1)
    };
    let mut kinds = vec![RowKind::Regular; n];
    for row in (0..n).rev() {
        if !only_diagonal(row) {
            break;
        }
        kinds[row] = RowKind::Constraint;
    }
    kinds
}
