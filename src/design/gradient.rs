//! Gradient-based co-design: projected quasi-Newton (BFGS) on the ratios, with the exact design
//! sensitivity dJ*/dr of every solve (`problem::cost_gradient`) and warm-started inner solves.
//!
//! The feasible set of designs is the box of the bounds cut by the order constraints
//! (r_i <= r_j, or r_i < r_j kept by a margin). Steps are projected onto it exactly (a small
//! active-set enumeration); a backtracking line
//! search accepts a step when the inner problem is feasible and the cost falls by the Armijo
//! fraction. Candidate starts (the original design and designs spread through the box) are
//! solved once; the best feasible ones are descended from, and the best result is kept.

use crate::ipopt::Solution;
use crate::problem::Formulation;
use crate::solver::{solve_design_from, SolveSettings};
use crate::transmission::Transmission;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Settings of a gradient-based run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GradientSettings {
    /// Quasi-Newton iterations per start at most.
    pub max_iterations: usize,
    /// Stop when the projected gradient step is shorter than this, or an iteration lowers the
    /// cost by less than this fraction.
    pub tolerance: f64,
    /// Candidate starting designs, each solved once from the standard initial guess.
    pub starts: Vec<Vec<f64>>,
    /// Further candidates, solved in order only while fewer than `descents` feasible ones are
    /// known (feasible designs can be rare: about 3% of the box at 3 kg in actuation space).
    pub fallback_starts: Vec<Vec<f64>>,
    /// How many of the feasible candidates, best first, are descended from.
    pub descents: usize,
}

/// One accepted iterate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GradientIterate {
    /// Which start it belongs to.
    pub start: usize,
    /// The design.
    pub ratios: Vec<f64>,
    /// Its optimal cost.
    pub cost: f64,
    /// Its cost gradient.
    pub gradient: Vec<f64>,
}

/// The outcome of a gradient-based run.
#[derive(Clone, Debug, PartialEq)]
pub struct GradientOutcome {
    /// The best design over all starts.
    pub best_ratios: Vec<f64>,
    /// Its cost (`f64::INFINITY` if no start was feasible).
    pub best_cost: f64,
    /// The inner solution behind `best_cost`: warm-started solves can reach a lower local
    /// optimum of the trajectory problem than a solve from the standard initial guess, so the
    /// best design's trajectory is recovered by warm-starting from this.
    pub best_solution: Option<Solution>,
    /// Accepted iterates of every start, in order.
    pub iterates: Vec<GradientIterate>,
    /// Every inner solve's cost (the penalty for infeasible trial designs), in order.
    pub costs: Vec<f64>,
    /// Every inner solve's wall time, s, in order.
    pub seconds: Vec<f64>,
    /// How many candidate starts were solved (`starts` and the fallbacks used).
    pub candidates_solved: usize,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Runs the projected quasi-Newton method from every start of `settings`.
pub fn optimize_gradient(
    formulation: &Formulation,
    settings: &GradientSettings,
    penalty: f64,
) -> GradientOutcome {
    let set = formulation.transmission().design_space();
    let mut outcome = GradientOutcome {
        best_ratios: Vec::new(),
        best_cost: f64::INFINITY,
        best_solution: None,
        iterates: Vec::new(),
        costs: Vec::new(),
        seconds: Vec::new(),
        candidates_solved: 0,
    };
    let solve_settings = SolveSettings::default();
    // One inner solve: (cost, gradient, raw solution) when feasible.
    // One inner solve: (cost, gradient, raw solution) when feasible; logs cost and time.
    let evaluate = |ratios: &[f64], warm: Option<&Solution>, outcome: &mut GradientOutcome| {
        match solve_design_from(formulation, ratios, &solve_settings, warm) {
            Ok((result, solution)) => {
                outcome.seconds.push(result.solve_seconds.total);
                outcome.costs.push(if result.feasible {
                    result.cost
                } else {
                    penalty
                });
                let gradient = result.cost_gradient.filter(|_| result.feasible);
                gradient.map(|gradient| (result.cost, gradient, solution))
            }
            Err(_) => {
                outcome.costs.push(penalty);
                outcome.seconds.push(0.0);
                None
            }
        }
    };
    // Every candidate is solved cold; the descents start from the best feasible ones.
    let mut candidates = Vec::new();
    let pool = settings.starts.iter().chain(&settings.fallback_starts);
    for (start_index, start) in pool.enumerate() {
        if start_index >= settings.starts.len() && candidates.len() >= settings.descents {
            break;
        }
        outcome.candidates_solved += 1;
        let x = set.project(start);
        if let Some((f, g, solution)) = evaluate(&x, None, &mut outcome) {
            candidates.push((start_index, x, f, g, solution));
        }
    }
    candidates.sort_by(|a, b| a.2.total_cmp(&b.2));
    candidates.truncate(settings.descents);
    for (start_index, x, f, g, solution) in candidates {
        let (mut x, mut f, mut g, mut solution) = (x, f, g, solution);
        outcome.iterates.push(GradientIterate {
            start: start_index,
            ratios: x.clone(),
            cost: f,
            gradient: g.clone(),
        });
        let n = x.len();
        // Inverse Hessian approximation, first scaled so that a unit step moves 10% of the box.
        let width = set.bounds().iter().map(|[l, u]| u - l).fold(0.0, f64::max);
        let identity_scale = 0.1 * width / dot(&g, &g).sqrt().max(1e-12);
        let mut h: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| if i == j { identity_scale } else { 0.0 })
                    .collect()
            })
            .collect();
        for _ in 0..settings.max_iterations {
            let projected_step: Vec<f64> =
                set.project(&x.iter().zip(&g).map(|(x, g)| x - g).collect::<Vec<_>>());
            if projected_step
                .iter()
                .zip(&x)
                .map(|(p, x)| (p - x).abs())
                .fold(0.0, f64::max)
                < settings.tolerance
            {
                break;
            }
            // Ratios held at a bound by the gradient do not move; the quasi-Newton step acts
            // on the others (the reduced Hessian of projected Newton methods).
            let held: Vec<bool> = (0..n)
                .map(|i| {
                    (x[i] <= set.bounds()[i][0] + 1e-9 && g[i] > 0.0)
                        || (x[i] >= set.bounds()[i][1] - 1e-9 && g[i] < 0.0)
                })
                .collect();
            let direction: Vec<f64> = (0..n)
                .map(|i| {
                    if held[i] {
                        0.0
                    } else {
                        -(0..n)
                            .filter(|&j| !held[j])
                            .map(|j| h[i][j] * g[j])
                            .sum::<f64>()
                    }
                })
                .collect();
            let mut accepted = None;
            let mut t = 1.0;
            for _ in 0..12 {
                let trial = set.project(
                    &x.iter()
                        .zip(&direction)
                        .map(|(x, d)| x + t * d)
                        .collect::<Vec<_>>(),
                );
                let step: Vec<f64> = trial.iter().zip(&x).map(|(a, b)| a - b).collect();
                if step.iter().all(|s| s.abs() < 1e-12) {
                    break;
                }
                if let Some((f_new, g_new, s_new)) = evaluate(&trial, Some(&solution), &mut outcome)
                {
                    if f_new <= f + 1e-4 * dot(&g, &step) {
                        accepted = Some((trial, step, f_new, g_new, s_new));
                        break;
                    }
                }
                t *= 0.5;
            }
            let Some((trial, s, f_new, g_new, s_new)) = accepted else {
                // No descent along the quasi-Newton direction: restart from steepest descent once,
                // and stop when even that fails.
                let reset: Vec<Vec<f64>> = (0..n)
                    .map(|i| {
                        (0..n)
                            .map(|j| if i == j { identity_scale } else { 0.0 })
                            .collect()
                    })
                    .collect();
                if h == reset {
                    break;
                }
                h = reset;
                continue;
            };
            let y: Vec<f64> = g_new.iter().zip(&g).map(|(a, b)| a - b).collect();
            let sy = dot(&s, &y);
            if sy > 1e-12 {
                // BFGS update of the inverse Hessian: H = (I - rho s y^T) H (I - rho y s^T) + rho s s^T.
                let rho = 1.0 / sy;
                let hy: Vec<f64> = h.iter().map(|row| dot(row, &y)).collect();
                let yhy = dot(&y, &hy);
                for i in 0..n {
                    for j in 0..n {
                        h[i][j] += -rho * (s[i] * hy[j] + hy[i] * s[j])
                            + (rho * rho * yhy + rho) * s[i] * s[j];
                    }
                }
            }
            let decrease = f - f_new;
            (x, f, g, solution) = (trial, f_new, g_new, s_new);
            outcome.iterates.push(GradientIterate {
                start: start_index,
                ratios: x.clone(),
                cost: f,
                gradient: g.clone(),
            });
            // The inner optimum is accurate to about IPOPT's tol (1e-8 relative); smaller
            // decreases are noise.
            if decrease <= settings.tolerance * f.abs().max(1.0) {
                break;
            }
        }
        if f < outcome.best_cost {
            outcome.best_cost = f;
            outcome.best_ratios = x;
            outcome.best_solution = Some(solution);
        }
    }
    outcome
}

/// The default candidate starts: the original design and the first `spread` designs of
/// [`spread_designs`].
pub fn default_starts(transmission: &Transmission, spread: u32) -> Vec<Vec<f64>> {
    let mut starts = vec![transmission.original().to_vec()];
    starts.extend(spread_designs(transmission, 1..spread + 1));
    starts
}

/// Designs spread through the box of the bounds by the Halton sequence (bases 2, 3, 5, 7, ...),
/// points `indices` of it, projected onto the order constraints.
pub fn spread_designs(transmission: &Transmission, indices: Range<u32>) -> Vec<Vec<f64>> {
    const PRIMES: [u32; 8] = [2, 3, 5, 7, 11, 13, 17, 19];
    let set = transmission.design_space();
    let radical_inverse = |mut index: u32, base: u32| {
        let (mut value, mut scale) = (0.0, 1.0 / f64::from(base));
        while index > 0 {
            value += f64::from(index % base) * scale;
            index /= base;
            scale /= f64::from(base);
        }
        value
    };
    indices
        .map(|k| {
            let point: Vec<f64> = set
                .bounds()
                .iter()
                .enumerate()
                .map(|(i, [lower, upper])| {
                    let fraction = radical_inverse(k, PRIMES[i % PRIMES.len()]);
                    lower + fraction * (upper - lower)
                })
                .collect();
            set.project(&point)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::Task;
    use std::path::Path;

    fn transmission() -> Transmission {
        let task =
            Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json"))
                .unwrap();
        Transmission::from_spec(&task.transmission).unwrap()
    }

    #[test]
    fn descends_from_the_original_design_to_a_stationary_point() {
        let mut task =
            Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json"))
                .unwrap();
        task.payload.mass_kg = 1.0;
        let robot = crate::model::Robot::load(&task).unwrap();
        let formulation = Formulation::new(
            &task,
            robot,
            crate::problem::Space::Actuation,
            task.limit_modes,
        )
        .unwrap();
        let settings = GradientSettings {
            max_iterations: 50,
            tolerance: 1e-6,
            starts: vec![task.transmission.original.clone()],
            fallback_starts: Vec::new(),
            descents: 1,
        };
        let outcome = optimize_gradient(&formulation, &settings, 1e6);
        let first = &outcome.iterates[0];
        let last = outcome.iterates.last().unwrap();
        assert!(
            last.cost < 0.5 * first.cost,
            "{} -> {}",
            first.cost,
            last.cost
        );
        assert_eq!(outcome.best_cost, last.cost);
        assert!(formulation
            .transmission()
            .check_design(&outcome.best_ratios)
            .is_ok());
        // Costs fall monotonically along the accepted iterates.
        assert!(outcome.iterates.windows(2).all(|w| w[1].cost <= w[0].cost));
        // At the end the projected gradient step is short: a stationary point of the design box.
        let set = formulation.transmission().design_space();
        let moved: Vec<f64> = last
            .ratios
            .iter()
            .zip(&last.gradient)
            .map(|(x, g)| x - g / last.cost)
            .collect();
        let step = set
            .project(&moved)
            .iter()
            .zip(&last.ratios)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            step < 1e-2,
            "projected relative gradient step {step} at {:?}",
            last.ratios
        );
        assert_eq!(outcome.costs.len(), outcome.seconds.len());
    }

    #[test]
    fn default_starts_lie_in_the_design_space() {
        let t = transmission();
        let starts = default_starts(&t, 12);
        assert_eq!(starts.len(), 13);
        for start in starts {
            assert!(t.check_design(&start).is_ok(), "{start:?}");
        }
    }
}
