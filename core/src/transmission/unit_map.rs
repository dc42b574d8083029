//! The map from the unit box [0, 1]^p onto the design space (docs/model.md, section 4): every
//! point of the box is a design within the bounds and the order constraints, and every such
//! design is the image of a point of the box. A search over the box (CMA-ES under
//! `--bounds map`) thus draws valid designs only.
//!
//! The ratios are placed one at a time, in an order where the smaller side of every order
//! constraint comes first. Each ratio's interval is its bounds narrowed by what the constraints
//! imply through the ratios on either side (so that every later ratio keeps some room), and
//! raised above the ratios already placed below it; the box coordinate picks the point of that
//! interval linearly.

use super::design_space::{DesignSpace, OrderConstraint, STRICT_MARGIN};
use crate::text::number;
use std::fmt;

/// Why the design space cannot be mapped from the unit box.
#[derive(Clone, Debug, PartialEq)]
pub enum UnitMapError {
    /// The order constraints among these ratios (0-based) form a cycle.
    Cycle(Vec<usize>),
    /// The bounds and order constraints leave ratio `index` (0-based) no value: it must be at
    /// least `lower` and at most `upper`, with `lower > upper`.
    Empty {
        /// The ratio.
        index: usize,
        /// The least value the constraints allow it.
        lower: f64,
        /// The largest value they allow it.
        upper: f64,
    },
}

impl fmt::Display for UnitMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnitMapError::Cycle(ratios) => {
                let names: Vec<String> = ratios.iter().map(|i| format!("r{}", i + 1)).collect();
                write!(
                    f,
                    "transmission.order: the constraints among {} form a cycle, which the map \
                     from the unit box cannot order (a cycle of <= makes those ratios equal: \
                     write one ratio for them)",
                    names.join(", ")
                )
            }
            UnitMapError::Empty {
                index,
                lower,
                upper,
            } => write!(
                f,
                "transmission.bounds and transmission.order leave r{} no value: the order \
                 constraints ask it to be at least {} and at most {} (a strict < keeps a margin \
                 of {})",
                index + 1,
                number(*lower),
                number(*upper),
                number(STRICT_MARGIN)
            ),
        }
    }
}

impl std::error::Error for UnitMapError {}

/// The continuous map u -> r from [0, 1]^p onto the design space and a right inverse r -> u
/// (docs/model.md, section 4). A strict constraint r_i < r_j is mapped as r_j >= r_i + 1e-6,
/// the margin [`DesignSpace::halfspaces`] keeps: the designs closer than that to its equality
/// are the only ones of the space the map does not reach.
#[derive(Clone, Debug)]
pub struct UnitMap {
    /// The ratios in the order they are placed: the smaller side of every constraint first.
    order: Vec<usize>,
    /// Per ratio, the constraints whose larger side it is: (the smaller ratio, the margin).
    below: Vec<Vec<(usize, f64)>>,
    /// Per ratio, its lower bound raised by the chains of constraints below it.
    lowest: Vec<f64>,
    /// Per ratio, its upper bound lowered by the chains of constraints above it.
    highest: Vec<f64>,
}

/// The margin a constraint keeps between its two ratios: 1e-6 when strict, else 0.
fn margin(constraint: &OrderConstraint) -> f64 {
    if constraint.strict {
        STRICT_MARGIN
    } else {
        0.0
    }
}

/// The ratios ordered so that every constraint's smaller side comes before its larger one,
/// the lowest index first among those free to come next; the ratios of a cycle when there is
/// none.
fn placing_order(count: usize, constraints: &[OrderConstraint]) -> Result<Vec<usize>, Vec<usize>> {
    let mut waiting = vec![0usize; count];
    for c in constraints {
        waiting[c.upper] += 1;
    }
    let mut order = Vec::with_capacity(count);
    let mut placed = vec![false; count];
    while let Some(next) = (0..count).find(|&i| !placed[i] && waiting[i] == 0) {
        placed[next] = true;
        order.push(next);
        for c in constraints.iter().filter(|c| c.lower == next) {
            waiting[c.upper] -= 1;
        }
    }
    if order.len() == count {
        Ok(order)
    } else {
        Err((0..count).filter(|&i| !placed[i]).collect())
    }
}

impl UnitMap {
    /// The map of `space`; fails when its order constraints form a cycle or leave a ratio no
    /// value.
    pub fn new(space: &DesignSpace) -> Result<UnitMap, UnitMapError> {
        let count = space.num_ratios();
        let constraints = space.order();
        let order = placing_order(count, constraints).map_err(UnitMapError::Cycle)?;
        let mut below = vec![Vec::new(); count];
        let mut above = vec![Vec::new(); count];
        for c in constraints {
            below[c.upper].push((c.lower, margin(c)));
            above[c.lower].push((c.upper, margin(c)));
        }
        let mut lowest: Vec<f64> = space.bounds().iter().map(|b| b[0]).collect();
        let mut highest: Vec<f64> = space.bounds().iter().map(|b| b[1]).collect();
        for &i in &order {
            for &(j, m) in &below[i] {
                lowest[i] = lowest[i].max(lowest[j] + m);
            }
        }
        for &i in order.iter().rev() {
            for &(j, m) in &above[i] {
                highest[i] = highest[i].min(highest[j] - m);
            }
        }
        if let Some(index) = (0..count).find(|&i| lowest[i] > highest[i]) {
            return Err(UnitMapError::Empty {
                index,
                lower: lowest[index],
                upper: highest[index],
            });
        }
        Ok(UnitMap {
            order,
            below,
            lowest,
            highest,
        })
    }

    /// Number of ratios (the dimension of the box).
    pub fn num_ratios(&self) -> usize {
        self.lowest.len()
    }

    /// The interval [low, high] of ratio `i` given the ratios placed before it in `r`.
    fn interval(&self, i: usize, r: &[f64]) -> (f64, f64) {
        let low = (self.below[i].iter()).fold(self.lowest[i], |low, &(j, m)| low.max(r[j] + m));
        (low, self.highest[i])
    }

    /// The design of the point `u` of the unit box: ratio by ratio in the placing order,
    /// r_i = low_i + u_i (high_i - low_i), where high_i is r_i's upper bound lowered by the
    /// constraints above it and low_i its lower bound raised by the constraints below it and by
    /// the ratios already placed below it (plus 1e-6 for a strict constraint). A coordinate
    /// outside [0, 1] is taken at the nearer end.
    ///
    /// ```
    /// use codesign_core::model::task::Task;
    /// use codesign_core::transmission::{Transmission, UnitMap};
    ///
    /// // The belt arm: bounds [1, 9]^2 x [1, 3]^2 and the order r3 <= r2 < r1.
    /// let spec = Task::built_in()?.transmission;
    /// let space = Transmission::from_spec(&spec)?.design_space().clone();
    /// let map = UnitMap::new(&space)?;
    /// for u in [[0.0; 4], [1.0; 4], [0.2, 0.9, 0.5, 0.0]] {
    ///     assert!(space.check(&map.design(&u)).is_ok());
    /// }
    /// // r3 first, in [1, 3]; then r2 in [r3, 9 - 1e-6]; then r1 in [r2 + 1e-6, 9].
    /// let r = map.design(&[0.5, 0.5, 0.5, 0.5]);
    /// assert_eq!(r[2], 2.0);
    /// assert!((r[1] - (2.0 + 0.5 * (7.0 - 1e-6))).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn design(&self, u: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.num_ratios()];
        for &i in &self.order {
            let (low, high) = self.interval(i, &r);
            // Rounding may put low an ulp above high after a strict margin: high then.
            r[i] = (low + u[i].clamp(0.0, 1.0) * (high - low)).clamp(low.min(high), high);
        }
        r
    }

    /// The point of the unit box whose design is `r`, for r in the space (within its strict
    /// margins): u_i = (r_i - low_i) / (high_i - low_i), with low_i and high_i as in
    /// [`UnitMap::design`]; 0.5 where the interval is a single point. A design the map does not
    /// reach gets its coordinates clamped to [0, 1], whose design is then another one.
    pub fn unit(&self, r: &[f64]) -> Vec<f64> {
        let mut u = vec![0.5; self.num_ratios()];
        for &i in &self.order {
            let (low, high) = self.interval(i, r);
            if high > low {
                u[i] = ((r[i] - low) / (high - low)).clamp(0.0, 1.0);
            }
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::DesignRng;
    use crate::transmission::fixtures::belt_arm;

    fn space(bounds: Vec<[f64; 2]>, order: &[(usize, usize, bool)]) -> DesignSpace {
        let original = bounds.iter().map(|b| b[0]).collect();
        let order = (order.iter())
            .map(|&(lower, upper, strict)| OrderConstraint {
                lower,
                upper,
                strict,
            })
            .collect();
        DesignSpace::new(original, bounds, order)
    }

    fn random_points(dim: usize, count: usize, seed: u64) -> Vec<Vec<f64>> {
        let mut rng = DesignRng::new(seed);
        (0..count)
            .map(|_| (0..dim).map(|_| rng.uniform()).collect())
            .collect()
    }

    /// Spaces with bounds that the order narrows, a chain, a diamond, a ratio between two
    /// others, fixed ratios and a space without order.
    fn spaces() -> Vec<DesignSpace> {
        vec![
            belt_arm().design_space().clone(),
            // r1 < r2 < r3 in overlapping bounds.
            space(
                vec![[0.0, 5.0], [2.0, 3.0], [1.0, 4.0]],
                &[(0, 1, true), (1, 2, true)],
            ),
            // A diamond: r1 <= r2, r1 <= r3, r2 < r4, r3 <= r4.
            space(
                vec![[-1.0, 1.0], [0.0, 2.0], [-5.0, 0.5], [0.0, 1.0]],
                &[(0, 1, false), (0, 2, false), (1, 3, true), (2, 3, false)],
            ),
            // r3 <= r1 and r3 <= r2 with r3 fixed, r2 fixed.
            space(
                vec![[1.0, 9.0], [4.0, 4.0], [2.0, 2.0]],
                &[(2, 0, false), (2, 1, false)],
            ),
            space(vec![[1.0, 2.0], [-3.0, 3.0]], &[]),
        ]
    }

    #[test]
    fn every_point_of_the_box_is_a_design_of_the_space() {
        for space in spaces() {
            let map = UnitMap::new(&space).unwrap();
            let n = space.num_ratios();
            let mut points = random_points(n, 2000, 7);
            // The corners of the box.
            points.extend(
                (0..1 << n).map(|mask: usize| (0..n).map(|i| ((mask >> i) & 1) as f64).collect()),
            );
            for u in &points {
                let r = map.design(u);
                assert!(
                    space.check(&r).is_ok(),
                    "{u:?} -> {r:?}: {:?}",
                    space.check(&r)
                );
            }
        }
    }

    #[test]
    fn the_design_of_the_inverse_is_the_design() {
        for space in spaces() {
            let map = UnitMap::new(&space).unwrap();
            let n = space.num_ratios();
            for u in random_points(n, 500, 11) {
                let r = map.design(&u);
                let back = map.unit(&r);
                assert!(back.iter().all(|v| (0.0..=1.0).contains(v)), "{back:?}");
                let again = map.design(&back);
                for (a, b) in again.iter().zip(&r) {
                    assert!(
                        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                        "{r:?} -> {again:?}"
                    );
                }
                // Where no interval is a point, the box point comes back too.
                if space.bounds().iter().all(|[lo, hi]| lo < hi) {
                    for (a, b) in back.iter().zip(&u) {
                        assert!((a - b).abs() < 1e-9, "{u:?} -> {back:?}");
                    }
                }
            }
        }
        // The belt arm's original design, and designs on its faces.
        let space = belt_arm().design_space().clone();
        let map = UnitMap::new(&space).unwrap();
        for r in [
            [6.0, 3.0, 1.0, 1.0],
            [9.0, 3.0, 3.0, 3.0],
            [9.0, 9.0 - 1e-6, 3.0, 1.0],
            [1.0 + 1e-6, 1.0, 1.0, 2.0],
        ] {
            let again = map.design(&map.unit(&r));
            assert!(
                again.iter().zip(&r).all(|(a, b)| (a - b).abs() < 1e-12),
                "{r:?} -> {again:?}"
            );
        }
    }

    #[test]
    fn the_map_is_continuous_and_monotone_along_a_coordinate() {
        let space = belt_arm().design_space().clone();
        let map = UnitMap::new(&space).unwrap();
        // Along u3 (r3, placed first), r3 rises and r2 follows it where r3 lifts its floor.
        let mut previous = map.design(&[0.5, 0.0, 0.0, 0.5]);
        for step in 1..=1000 {
            let t = step as f64 / 1000.0;
            let r = map.design(&[0.5, 0.0, t, 0.5]);
            let jump: f64 = r.iter().zip(&previous).map(|(a, b)| (a - b).abs()).sum();
            assert!(jump < 0.01, "a jump of {jump} at u3 = {t}");
            assert!(r[2] >= previous[2] && r[1] >= previous[1]);
            previous = r;
        }
        assert_eq!(previous[2], 3.0);
        assert_eq!(previous[1], 3.0, "r2 at its floor r3");
    }

    #[test]
    fn cycles_and_empty_spaces_are_refused_by_name() {
        let cycle = space(
            vec![[1.0, 2.0], [1.0, 2.0], [1.0, 2.0]],
            &[(0, 1, false), (1, 2, false), (2, 0, false)],
        );
        let error = UnitMap::new(&cycle).unwrap_err();
        assert_eq!(error, UnitMapError::Cycle(vec![0, 1, 2]));
        assert!(error
            .to_string()
            .starts_with("transmission.order: the constraints among r1, r2, r3 form a cycle"));
        let empty = space(vec![[2.0, 3.0], [0.0, 2.0]], &[(0, 1, true)]);
        let error = UnitMap::new(&empty).unwrap_err();
        assert!(
            matches!(error, UnitMapError::Empty { index: 0, .. }),
            "{error:?}"
        );
        assert!(error
            .to_string()
            .starts_with("transmission.bounds and transmission.order leave r1 no value"));
        // Touching bounds under <= leave exactly one design.
        let single = space(vec![[2.0, 3.0], [0.0, 2.0]], &[(0, 1, false)]);
        let map = UnitMap::new(&single).unwrap();
        for u in random_points(2, 20, 3) {
            assert_eq!(map.design(&u), [2.0, 2.0]);
        }
        assert_eq!(map.unit(&[2.0, 2.0]), [0.5, 0.5]);
    }

    #[test]
    fn coordinates_outside_the_box_are_taken_at_its_faces() {
        let space = belt_arm().design_space().clone();
        let map = UnitMap::new(&space).unwrap();
        assert_eq!(
            map.design(&[-1.0, 2.0, -0.5, 7.0]),
            map.design(&[0.0, 1.0, 0.0, 1.0])
        );
        // An invalid design's coordinates are clamped: its image is a design of the space.
        let u = map.unit(&[2.0, 8.0, 3.5, 0.0]);
        assert!(u.iter().all(|v| (0.0..=1.0).contains(v)));
        assert!(space.check(&map.design(&u)).is_ok());
    }
}
