//! The LDLᵀ against dense references: inertia from the eigenvalues, solutions from nalgebra's LU.

use super::*;
use crate::testing::Random;
use nalgebra::DMatrix;
use std::sync::Arc;

/// A symmetric matrix as IPOPT hands it over: upper triangle, 1-based compressed rows, every
/// diagonal present.
struct Upper {
    ia: Vec<i32>,
    ja: Vec<i32>,
    a: Vec<f64>,
}

impl Upper {
    fn from_dense(m: &DMatrix<f64>) -> Upper {
        let n = m.nrows();
        let (mut ia, mut ja, mut a) = (vec![1], Vec::new(), Vec::new());
        for i in 0..n {
            for j in i..n {
                if j == i || m[(i, j)] != 0.0 {
                    ja.push(j as i32 + 1);
                    a.push(m[(i, j)]);
                }
            }
            ia.push(ja.len() as i32 + 1);
        }
        Upper { ia, ja, a }
    }

    fn csr(&self) -> UpperCsr<'_> {
        UpperCsr {
            ia: &self.ia,
            ja: &self.ja,
        }
    }
}

/// A KKT matrix [[W, Jᵀ], [J, -δ I]] with sparse random W (n x n, indefinite when `convex` is
/// false) and J (m x n, full row rank almost surely).
fn kkt(rng: &mut Random, n: usize, m: usize, convex: bool, delta: f64) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(n + m, n + m);
    for i in 0..n {
        k[(i, i)] = if convex {
            rng.real(0.5..4.0)
        } else {
            rng.real(-2.0..4.0)
        };
        for _ in 0..2 {
            let j = rng.index(0..n);
            if j != i {
                let v = rng.real(-1.0..1.0);
                k[(i, j)] = v;
                k[(j, i)] = v;
            }
        }
    }
    for c in 0..m {
        // Each constraint couples a few neighbouring variables, as a transcription does.
        let base = (c * n) / m;
        for offset in 0..3 {
            let j = (base + offset) % n;
            let v = rng.real(0.5..2.0) * if offset % 2 == 0 { 1.0 } else { -1.0 };
            k[(n + c, j)] = v;
            k[(j, n + c)] = v;
        }
        k[(n + c, n + c)] = -delta;
    }
    k
}

fn dense_inertia(m: &DMatrix<f64>) -> Inertia {
    let eigenvalues = m.clone().symmetric_eigen().eigenvalues;
    let positive = eigenvalues.iter().filter(|&&e| e > 0.0).count();
    Inertia {
        positive,
        negative: eigenvalues.len() - positive,
    }
}

fn factorise(m: &DMatrix<f64>) -> (Symbolic, Numeric, Result<Inertia, LdlError>) {
    let upper = Upper::from_dense(m);
    let symbolic = Symbolic::analyse(m.nrows(), upper.csr(), &upper.a).expect("a valid structure");
    let mut numeric = Numeric::new(&symbolic);
    let inertia = numeric.factorise(&symbolic, &upper.a);
    (symbolic, numeric, inertia)
}

/// Relative residual ||A x - b|| / (||A|| ||x|| + ||b||) of the LDLᵀ's solutions of two
/// right-hand sides solved together.
fn residual(m: &DMatrix<f64>, symbolic: &Symbolic, numeric: &mut Numeric, seed: u64) -> f64 {
    let n = m.nrows();
    let mut rng = Random::new(seed);
    let b = DMatrix::from_fn(n, 2, |_, _| rng.real(-1.0..1.0));
    let mut x = b.as_slice().to_vec();
    numeric.solve_in_place(symbolic, &mut x);
    let x = DMatrix::from_column_slice(n, 2, &x);
    (m * &x - &b).norm() / (m.norm() * x.norm() + b.norm())
}

#[test]
fn kkt_matrices_give_the_dense_inertia_and_solution() {
    let mut rng = Random::new(7);
    for case in 0..40 {
        let (n, m) = (rng.index(5..60), rng.index(1..5));
        let m = (m * n / 6).clamp(1, n - 1);
        let convex = case % 2 == 0;
        let delta = if case % 3 == 0 { 1e-8 } else { 0.0 };
        let matrix = kkt(&mut rng, n, m, convex, delta);
        let (symbolic, mut numeric, inertia) = factorise(&matrix);
        let inertia = inertia.expect("a regular KKT matrix factorises");
        assert_eq!(inertia, dense_inertia(&matrix), "case {case}");
        let error = residual(&matrix, &symbolic, &mut numeric, case);
        assert!(error < 1e-12, "case {case}: residual {error:e}");
    }
}

#[test]
fn random_sparse_symmetric_matrices_agree_with_the_dense_reference() {
    let mut rng = Random::new(11);
    for case in 0..40 {
        let n = rng.index(1..50);
        let mut matrix = DMatrix::zeros(n, n);
        for i in 0..n {
            matrix[(i, i)] = rng.real(-3.0..3.0);
            for _ in 0..3 {
                let j = rng.index(0..n);
                let v = rng.real(-1.0..1.0);
                matrix[(i, j)] = v;
                matrix[(j, i)] = v;
            }
        }
        let (symbolic, mut numeric, inertia) = factorise(&matrix);
        match inertia {
            Ok(inertia) => {
                assert_eq!(inertia, dense_inertia(&matrix), "case {case}");
                let error = residual(&matrix, &symbolic, &mut numeric, case);
                // Without pivoting a random indefinite matrix can lose a few digits.
                assert!(error < 1e-9, "case {case}: residual {error:e}");
            }
            Err(error) => {
                // Only a (nearly) singular matrix may be refused.
                let smallest = matrix
                    .clone()
                    .symmetric_eigen()
                    .eigenvalues
                    .iter()
                    .fold(f64::INFINITY, |acc, e| acc.min(e.abs()));
                assert!(smallest < 1e-6 * matrix.norm(), "case {case}: {error}");
            }
        }
    }
}

#[test]
fn singular_matrices_are_reported_or_solved_where_consistent() {
    let mut rng = Random::new(3);
    // A zero row and column: singular.
    let mut matrix = kkt(&mut rng, 12, 4, true, 0.0);
    for j in 0..16 {
        matrix[(5, j)] = 0.0;
        matrix[(j, 5)] = 0.0;
    }
    assert!(matches!(
        factorise(&matrix).2,
        Err(LdlError::Singular { .. })
    ));
    // Two equal constraint rows (J without full row rank): the second row's pivot cancels and
    // is set to the rounding bound with a constraint row's sign, so the inertia is the regular
    // KKT matrix's; a consistent system (equal right-hand sides in those rows) is still solved
    // to rounding level.
    let mut matrix = kkt(&mut rng, 12, 4, true, 0.0);
    for j in 0..12 {
        matrix[(13, j)] = matrix[(12, j)];
        matrix[(j, 13)] = matrix[(j, 12)];
    }
    let (symbolic, mut numeric, inertia) = factorise(&matrix);
    let inertia = inertia.expect("a regularised factorisation");
    assert_eq!(numeric.regularised_pivots(), 1);
    assert_eq!((inertia.positive, inertia.negative), (12, 4));
    let mut b: Vec<f64> = (0..16).map(|i| (i as f64).sin()).collect();
    b[13] = b[12];
    let rhs = DMatrix::from_column_slice(16, 1, &b);
    numeric.solve_in_place(&symbolic, &mut b);
    let x = DMatrix::from_column_slice(16, 1, &b);
    let error = (&matrix * &x - &rhs).norm() / (matrix.norm() * x.norm() + rhs.norm());
    assert!(error < 1e-10, "residual {error:e}");
    // A NaN is never factorised.
    let mut matrix = kkt(&mut rng, 12, 4, true, 0.0);
    matrix[(3, 3)] = f64::NAN;
    assert!(factorise(&matrix).2.is_err());
}

#[test]
fn a_second_factorisation_of_the_same_structure_reuses_the_analysis() {
    let mut rng = Random::new(5);
    let first = kkt(&mut rng, 30, 10, false, 0.0);
    let (symbolic, mut numeric, _) = factorise(&first);
    // New values on the same pattern (a different diagonal shift, as IPOPT's inertia correction).
    let mut second = first.clone();
    for i in 0..30 {
        second[(i, i)] += 5.0;
    }
    let upper = Upper::from_dense(&second);
    let inertia = numeric.factorise(&symbolic, &upper.a).unwrap();
    assert_eq!(inertia, dense_inertia(&second));
    assert!(residual(&second, &symbolic, &mut numeric, 1) < 1e-12);
}

#[test]
fn malformed_structures_are_refused() {
    let bad = [
        (vec![1, 2], vec![1], 2),       // too few row starts
        (vec![1, 2, 3], vec![2, 1], 2), // an entry below the diagonal
        (vec![1, 2, 3], vec![1, 3], 2), // a column beyond n
        (vec![0, 1, 2], vec![1, 2], 2), // 0-based row starts
    ];
    for (ia, ja, n) in bad {
        let values = vec![1.0; ja.len()];
        let result = Symbolic::analyse(n, UpperCsr { ia: &ia, ja: &ja }, &values);
        assert!(
            matches!(result, Err(LdlError::Structure(_))),
            "{ia:?} {ja:?}"
        );
    }
}

/// KKT matrices captured from real trajectory solves (5 steps, both spaces, a feasible and an
/// infeasible payload, so that IPOPT corrects inertia and regularises): every factorisation
/// that succeeds has the dense inertia and solves accurately, and a matrix refused as singular
/// is numerically close to singular or needs the 2x2 pivots this solver does not make.
#[test]
fn kkt_matrices_of_real_solves_agree_with_the_dense_reference() {
    use crate::ipopt::LinearSolver;
    use crate::model::task::Task;
    use crate::model::Robot;
    use crate::problem::{Formulation, Space};
    use crate::solve::{solve_design, SolveSettings};
    let mut task = Task::built_in().unwrap();
    task.motion.steps = 5;
    let settings = SolveSettings {
        linear_solver: Some(LinearSolver::Ldl),
        ..crate::testing::settings()
    };
    let (mut checked, mut refused, mut unresolved) = (0, 0, 0);
    for (space, payload) in [
        (Space::Actuation, 0.0),
        (Space::Joint, 0.0),
        (Space::Actuation, 3.0),
    ] {
        task.payload.mass_kg = payload;
        let robot = Robot::load(&task).unwrap();
        let formulation = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
        super::pardiso::capture::start();
        solve_design(&formulation, &task.transmission.original, &settings).unwrap();
        let matrices = super::pardiso::capture::take();
        assert!(
            matrices.len() > 5,
            "{space} {payload} kg: {} matrices",
            matrices.len()
        );
        for (n, ia, ja, a) in matrices.iter().step_by(3) {
            let dense = dense_of(*n, ia, ja, a);
            let symbolic = Symbolic::analyse(*n, UpperCsr { ia, ja }, a).unwrap();
            let mut numeric = Numeric::new(&symbolic);
            match numeric.factorise(&symbolic, a) {
                Ok(inertia) => {
                    // Near a solution the barrier terms reach 1e15 while other pivots are 1e-9:
                    // the dense reference resolves the signs only after equilibration, a
                    // congruence that keeps the inertia.
                    let scaled = equilibrated(&dense);
                    let eigenvalues = scaled.clone().symmetric_eigen().eigenvalues;
                    let smallest = eigenvalues
                        .iter()
                        .fold(f64::INFINITY, |m, e| m.min(e.abs()));
                    if smallest < 1e-10 * scaled.norm() {
                        unresolved += 1;
                        continue;
                    }
                    assert_eq!(inertia, dense_inertia(&scaled), "{space} {payload} kg");
                    let error = residual(&dense, &symbolic, &mut numeric, checked as u64);
                    assert!(error < 1e-10, "{space} {payload} kg: residual {error:e}");
                    checked += 1;
                }
                Err(LdlError::Singular { .. }) => refused += 1,
                Err(error) => panic!("{space} {payload} kg: {error}"),
            }
        }
    }
    println!(
        "{checked} captured KKT matrices factorised and checked, {refused} refused as singular, \
         {unresolved} too ill-conditioned for the dense reference"
    );
    assert!(
        checked > 10 && refused * 4 < checked,
        "{checked} checked, {refused} refused"
    );
}

/// `S A S` with `S = diag(1 / sqrt(max_j |a_ij|))`: the same inertia, entries at most 1.
fn equilibrated(a: &DMatrix<f64>) -> DMatrix<f64> {
    let scale: Vec<f64> = (0..a.nrows())
        .map(|i| {
            let largest = a.row(i).iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if largest > 0.0 {
                1.0 / largest.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| scale[i] * a[(i, j)] * scale[j])
}

/// The dense symmetric matrix of an upper triangle in 1-based compressed rows.
fn dense_of(n: usize, ia: &[i32], ja: &[i32], a: &[f64]) -> DMatrix<f64> {
    let mut dense = DMatrix::zeros(n, n);
    for row in 0..n {
        for index in (ia[row] - 1) as usize..(ia[row + 1] - 1) as usize {
            let col = (ja[index] - 1) as usize;
            dense[(row, col)] += a[index];
            if col != row {
                dense[(col, row)] += a[index];
            }
        }
    }
    dense
}

/// The matrix of `upper`'s structure with new random values: the constraint rows' zero
/// diagonals kept zero, every other entry drawn again (non-zero), with `shift` added to the
/// primal diagonals (a positive shift makes the primal block dominant).
fn revalued(upper: &Upper, primal: usize, shift: f64, rng: &mut Random) -> Vec<f64> {
    let mut a = Vec::with_capacity(upper.a.len());
    for row in 0..upper.ia.len() - 1 {
        for index in (upper.ia[row] - 1) as usize..(upper.ia[row + 1] - 1) as usize {
            let diagonal = upper.ja[index] as usize == row + 1;
            a.push(match (diagonal, row < primal) {
                (true, false) => 0.0,
                (true, true) => shift + rng.real(0.5..2.0) * if shift > 0.0 { 1.0 } else { -1.0 },
                (false, _) => rng.real(0.1..1.0) * if rng.unit() < 0.5 { 1.0 } else { -1.0 },
            });
        }
    }
    a
}

/// Factorises `a` with `symbolic` and solves two right-hand sides: the inertia (or the error),
/// the bits of the pivots' solution and of the solutions.
fn factor_bits(symbolic: &Symbolic, a: &[f64], seed: u64) -> (Result<Inertia, LdlError>, Vec<u64>) {
    let mut numeric = Numeric::new(symbolic);
    let inertia = numeric.factorise(symbolic, a);
    let mut rng = Random::new(seed);
    let mut x: Vec<f64> = (0..2 * symbolic.n()).map(|_| rng.real(-1.0..1.0)).collect();
    if inertia.is_ok() {
        numeric.solve_in_place(symbolic, &mut x);
    }
    (inertia, x.iter().map(|v| v.to_bits()).collect())
}

#[test]
fn a_cached_analysis_is_reused_for_the_same_structure_and_gives_the_same_bits() {
    let (primal, constraints) = (40, 12);
    let mut rng = Random::new(17);
    let first = Upper::from_dense(&kkt(&mut rng, primal, constraints, false, 0.0));
    let n = primal + constraints;
    let cache = AnalysisCache::new(2);
    let analysed = cache.analyse(n, first.csr(), &first.a).unwrap();
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 1,
            reused: 0
        }
    );
    assert_eq!(
        *analysed,
        Symbolic::analyse(n, first.csr(), &first.a).unwrap()
    );
    // Matrices of the same structure, positive definite primal block or indefinite: the kept
    // analysis comes back, and its factors and solutions are bit for bit those of a new one.
    for (case, shift) in [4.0, 0.0, -1.0, 2.0, -3.0, 0.5].into_iter().enumerate() {
        let a = revalued(&first, primal, shift, &mut rng);
        let cached = cache.analyse(n, first.csr(), &a).unwrap();
        assert!(Arc::ptr_eq(&cached, &analysed), "case {case}");
        let fresh = Symbolic::analyse(n, first.csr(), &a).unwrap();
        assert_eq!(*cached, fresh, "case {case}");
        let (inertia, bits) = factor_bits(&cached, &a, case as u64);
        assert_eq!(
            (inertia.clone(), bits),
            factor_bits(&fresh, &a, case as u64)
        );
        if shift > 3.0 {
            assert_eq!(
                inertia,
                Ok(Inertia {
                    positive: primal,
                    negative: constraints
                })
            );
        }
    }
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 1,
            reused: 6
        }
    );
}

#[test]
fn the_cache_tells_structures_and_zero_diagonals_apart_and_keeps_the_last_few() {
    let (primal, constraints) = (30, 8);
    let n = primal + constraints;
    let mut rng = Random::new(23);
    let dense = kkt(&mut rng, primal, constraints, true, 0.0);
    let first = Upper::from_dense(&dense);
    let cache = AnalysisCache::new(2);
    let analysed = cache.analyse(n, first.csr(), &first.a).unwrap();
    // A primal diagonal that is zero: another analysis, which reanalysing the kept one with that
    // matrix then finds (as the second analysis of every solve does).
    let mut zero = first.a.clone();
    zero[first.ia[3] as usize - 1] = 0.0;
    let with_zero = cache.analyse(n, first.csr(), &zero).unwrap();
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 2,
            reused: 0
        }
    );
    assert!(analysed.needs_reanalysis(&zero));
    let reanalysed = cache.reanalyse(&analysed, first.csr(), &zero).unwrap();
    assert!(Arc::ptr_eq(&reanalysed, &with_zero));
    assert_eq!(*reanalysed, analysed.reanalyse(first.csr(), &zero).unwrap());
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 2,
            reused: 1
        }
    );
    // As many entries, one moved to another column: a structure of its own. It pushes the least
    // recently used analysis (the first) out of a cache that keeps two.
    let mut moved = dense.clone();
    let column = (1..n).find(|&j| moved[(0, j)] == 0.0).unwrap();
    let row = (1..n).find(|&j| moved[(0, j)] != 0.0).unwrap();
    moved.swap((0, column), (0, row));
    moved.swap((column, 0), (row, 0));
    let moved = Upper::from_dense(&moved);
    assert_eq!(
        (moved.ia.len(), moved.ja.len()),
        (first.ia.len(), first.ja.len())
    );
    let other = cache.analyse(n, moved.csr(), &moved.a).unwrap();
    assert!(!Arc::ptr_eq(&other, &analysed));
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 3,
            reused: 1
        }
    );
    let again = cache.analyse(n, first.csr(), &first.a).unwrap();
    assert!(!Arc::ptr_eq(&again, &analysed));
    assert_eq!(*again, *analysed);
    assert_eq!(
        cache.counts(),
        CacheCounts {
            analysed: 4,
            reused: 1
        }
    );
    // A malformed structure is refused before any look-up.
    let bad = UpperCsr {
        ia: &[1, 2, 3],
        ja: &[2, 1],
    };
    assert!(matches!(
        cache.analyse(2, bad, &[1.0, 1.0]),
        Err(LdlError::Structure(_))
    ));
    assert_eq!(cache.counts().analysed, 4);
}
