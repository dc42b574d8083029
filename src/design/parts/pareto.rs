//! The Pareto front of points (actuator mass, objective value): the mass is better lower, the
//! objective lower or higher as its [`Better`] says. A pure function of the points.

use serde::{Deserialize, Serialize};

/// Which way an axis is better.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Better {
    /// Smaller values are better (a mass, a cost J*, a duration T*).
    Lower,
    /// Larger values are better (a payload capacity).
    Higher,
}

impl Better {
    /// Whether `a` is at least as good as `b`.
    fn at_least(self, a: f64, b: f64) -> bool {
        match self {
            Better::Lower => a <= b,
            Better::Higher => a >= b,
        }
    }
}

/// Whether the point `a` = (mass, value) dominates `b`: at most `b`'s mass, a value at least as
/// good (as `better` says), and strictly better in one of the two. Equal points dominate
/// neither.
pub fn dominates(a: (f64, f64), b: (f64, f64), better: Better) -> bool {
    let no_worse = a.0 <= b.0 && better.at_least(a.1, b.1);
    no_worse && (a.0 < b.0 || a.1 != b.1)
}

/// The indices of the non-dominated points of `points` (mass, value), by increasing mass (then
/// by better value), and those of the dominated ones, in the order given. Points equal to each
/// other are all on the front.
pub fn front(points: &[(f64, f64)], better: Better) -> (Vec<usize>, Vec<usize>) {
    let (mut kept, dominated): (Vec<usize>, Vec<usize>) = (0..points.len()).partition(|&i| {
        !points
            .iter()
            .any(|&other| dominates(other, points[i], better))
    });
    kept.sort_by(|&i, &j| {
        let (a, b) = (points[i], points[j]);
        let by_value = match better {
            Better::Lower => a.1.total_cmp(&b.1),
            Better::Higher => b.1.total_cmp(&a.1),
        };
        a.0.total_cmp(&b.0).then(by_value).then(i.cmp(&j))
    });
    (kept, dominated)
}

#[cfg(test)]
mod tests {
    use super::{dominates, front, Better};

    #[test]
    fn a_single_point_is_the_front() {
        assert_eq!(front(&[(1.0, 5.0)], Better::Lower), (vec![0], vec![]));
        assert_eq!(front(&[], Better::Higher), (vec![], vec![]));
    }

    /// Lighter and cheaper dominates; a trade-off keeps both, by increasing mass.
    #[test]
    fn the_front_keeps_the_trade_offs_by_mass() {
        let points = [
            (2.0, 10.0),
            (1.0, 30.0),
            (1.5, 20.0),
            (2.5, 25.0),
            (3.0, 5.0),
        ];
        let (kept, dominated) = front(&points, Better::Lower);
        assert_eq!(kept, [1, 2, 0, 4]);
        assert_eq!(dominated, [3]);
    }

    /// Equal points dominate neither: both stay. At equal mass the better value dominates; at
    /// equal value the lighter one.
    #[test]
    fn ties_and_equal_masses() {
        let points = [(1.0, 5.0), (1.0, 5.0), (1.0, 7.0), (2.0, 5.0)];
        let (kept, dominated) = front(&points, Better::Lower);
        assert_eq!(kept, [0, 1]);
        assert_eq!(dominated, [2, 3]);
        assert!(!dominates((1.0, 5.0), (1.0, 5.0), Better::Lower));
        assert!(dominates((1.0, 5.0), (1.0, 7.0), Better::Lower));
        assert!(dominates((1.0, 5.0), (1.5, 5.0), Better::Lower));
    }

    /// For a capacity larger is better: the heavier design with the larger capacity stays, the
    /// heavier one with a smaller capacity goes.
    #[test]
    fn capacity_is_better_higher() {
        let points = [(1.0, 2.0), (2.0, 3.5), (2.5, 3.0), (1.0, 1.5)];
        let (kept, dominated) = front(&points, Better::Higher);
        assert_eq!(kept, [0, 1]);
        assert_eq!(dominated, [2, 3]);
        let (kept, _) = front(&points, Better::Lower);
        assert_eq!(kept, [3]);
    }
}
