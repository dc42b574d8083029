//! Gradient-based co-design: projected quasi-Newton (BFGS) on the ratios, with the exact design
//! sensitivity dJ*/dr of every solve (`problem::cost_gradient`) and warm-started inner solves.
//!
//! The feasible set of designs is the box of the bounds cut by the order constraints
//! (r_i <= r_j, or r_i < r_j kept by a margin). Steps are projected onto it exactly (a small
//! active-set enumeration); a backtracking line search accepts a step when the inner problem
//! is solved (and, with the flat penalty, feasible) and the merit falls by the Armijo fraction.
//! Candidate starts (the original design and designs spread through the box) are solved once;
//! the best ones are descended from, and the best feasible design is kept. The merit is J*
//! with the flat penalty; with the graded one it is the optimal objective of the elastic
//! problem (docs/model.md, section 14), whose exact penalty makes it J* on feasible designs and
//! larger by the weighted slack elsewhere, so that descents from infeasible designs move toward
//! feasibility.

use super::outcome::{DesignOutcome, GradientIterate, MethodOutcome};
use super::penalty::{Grading, Penalty};
use super::score;
use crate::ipopt::{LinearSolver, Solution};
use crate::problem::{Formulation, ProblemKind};
use crate::solve::SolveSettings;
use crate::transmission::{DesignSpace, Transmission};
use std::fmt;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Settings of a gradient-based run; `Default` gives the values `optimize` and `reproduce` use.
#[derive(Clone, Debug, PartialEq)]
pub struct GradientSettings {
    /// Quasi-Newton iterations per descent at most.
    pub max_iterations: usize,
    /// Stop when the projected gradient step is shorter than this, or an iteration lowers the
    /// cost by less than this fraction.
    pub tolerance: f64,
    /// Halton designs solved as candidate starts beside the original design.
    pub spread: u32,
    /// Further Halton designs, solved in order only while fewer than `descents` feasible
    /// candidates are known (feasible designs can be rare: about 3% of the box at 3 kg in
    /// actuation space).
    pub fallbacks: u32,
    /// How many of the feasible candidates, best first, are descended from.
    pub descents: usize,
}

impl Default for GradientSettings {
    fn default() -> GradientSettings {
        GradientSettings {
            max_iterations: 50,
            tolerance: 1e-6,
            spread: 12,
            fallbacks: 64,
            descents: 3,
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A design with what its solve gave: the merit the descent lowers, its gradient and the inner
/// solution that warm starts the solves near it. The merit is the optimal cost J* (flat
/// penalty: only feasible designs are points) or the elastic problem's optimal penalised
/// objective (graded penalty: every solved design is one), which is J* where it is feasible.
#[derive(Clone)]
struct Point {
    ratios: Vec<f64>,
    cost: f64,
    gradient: Vec<f64>,
    solution: Solution,
    /// The optimal cost J*, when the design is feasible.
    feasible_cost: Option<f64>,
}

impl Point {
    fn iterate(&self, start: usize) -> GradientIterate {
        GradientIterate {
            start,
            ratios: self.ratios.clone(),
            cost: self.cost,
            gradient: self.gradient.clone(),
        }
    }
}

/// The inner solves of a run, with the fitness and time of each recorded in order, and the best
/// feasible point accepted so far.
struct Evaluator<'a> {
    /// The hard problem (flat penalty) or the elastic one (graded).
    formulation: &'a Formulation,
    penalty: Penalty,
    solve_settings: SolveSettings,
    costs: Vec<f64>,
    seconds: Vec<f64>,
    best: Option<Point>,
}

/// One solve of the gradient method, not yet recorded: its fitness, its solve time (None when
/// no solve ran) and the point when the descent can use it.
struct Attempt {
    fitness: f64,
    seconds: Option<f64>,
    point: Option<Point>,
}

impl Evaluator<'_> {
    /// Solves `ratios` (warm-started from `warm`) without recording it. It reads the evaluator
    /// only, so that several threads can attempt designs at once.
    fn attempt(&self, ratios: &[f64], warm: Option<&Solution>) -> Attempt {
        let solved = score::validate(self.formulation.transmission(), ratios)
            .and_then(|()| score::solve(self.formulation, &self.solve_settings, ratios, warm));
        let (result, solution) = match solved {
            Ok(solved) => solved,
            Err(verdict) => {
                return Attempt {
                    fitness: verdict.fitness(&self.penalty),
                    seconds: None,
                    point: None,
                }
            }
        };
        let verdict = score::judge(self.formulation, &result);
        let mut attempt = Attempt {
            fitness: verdict.fitness(&self.penalty),
            seconds: Some(result.solve_seconds.total),
            point: None,
        };
        // The flat penalty descends on feasible designs only: the elastic result the rule
        // reports for an infeasible design of the hard problem is not its objective.
        let flat = self.formulation.kind() == ProblemKind::Hard;
        if flat && !result.feasible {
            return attempt;
        }
        let merit = match result.elastic {
            Some(measures) => measures.objective_gradient.map(|g| (measures.objective, g)),
            None => result.cost_gradient.map(|g| (result.cost, g)),
        };
        attempt.point = merit.map(|(cost, gradient)| Point {
            ratios: ratios.to_vec(),
            cost,
            gradient,
            solution,
            feasible_cost: result.feasible.then_some(result.cost),
        });
        attempt
    }

    /// Records `attempt`'s fitness and time, in the order of the solves; its point.
    fn record(&mut self, attempt: Attempt) -> Option<Point> {
        self.seconds.extend(attempt.seconds);
        self.costs.push(attempt.fitness);
        attempt.point
    }

    /// Solves `ratios` (warm-started from `warm`) and records its fitness; the point when the
    /// descent can use it.
    fn solve(&mut self, ratios: &[f64], warm: Option<&Solution>) -> Option<Point> {
        let attempt = self.attempt(ratios, warm);
        self.record(attempt)
    }

    /// Attempts every design of `designs` cold on up to `threads` threads of this process,
    /// returning the attempts in order; each thread stops taking designs once the host asks
    /// the run to stop (the attempts it did not make are missing from the end).
    fn attempt_all(&self, designs: &[Vec<f64>], threads: usize) -> Vec<Attempt> {
        let next = AtomicUsize::new(0);
        let mut attempts: Vec<Option<Attempt>> = Vec::new();
        attempts.resize_with(designs.len(), || None);
        let made = Mutex::new(attempts);
        std::thread::scope(|scope| {
            for _ in 0..threads.clamp(1, designs.len().max(1)) {
                scope.spawn(|| loop {
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    if index >= designs.len() || crate::signals::stop_requested() {
                        return;
                    }
                    let attempt = self.attempt(&designs[index], None);
                    if let Ok(mut made) = made.lock() {
                        made[index] = Some(attempt);
                    }
                });
            }
        });
        let made = made.into_inner().unwrap_or_default();
        made.into_iter().map_while(|attempt| attempt).collect()
    }

    /// Keeps `point` as the best if it is feasible and cheaper than the best so far.
    fn keep(&mut self, point: &Point) {
        let better = |cost: f64| {
            self.best
                .as_ref()
                .is_none_or(|best| cost < best.feasible_cost.unwrap_or(f64::INFINITY))
        };
        if point.feasible_cost.is_some_and(better) {
            self.best = Some(point.clone());
        }
    }
}

/// Why a gradient-based run found no result.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GradientError {
    /// With the flat penalty, no candidate start was feasible to descend from.
    NoFeasibleStart {
        /// The candidate designs solved.
        solved: usize,
    },
    /// The host asked the run to stop (`signals::request_stop`).
    Interrupted,
}

impl fmt::Display for GradientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GradientError::NoFeasibleStart { solved } => write!(
                f,
                "the gradient method found no feasible start among {solved} candidate designs"
            ),
            GradientError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for GradientError {}

/// Runs the projected quasi-Newton method from the best candidate starts (the original design
/// and Halton-spread designs, see [`default_starts`]). With a flat `penalty` the descents start
/// from feasible candidates and lower J*, and the run fails when no candidate is feasible; with
/// a graded one they lower the elastic problem's optimal objective from any candidate, moving
/// infeasible designs toward feasibility (docs/model.md, section 14). Each solve is recorded
/// with its fitness (J*, or the penalty of an infeasible design); the best feasible accepted
/// design is the result.
pub fn optimize_gradient(
    formulation: &Formulation,
    solve: &SolveSettings,
    settings: &GradientSettings,
    penalty: Penalty,
    threads: usize,
) -> Result<DesignOutcome, GradientError> {
    let set = formulation.transmission().design_space();
    let elastic;
    let mut evaluator = Evaluator {
        formulation: match penalty.grading {
            Grading::Flat => formulation,
            Grading::Graded => {
                elastic = formulation.elastic();
                &elastic
            }
        },
        penalty,
        solve_settings: solve.clone(),
        costs: Vec::new(),
        seconds: Vec::new(),
        best: None,
    };
    let interrupted = || crate::signals::stop_requested();
    let (candidates, solved) = descent_starts(set, settings, &mut evaluator, threads);
    if interrupted() {
        return Err(GradientError::Interrupted);
    }
    if candidates.is_empty() {
        return Err(GradientError::NoFeasibleStart { solved });
    }
    let mut iterates = Vec::new();
    for (start, point) in candidates {
        descend(start, point, set, settings, &mut evaluator, &mut iterates);
        if interrupted() {
            return Err(GradientError::Interrupted);
        }
    }
    let solves = evaluator.costs.len();
    let stop_reason = format!(
        "{solved} candidate starts solved, {} descents, {} iterates, {solves} solves",
        settings.descents,
        iterates.len()
    );
    let (best_ratios, best_cost, best_solution) = match evaluator.best {
        Some(best) => (
            best.ratios,
            best.feasible_cost.expect("only feasible points are kept"),
            Some(best.solution),
        ),
        // Only a graded descent can end without a feasible design.
        None => (Vec::new(), penalty.base, None),
    };
    Ok(DesignOutcome {
        best_ratios,
        best_cost,
        costs: evaluator.costs,
        seconds: evaluator.seconds,
        stop_reason,
        method: MethodOutcome::Gradient {
            iterates,
            best_solution,
        },
    })
}

/// Solves the candidate starts cold (the fallbacks only while fewer than `descents` usable
/// ones are known: feasible ones with a flat penalty, every solved one with a graded); returns
/// the best `descents` usable ones with their start indices, and how many candidates were solved.
/// The solves run on up to `threads` threads, the fallbacks a batch of `threads` at a time; the
/// record keeps the solves the one-at-a-time order makes, and drops a batch's solves beyond the
/// candidate that made enough, so that it does not depend on `threads`.
fn descent_starts(
    set: &DesignSpace,
    settings: &GradientSettings,
    evaluator: &mut Evaluator<'_>,
    threads: usize,
) -> (Vec<(usize, Point)>, usize) {
    let transmission = evaluator.formulation.transmission();
    let starts = default_starts(transmission, settings.spread);
    let first_fallback = settings.spread + 1;
    let fallbacks = spread_designs(
        transmission,
        first_fallback..first_fallback + settings.fallbacks,
    );
    let batch = match evaluator.solve_settings.linear_solver() {
        LinearSolver::Mumps => 1,
        LinearSolver::Ldl => threads.max(1),
    };
    let designs: Vec<Vec<f64>> = starts
        .iter()
        .chain(&fallbacks)
        .map(|design| set.project(design))
        .collect();
    let enough = |candidates: &Vec<(usize, Point)>, index: usize| {
        index >= starts.len() && candidates.len() >= settings.descents
    };
    let (mut candidates, mut solved, mut index) = (Vec::new(), 0, 0);
    'batches: while index < designs.len() && !enough(&candidates, index) {
        // The starts at once; then the fallbacks a batch at a time.
        let end = match index < starts.len() {
            true => starts.len(),
            false => (index + batch).min(designs.len()),
        };
        let attempts = evaluator.attempt_all(&designs[index..end], batch);
        let complete = attempts.len() == end - index;
        for attempt in attempts {
            if enough(&candidates, index) || crate::signals::stop_requested() {
                break 'batches;
            }
            solved += 1;
            if let Some(point) = evaluator.record(attempt) {
                candidates.push((index, point));
            }
            index += 1;
        }
        if !complete {
            break;
        }
    }
    candidates.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
    candidates.truncate(settings.descents);
    (candidates, solved)
}

/// The BFGS approximation of the inverse Hessian of J*(r).
struct InverseHessian {
    h: Vec<Vec<f64>>,
    /// The diagonal it starts from and is reset to.
    scale: f64,
}

impl InverseHessian {
    /// `scale` times the identity.
    fn scaled_identity(n: usize, scale: f64) -> InverseHessian {
        let h = (0..n)
            .map(|i| (0..n).map(|j| if i == j { scale } else { 0.0 }).collect())
            .collect();
        InverseHessian { h, scale }
    }

    /// Whether it is (still, or again) the scaled identity.
    fn is_initial(&self) -> bool {
        self.h == InverseHessian::scaled_identity(self.h.len(), self.scale).h
    }

    /// -H g over the ratios not `held` (the reduced Hessian of projected Newton methods); held
    /// ratios do not move.
    fn direction(&self, gradient: &[f64], held: &[bool]) -> Vec<f64> {
        let n = gradient.len();
        (0..n)
            .map(|i| {
                if held[i] {
                    0.0
                } else {
                    -(0..n)
                        .filter(|&j| !held[j])
                        .map(|j| self.h[i][j] * gradient[j])
                        .sum::<f64>()
                }
            })
            .collect()
    }

    /// The BFGS update with step `s` and gradient change `y`, skipped unless s.y > 0:
    /// H = (I - rho s y^T) H (I - rho y s^T) + rho s s^T, rho = 1 / s.y.
    fn update(&mut self, s: &[f64], y: &[f64]) {
        let sy = dot(s, y);
        if sy <= 1e-12 {
            return;
        }
        let rho = 1.0 / sy;
        let hy: Vec<f64> = self.h.iter().map(|row| dot(row, y)).collect();
        let yhy = dot(y, &hy);
        for (i, row) in self.h.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                *entry +=
                    -rho * (s[i] * hy[j] + hy[i] * s[j]) + (rho * rho * yhy + rho) * s[i] * s[j];
            }
        }
    }
}

/// The ratios held at a bound by the gradient pointing out of the box.
fn held_at_bounds(set: &DesignSpace, x: &[f64], g: &[f64]) -> Vec<bool> {
    (0..x.len())
        .map(|i| {
            (x[i] <= set.bounds()[i][0] + 1e-9 && g[i] > 0.0)
                || (x[i] >= set.bounds()[i][1] - 1e-9 && g[i] < 0.0)
        })
        .collect()
}

/// Whether the projected gradient step from `point` is shorter than `tolerance`: a stationary
/// point of the design space.
fn is_stationary(set: &DesignSpace, point: &Point, tolerance: f64) -> bool {
    let moved: Vec<f64> = point
        .ratios
        .iter()
        .zip(&point.gradient)
        .map(|(x, g)| x - g)
        .collect();
    set.project(&moved)
        .iter()
        .zip(&point.ratios)
        .map(|(p, x)| (p - x).abs())
        .fold(0.0, f64::max)
        < tolerance
}

/// Backtracking from the full step along `direction`, projected onto the design space: the
/// first usable trial (see `Evaluator::solve`) with the Armijo decrease, and its step, within 12 halvings.
fn line_search(
    set: &DesignSpace,
    point: &Point,
    direction: &[f64],
    evaluator: &mut Evaluator<'_>,
) -> Option<(Point, Vec<f64>)> {
    let mut t = 1.0;
    for _ in 0..12 {
        let trial: Vec<f64> = point
            .ratios
            .iter()
            .zip(direction)
            .map(|(x, d)| x + t * d)
            .collect();
        let trial = set.project(&trial);
        let step: Vec<f64> = trial
            .iter()
            .zip(&point.ratios)
            .map(|(a, b)| a - b)
            .collect();
        if step.iter().all(|s| s.abs() < 1e-12) {
            return None;
        }
        if let Some(next) = evaluator.solve(&trial, Some(&point.solution)) {
            if next.cost <= point.cost + 1e-4 * dot(&point.gradient, &step) {
                return Some((next, step));
            }
        }
        t *= 0.5;
    }
    None
}

/// One descent from a candidate: quasi-Newton steps with line search until the projected
/// gradient step or the decrease is under the tolerance; appends its accepted iterates and offers
/// each to the evaluator's best.
fn descend(
    start: usize,
    mut point: Point,
    set: &DesignSpace,
    settings: &GradientSettings,
    evaluator: &mut Evaluator<'_>,
    iterates: &mut Vec<GradientIterate>,
) {
    iterates.push(point.iterate(start));
    evaluator.keep(&point);
    // The inverse Hessian starts scaled so that a unit step moves 10% of the box.
    let width = set.bounds().iter().map(|[l, u]| u - l).fold(0.0, f64::max);
    let scale = 0.1 * width / dot(&point.gradient, &point.gradient).sqrt().max(1e-12);
    let mut h = InverseHessian::scaled_identity(point.ratios.len(), scale);
    for _ in 0..settings.max_iterations {
        if is_stationary(set, &point, settings.tolerance) || crate::signals::stop_requested() {
            break;
        }
        let held = held_at_bounds(set, &point.ratios, &point.gradient);
        let direction = h.direction(&point.gradient, &held);
        let Some((next, step)) = line_search(set, &point, &direction, evaluator) else {
            // No descent along the quasi-Newton direction: restart from steepest descent once,
            // and stop when even that fails.
            if h.is_initial() {
                break;
            }
            h = InverseHessian::scaled_identity(point.ratios.len(), scale);
            continue;
        };
        let y: Vec<f64> = next
            .gradient
            .iter()
            .zip(&point.gradient)
            .map(|(a, b)| a - b)
            .collect();
        h.update(&step, &y);
        let decrease = point.cost - next.cost;
        point = next;
        iterates.push(point.iterate(start));
        evaluator.keep(&point);
        // The inner optimum is accurate to about IPOPT's tol (1e-8 relative); smaller
        // decreases are noise.
        if decrease <= settings.tolerance * point.cost.abs().max(1.0) {
            break;
        }
    }
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
    use crate::problem::Space;
    use crate::solve::{solve_design, solve_design_from};
    use crate::testing;

    fn transmission() -> Transmission {
        Transmission::from_spec(&testing::task().transmission).unwrap()
    }

    /// The gradient method's own part of an outcome: its iterates and best solution.
    fn gradient_part(outcome: &DesignOutcome) -> (&[GradientIterate], Option<&Solution>) {
        match &outcome.method {
            MethodOutcome::Gradient {
                iterates,
                best_solution,
            } => (iterates, best_solution.as_ref()),
            MethodOutcome::Cmaes { .. } => panic!("a CMA-ES outcome"),
        }
    }

    /// The candidate starts and the fallbacks solved on 1, 2 or 3 threads give the same
    /// record: the same solves in the same order, the same descents, the same best design.
    #[test]
    fn the_outcome_does_not_depend_on_the_threads() {
        // 1 kg held at rest at the ends: the designs whose motors cannot hold it are
        // infeasible at once, so that fallbacks are solved, in batches.
        let formulation = testing::held_formulation(1.0, Space::Actuation);
        let settings = GradientSettings {
            spread: 3,
            fallbacks: 8,
            descents: 3,
            // The starts alone: what the threads change.
            max_iterations: 0,
            ..GradientSettings::default()
        };
        let run = |threads: usize| {
            let solve = testing::settings();
            optimize_gradient(&formulation, &solve, &settings, Penalty::PAPER, threads).unwrap()
        };
        let one = run(1);
        // Five of the first eight candidates cannot hold the load: four fallbacks are solved
        // (on 3 threads, in batches whose last two attempts are dropped).
        assert!(
            one.stop_reason.starts_with("8 candidate starts solved"),
            "{one:?}"
        );
        for threads in [2, 3] {
            let other = run(threads);
            assert_eq!(other.costs, one.costs, "{threads} threads");
            assert_eq!(other.stop_reason, one.stop_reason, "{threads} threads");
            assert_eq!(other.best_ratios, one.best_ratios, "{threads} threads");
            assert_eq!(other.best_cost, one.best_cost, "{threads} threads");
            assert_eq!(gradient_part(&other).0, gradient_part(&one).0);
        }
    }

    #[test]
    fn descends_from_the_original_design_to_a_stationary_point() {
        // 0.5 kg: a payload the original design holds at rest (up to 0.585 kg).
        let formulation = testing::formulation(0.5, Space::Actuation);
        // The original design alone.
        let settings = GradientSettings {
            spread: 0,
            fallbacks: 0,
            descents: 1,
            ..GradientSettings::default()
        };
        let outcome = optimize_gradient(
            &formulation,
            &testing::settings(),
            &settings,
            Penalty::PAPER,
            1,
        )
        .unwrap();
        let (iterates, _) = gradient_part(&outcome);
        let first = &iterates[0];
        let last = iterates.last().unwrap();
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
        assert!(iterates.windows(2).all(|w| w[1].cost <= w[0].cost));
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
        assert_eq!(
            outcome.costs.len(),
            outcome.seconds.len(),
            "every solve ran"
        );
    }

    /// At 1.5 kg in actuation space the original design and the first Halton designs are
    /// infeasible; the graded penalty descends from the best of them to a feasible design (one
    /// that holds the load at rest too: at 3 kg, where the designs the elastic merit leads to
    /// cannot hold it, the descent ends without one).
    #[test]
    fn graded_descent_reaches_feasibility_from_an_infeasible_start() {
        let formulation = testing::held_formulation(1.5, Space::Actuation);
        let descent = GradientSettings {
            spread: 3,
            fallbacks: 0,
            descents: 1,
            ..GradientSettings::default()
        };
        let flat = optimize_gradient(
            &formulation,
            &testing::settings(),
            &descent,
            Penalty::PAPER,
            2,
        );
        let none = GradientError::NoFeasibleStart { solved: 4 };
        assert_eq!(flat, Err(none), "no start is feasible");
        let graded: Penalty = "graded".parse().unwrap();
        let settings = testing::settings();
        let outcome = optimize_gradient(&formulation, &settings, &descent, graded, 2).unwrap();
        let (iterates, best_solution) = gradient_part(&outcome);
        let first = &iterates[0];
        let start = solve_design(&formulation, &first.ratios, &settings).unwrap();
        assert!(!start.feasible, "the descent starts infeasible");
        // The merit falls along the accepted iterates, to a feasible design whose elastic solve
        // warm-started from the descent's solution gives the reported cost.
        assert!(iterates.windows(2).all(|w| w[1].cost <= w[0].cost));
        let best = solve_design_from(
            &formulation.elastic(),
            &outcome.best_ratios,
            &settings,
            best_solution,
        );
        let (best, _) = best.unwrap();
        assert!(best.feasible, "{}", best.status);
        assert!(
            (best.cost - outcome.best_cost).abs() <= 1e-6 * best.cost,
            "{} against {}",
            best.cost,
            outcome.best_cost
        );
        // Every solve's fitness is recorded: the penalty band for infeasible ones.
        assert_eq!(outcome.costs.len(), outcome.seconds.len());
        assert!(outcome.costs.iter().any(|&c| (1e6..2e6).contains(&c)));
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
