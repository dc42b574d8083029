//! The LDLᵀ on the default problem's KKT matrix: one analysis, the same analysis found again in
//! an [`AnalysisCache`] (as every solve after a worker's first finds it), then the median of 200
//! factorisations and of 200 solves, in microseconds.
//!
//! `cargo bench --bench ldl`. The matrix is assembled as IPOPT assembles its augmented system,
//! `[[W + Σ, Jᵀ], [J, 0]]` in upper-triangle 1-based compressed rows, from the trajectory
//! problem's exact Hessian and Jacobian at its initial guess (multipliers 1, Σ = I). MUMPS has no
//! entry point outside IPOPT: `cargo bench --bench solve` compares the two inside whole solves.

use codesign::stats::median;
use codesign_core::ipopt::Nlp;
use codesign_core::ldl::{AnalysisCache, Numeric, UpperCsr, KEPT_ANALYSES};
use codesign_core::model::task::Task;
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use std::collections::BTreeMap;
use std::hint::black_box;
use std::time::Instant;

/// The upper triangle of the KKT matrix: (row starts, columns, values), 1-based.
fn kkt(space: Space) -> (usize, Vec<i32>, Vec<i32>, Vec<f64>) {
    let task = Task::built_in().expect("the built-in task loads");
    let robot = Robot::load(&task).expect("the robot loads");
    let formulation = Formulation::new(&task, robot, space, task.limit_modes).expect("formulation");
    let mut problem = formulation
        .problem(&task.transmission.original)
        .expect("the original design is valid");
    let (n, m) = (problem.num_variables(), problem.num_constraints());
    let mut x = vec![0.0; n];
    problem.initial_point(&mut x);
    let mut entries: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    let hessian = problem.hessian_structure();
    let mut values = vec![0.0; hessian.len()];
    problem
        .hessian_values(&x, true, 1.0, &vec![1.0; m], &mut values)
        .expect("the Hessian evaluates");
    for (&(row, col), value) in hessian.iter().zip(values) {
        *entries.entry((col, row)).or_default() += value;
    }
    for i in 0..n {
        *entries.entry((i, i)).or_default() += 1.0;
    }
    let jacobian = problem.jacobian_structure();
    let mut values = vec![0.0; jacobian.len()];
    problem
        .jacobian_values(&x, false, &mut values)
        .expect("the Jacobian evaluates");
    for (&(row, col), value) in jacobian.iter().zip(values) {
        *entries.entry((col, n + row)).or_default() += value;
    }
    for c in 0..m {
        entries.entry((n + c, n + c)).or_default();
    }
    let (mut ia, mut ja, mut a) = (vec![1], Vec::new(), Vec::new());
    let mut row = 0;
    for (&(i, j), &value) in &entries {
        while row < i {
            ia.push(ja.len() as i32 + 1);
            row += 1;
        }
        ja.push(j as i32 + 1);
        a.push(value);
    }
    while ia.len() <= n + m {
        ia.push(ja.len() as i32 + 1);
    }
    (n + m, ia, ja, a)
}

/// The median of `samples` (s), us.
fn median_us(samples: Vec<f64>) -> f64 {
    median(&samples) * 1e6
}

fn main() {
    for space in [Space::Actuation, Space::Joint] {
        let (n, ia, ja, a) = kkt(space);
        let matrix = UpperCsr { ia: &ia, ja: &ja };
        let cache = AnalysisCache::new(KEPT_ANALYSES);
        let started = Instant::now();
        let symbolic = cache.analyse(n, matrix, &a).expect("a valid structure");
        let analysis = started.elapsed().as_secs_f64() * 1e6;
        let started = Instant::now();
        black_box(cache.analyse(n, matrix, black_box(&a))).expect("a valid structure");
        let reused = started.elapsed().as_secs_f64() * 1e6;
        assert_eq!(cache.counts().reused, 1);
        let mut numeric = Numeric::new(&symbolic);
        let factorisations: Vec<f64> = (0..200)
            .map(|_| {
                let started = Instant::now();
                black_box(numeric.factorise(&symbolic, black_box(&a))).expect("factorises");
                started.elapsed().as_secs_f64()
            })
            .collect();
        let mut rhs = vec![1.0; n];
        let solves: Vec<f64> = (0..200)
            .map(|_| {
                let started = Instant::now();
                numeric.solve_in_place(&symbolic, black_box(&mut rhs));
                started.elapsed().as_secs_f64()
            })
            .collect();
        println!(
            "ldl {space} space KKT: n = {n}, {} entries, {} in L, inertia {:?}; analysis {analysis:.0} us, found again {reused:.0} us, median of 200: factorisation {:.1} us, solve {:.1} us",
            a.len(),
            symbolic.factor_entries(),
            numeric.inertia(),
            median_us(factorisations),
            median_us(solves)
        );
    }
}
