//! The candidate starts of the gradient method: the original design and designs spread through
//! the box by the Halton sequence, solved cold, with fallbacks while too few are usable.

use super::{GradientError, GradientSettings, Point, Solves};
use codesign_core::transmission::Transmission;
use std::ops::Range;

/// Solves the candidate starts cold (the fallbacks only while fewer than `descents` usable
/// ones are known: feasible ones with a flat penalty, every solved one with a graded); returns
/// the best `descents` usable ones with their start indices, and how many candidates were solved.
/// The starts go to the evaluator at once, the fallbacks a batch of its parallelism at a time;
/// the record keeps the solves the one-at-a-time order makes, and drops a batch's solves beyond
/// the candidate that made enough, so that it does not depend on the parallelism.
pub(super) fn descent_starts(
    transmission: &Transmission,
    settings: &GradientSettings,
    solves: &mut Solves<'_>,
) -> Result<(Vec<(usize, Point)>, usize), GradientError> {
    let set = transmission.design_space();
    let starts = default_starts(transmission, settings.spread);
    let first_fallback = settings.spread + 1;
    let fallbacks = spread_designs(
        transmission,
        first_fallback..first_fallback + settings.fallbacks,
    );
    let batch = solves.evaluator.parallelism().max(1);
    let designs: Vec<(usize, Vec<f64>)> = starts
        .iter()
        .chain(&fallbacks)
        .map(|design| set.project(design))
        .enumerate()
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
        for descent in solves.evaluator.descend(&designs[index..end], &[])? {
            if enough(&candidates, index) || codesign_core::signals::stop_requested() {
                break 'batches;
            }
            solved += 1;
            if let Some(point) = solves.record(descent, &[]) {
                candidates.push((index, point));
            }
            index += 1;
        }
    }
    candidates.sort_by(|a, b| a.1.merit.value.total_cmp(&b.1.merit.value));
    candidates.truncate(settings.descents);
    Ok((candidates, solved))
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
