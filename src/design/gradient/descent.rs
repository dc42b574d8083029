//! One descent of the gradient method: projected quasi-Newton steps (BFGS on the inverse
//! Hessian, reduced to the ratios not held at a bound) with a backtracking line search.

use super::{GradientError, GradientSettings, Point, Solves};
use crate::design::outcome::GradientIterate;
use crate::parallel;
use codesign_core::signals;
use codesign_core::transmission::DesignSpace;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
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
        .zip(&point.merit.gradient)
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
/// first usable trial (see `Solves::solve`) with the Armijo decrease, and its step, within 12
/// halvings.
fn line_search(
    set: &DesignSpace,
    point: &Point,
    direction: &[f64],
    solves: &mut Solves<'_>,
) -> Result<Option<(Point, Vec<f64>)>, GradientError> {
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
            return Ok(None);
        }
        if let Some(next) = solves.solve(&trial, &point.merit.starts)? {
            let (merit, gradient) = (point.merit.value, &point.merit.gradient);
            if next.merit.value <= merit + 1e-4 * dot(gradient, &step) {
                return Ok(Some((next, step)));
            }
        }
        t *= 0.5;
    }
    Ok(None)
}

/// The descents from `candidates` (start index and point), side by side on as many threads as
/// the evaluator's parallelism, each recording its own solves; appends their solves to `solves`
/// in the order of the candidates, as one descent after the other would have made them, and
/// returns their accepted iterates in that order.
pub(super) fn descend_all(
    candidates: &[(usize, Point)],
    set: &DesignSpace,
    settings: &GradientSettings,
    solves: &mut Solves<'_>,
) -> Result<Vec<GradientIterate>, GradientError> {
    let evaluator = solves.evaluator;
    type Made<'e> = Result<(Solves<'e>, Vec<GradientIterate>), GradientError>;
    let one = |index: usize| -> Made<'_> {
        let (start, point) = candidates[index].clone();
        let mut own = Solves::new(evaluator);
        let mut iterates = Vec::new();
        descend(start, point, set, settings, &mut own, &mut iterates)?;
        Ok((own, iterates))
    };
    let threads = evaluator.parallelism();
    let heard = |_: usize, _: &_| Ok::<(), std::convert::Infallible>(());
    let Ok(descents) = parallel::in_order(
        candidates.len(),
        threads,
        signals::stop_requested,
        one,
        heard,
    );
    let mut iterates = Vec::new();
    for descent in descents {
        let (own, accepted) = descent.ok_or(GradientError::Interrupted)??;
        solves.append(own);
        iterates.extend(accepted);
        if signals::stop_requested() {
            return Err(GradientError::Interrupted);
        }
    }
    Ok(iterates)
}

/// One descent from a candidate: quasi-Newton steps with line search until the projected
/// gradient step or the decrease is under the tolerance; appends its accepted iterates and offers
/// each to the run's best.
fn descend(
    start: usize,
    mut point: Point,
    set: &DesignSpace,
    settings: &GradientSettings,
    solves: &mut Solves<'_>,
    iterates: &mut Vec<GradientIterate>,
) -> Result<(), GradientError> {
    iterates.push(point.iterate(start));
    solves.keep(&point);
    // The inverse Hessian starts scaled so that a unit step moves 10% of the box.
    let width = set.bounds().iter().map(|[l, u]| u - l).fold(0.0, f64::max);
    let scale = 0.1 * width
        / dot(&point.merit.gradient, &point.merit.gradient)
            .sqrt()
            .max(1e-12);
    let mut h = InverseHessian::scaled_identity(point.ratios.len(), scale);
    for _ in 0..settings.max_iterations {
        if is_stationary(set, &point, settings.tolerance) || signals::stop_requested() {
            break;
        }
        let held = held_at_bounds(set, &point.ratios, &point.merit.gradient);
        let direction = h.direction(&point.merit.gradient, &held);
        let Some((next, step)) = line_search(set, &point, &direction, solves)? else {
            // No descent along the quasi-Newton direction: restart from steepest descent once,
            // and stop when even that fails.
            if h.is_initial() {
                break;
            }
            h = InverseHessian::scaled_identity(point.ratios.len(), scale);
            continue;
        };
        let y: Vec<f64> = next
            .merit
            .gradient
            .iter()
            .zip(&point.merit.gradient)
            .map(|(a, b)| a - b)
            .collect();
        h.update(&step, &y);
        let decrease = point.merit.value - next.merit.value;
        point = next;
        iterates.push(point.iterate(start));
        solves.keep(&point);
        // The inner optimum is accurate to about IPOPT's tol (1e-8 relative); smaller
        // decreases are noise.
        if decrease <= settings.tolerance * point.merit.value.abs().max(1.0) {
            break;
        }
    }
    Ok(())
}
