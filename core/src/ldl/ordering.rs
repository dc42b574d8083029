//! The elimination order of a KKT matrix: approximate minimum degree (SuiteSparse's AMD, by the
//! `amd` crate) on the symmetric pattern, then every row with a zero diagonal moved behind a
//! partner of its own.
//!
//! With 1x1 pivots and no pivoting, every leading block of the permuted matrix must be regular.
//! A row whose diagonal is zero (a constraint row of `[[H, Jᵀ], [J, 0]]`, or a variable that
//! enters neither the objective's curvature nor a bound, such as an acceleration) gets a
//! non-zero pivot only from rows eliminated before it, and two such rows behind one shared
//! neighbour cancel exactly. So each zero row gets a partner of its own, a neighbour eliminated
//! before it: a row with a non-zero diagonal, or a zero row that has a partner itself. The
//! partners form chains that start at a non-zero diagonal (e.g. velocity update -> acceleration
//! -> dynamics row -> joint position), so every leading block has a structurally non-zero
//! determinant (pair each zero row's chain from its end). Constraint rows are matched to regular
//! rows first, by a maximum bipartite matching; the rest are chained on in passes. Both prefer
//! the earliest neighbour in the minimum degree order, so that rows move little.

/// The symmetric pattern of a matrix without its diagonal: `neighbours[ptr[i]..ptr[i + 1]]` are
/// the columns `j != i` with a structural non-zero in row `i`, sorted, without repeats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    /// Start of each row's neighbours; length `n + 1`.
    pub ptr: Vec<usize>,
    /// The neighbours, row after row.
    pub neighbours: Vec<usize>,
}

impl Pattern {
    /// The symmetric pattern of the off-diagonal entries `(i, j)` (either triangle, repeats
    /// allowed; diagonal entries are skipped).
    pub fn from_entries(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Pattern {
        let mut rows = vec![Vec::new(); n];
        for (i, j) in entries {
            if i != j {
                rows[i].push(j);
                rows[j].push(i);
            }
        }
        let mut ptr = Vec::with_capacity(n + 1);
        ptr.push(0);
        let mut neighbours = Vec::new();
        for mut row in rows {
            row.sort_unstable();
            row.dedup();
            neighbours.extend(row);
            ptr.push(neighbours.len());
        }
        Pattern { ptr, neighbours }
    }

    /// Number of rows.
    pub fn n(&self) -> usize {
        self.ptr.len() - 1
    }

    /// The neighbours of row `i`.
    pub fn row(&self, i: usize) -> &[usize] {
        &self.neighbours[self.ptr[i]..self.ptr[i + 1]]
    }
}

/// What the order needs to know of each row's diagonal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowKind {
    /// A non-zero diagonal.
    Regular,
    /// A primal row whose diagonal is zero.
    ZeroPrimal,
    /// A constraint row (zero diagonal until IPOPT regularises it).
    Constraint,
}

/// The elimination order: `order[k]` is the original index of the `k`-th pivot.
pub fn elimination_order(pattern: &Pattern, kinds: &[RowKind]) -> Vec<usize> {
    let order = minimum_degree(pattern);
    let mut position = vec![0usize; order.len()];
    for (k, &row) in order.iter().enumerate() {
        position[row] = k;
    }
    let partner = match_zero_rows(pattern, kinds, &position);
    defer_zero_rows(&partner, &order, &position)
}

/// The approximate minimum degree order of the pattern (AMD's default control: dense rows above
/// 10 sqrt(n) neighbours, aggressive absorption). AMD ignores the diagonal, but the `amd` crate
/// checks (in builds with debug assertions) that its entries are at least as many as its rows,
/// which a pattern without its diagonal need not be: it is given the diagonal too.
fn minimum_degree(pattern: &Pattern) -> Vec<usize> {
    let n = pattern.n();
    let (mut ptr, mut entries) = (Vec::with_capacity(n + 1), Vec::new());
    ptr.push(0);
    for i in 0..n {
        let row = pattern.row(i);
        let before = row.partition_point(|&j| j < i);
        entries.extend_from_slice(&row[..before]);
        entries.push(i);
        entries.extend_from_slice(&row[before..]);
        ptr.push(entries.len());
    }
    // The pattern is square, sorted and within bounds by construction, and AMD's only other
    // failure is running out of memory for sizes far beyond any KKT matrix IPOPT can hold; the
    // identity order is a correct (if slower) fallback all the same.
    match amd::order::<usize>(n, &ptr, &entries, &amd::Control::default()) {
        Ok((order, _, _)) => order,
        Err(_) => (0..n).collect(),
    }
}

/// Partners for the zero rows (see the module's documentation): `partner[z]` for each matched
/// zero row `z`, each row the partner of at most one. First a maximum matching of constraint rows
/// to regular rows (greedy in the minimum degree order, then augmenting paths); then, pass after
/// pass, each zero row still without a partner takes its earliest free neighbour that is regular
/// or already has one, so every chain starts at a regular row. A zero row left without a partner
/// makes the matrix structurally singular.
fn match_zero_rows(pattern: &Pattern, kinds: &[RowKind], position: &[usize]) -> Vec<Option<usize>> {
    let n = pattern.n();
    let mut matching = Matching {
        partner: vec![None; n],
        taken_by: vec![None; n],
        visited: vec![usize::MAX; n],
    };
    let mut zero_rows: Vec<usize> = (0..n).filter(|&i| kinds[i] != RowKind::Regular).collect();
    zero_rows.sort_unstable_by_key(|&row| position[row]);
    let constraints = zero_rows
        .iter()
        .copied()
        .filter(|&row| kinds[row] == RowKind::Constraint);
    for row in constraints.clone() {
        let free = |p: usize| kinds[p] == RowKind::Regular && matching.taken_by[p].is_none();
        if let Some(p) = earliest(pattern.row(row), position, free) {
            matching.take(row, p);
        }
    }
    for row in constraints {
        if matching.partner[row].is_none() {
            matching.augment(pattern, kinds, row);
        }
    }
    loop {
        let mut progress = false;
        for &row in &zero_rows {
            if matching.partner[row].is_some() {
                continue;
            }
            let supported = |p: usize| {
                matching.taken_by[p].is_none()
                    && (kinds[p] == RowKind::Regular || matching.partner[p].is_some())
            };
            if let Some(p) = earliest(pattern.row(row), position, supported) {
                matching.take(row, p);
                progress = true;
            }
        }
        if !progress {
            return matching.partner;
        }
    }
}

/// The neighbour earliest in the minimum degree order among those `eligible`.
fn earliest(
    neighbours: &[usize],
    position: &[usize],
    eligible: impl Fn(usize) -> bool,
) -> Option<usize> {
    neighbours
        .iter()
        .copied()
        .filter(|&p| eligible(p))
        .min_by_key(|&p| position[p])
}

/// A matching of zero rows to partners, built up by augmenting paths.
struct Matching {
    partner: Vec<Option<usize>>,
    taken_by: Vec<Option<usize>>,
    /// The search that last visited each row (its starting row).
    visited: Vec<usize>,
}

impl Matching {
    /// Makes `p` the partner of `row`.
    fn take(&mut self, row: usize, p: usize) {
        self.partner[row] = Some(p);
        self.taken_by[p] = Some(row);
    }

    /// Looks for an augmenting path of constraint rows and regular partners from the unmatched
    /// constraint row `start` (depth first, with an explicit stack) and flips the matching along
    /// it when one exists.
    fn augment(&mut self, pattern: &Pattern, kinds: &[RowKind], start: usize) {
        // Each frame: a constraint row and how many of its neighbours it has tried.
        let mut stack = vec![(start, 0usize)];
        while let Some(&mut (row, ref mut tried)) = stack.last_mut() {
            let Some(&p) = pattern.row(row).get(*tried) else {
                stack.pop();
                continue;
            };
            *tried += 1;
            if kinds[p] != RowKind::Regular || self.visited[p] == start {
                continue;
            }
            self.visited[p] = start;
            match self.taken_by[p] {
                Some(owner) => stack.push((owner, 0)),
                None => {
                    // Flip the path: each row on the stack takes the row it reached next.
                    let mut next = p;
                    while let Some((row, _)) = stack.pop() {
                        let previous = self.partner[row].replace(next);
                        self.taken_by[next] = Some(row);
                        match previous {
                            Some(freed) => next = freed,
                            None => break,
                        }
                    }
                    return;
                }
            }
        }
    }
}

/// Moves each zero row that comes before its partner to just after it (after the partner has
/// itself moved behind its own partner), keeping the relative order of everything else.
fn defer_zero_rows(partner: &[Option<usize>], order: &[usize], position: &[usize]) -> Vec<usize> {
    // Sort key: the position the row's chain is anchored at, its depth behind that anchor, and
    // its own position. Chains are short: at most constraint -> zero primal -> constraint ->
    // regular.
    fn key(row: usize, partner: &[Option<usize>], position: &[usize]) -> (usize, usize, usize) {
        let own = (position[row], 0, position[row]);
        match partner[row] {
            Some(p) => {
                let (anchor, depth, _) = key(p, partner, position);
                own.max((anchor, depth + 1, position[row]))
            }
            None => own,
        }
    }
    let mut keyed: Vec<_> = order
        .iter()
        .map(|&row| (key(row, partner, position), row))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, row)| row).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use RowKind::{Constraint as C, Regular as R, ZeroPrimal as Z};

    fn pattern(n: usize, edges: &[(usize, usize)]) -> Pattern {
        Pattern::from_entries(n, edges.iter().copied())
    }

    #[test]
    fn zero_primal_rows_follow_a_constraint_that_follows_a_regular_row() {
        // An acceleration-like row 0 (zero diagonal) couples only to constraint row 2, which
        // couples to rows 0 and 1 (regular). The order must be 1, 2, 0.
        let p = pattern(3, &[(2, 0), (2, 1)]);
        let order = elimination_order(&p, &[Z, R, C]);
        assert_eq!(order, vec![1, 2, 0]);
    }

    /// A pattern with fewer entries than rows (isolated rows, or none at all) is ordered, also
    /// where debug assertions are on (the `amd` crate's check of its entries).
    #[test]
    fn a_pattern_sparser_than_its_rows_is_ordered() {
        for (n, edges) in [(4, vec![(0, 1)]), (3, vec![]), (0, vec![])] {
            let mut order = minimum_degree(&pattern(n, &edges));
            order.sort_unstable();
            assert_eq!(order, (0..n).collect::<Vec<_>>());
        }
    }

    #[test]
    fn a_dense_row_is_eliminated_last() {
        // An arrow: row 0 couples to every other row, which couple to nothing else.
        let edges: Vec<_> = (1..8).map(|j| (0, j)).collect();
        let order = minimum_degree(&pattern(8, &edges));
        assert_eq!(order.len(), 8);
        assert_eq!(*order.last().unwrap(), 0);
    }

    #[test]
    fn constraint_rows_sharing_a_neighbour_get_partners_of_their_own() {
        // Rows 3 and 4 both couple to primal row 0; row 4 can also take 1, row 3 only 0 or 2.
        let p = pattern(5, &[(3, 0), (3, 2), (4, 0), (4, 1)]);
        let kinds = [R, R, R, C, C];
        let partner = match_zero_rows(&p, &kinds, &[0, 1, 2, 3, 4]);
        let (a, b) = (partner[3].unwrap(), partner[4].unwrap());
        assert_ne!(a, b);
        assert!(p.row(3).contains(&a) && p.row(4).contains(&b));
        // Only primal row 0 for both: one of them stays unmatched (J is rank deficient).
        let p = pattern(3, &[(1, 0), (2, 0)]);
        let partner = match_zero_rows(&p, &[R, C, C], &[0, 1, 2]);
        assert_eq!(partner.iter().filter(|m| m.is_some()).count(), 1);
    }

    #[test]
    fn augmenting_paths_complete_a_greedy_matching() {
        // Greedy gives row 3 the earliest free neighbour 0; row 4 has only 0, so 3 must move to 1.
        let p = pattern(5, &[(3, 0), (3, 1), (4, 0)]);
        let partner = match_zero_rows(&p, &[R, R, R, C, C], &[0, 1, 2, 3, 4]);
        assert_eq!(partner[3], Some(1));
        assert_eq!(partner[4], Some(0));
    }

    #[test]
    fn every_constraint_row_follows_one_of_its_neighbours() {
        // A chain of primal rows 0..6 with constraint rows 6..9 coupling consecutive pairs.
        let mut edges: Vec<_> = (0..5).map(|i| (i, i + 1)).collect();
        edges.extend([(6, 0), (6, 1), (7, 2), (7, 3), (8, 4), (8, 5)]);
        let p = pattern(9, &edges);
        let kinds: Vec<RowKind> = (0..9).map(|i| if i >= 6 { C } else { R }).collect();
        let order = elimination_order(&p, &kinds);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..9).collect::<Vec<_>>());
        let mut position = [0; 9];
        for (k, &row) in order.iter().enumerate() {
            position[row] = k;
        }
        for c in 6..9 {
            assert!(
                p.row(c).iter().any(|&j| position[j] < position[c]),
                "{order:?}"
            );
        }
    }
}
