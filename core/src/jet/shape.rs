//! The symbolic part of a jet: which monomials it keeps and how they multiply, computed once per
//! use (a linkage row at a node), apart from the numbers.

use std::collections::HashMap;

/// The highest order of a jet: its functions ([`super::Jet::compose`]'s callers) know their
/// derivatives to the fourth.
pub const MAX_ORDER: usize = 4;

/// The monomials of a truncated Taylor polynomial in `primary` variables up to total degree
/// `order`, each possibly times one of `linear` further variables (kept to first order: a design
/// parameter's sensitivity). Monomials are graded: degree 0, then 1, and so on.
#[derive(Clone, Debug)]
pub struct JetShape {
    primary: usize,
    linear: usize,
    order: usize,
    /// Each monomial as its sorted variable indices (a multiset; linear variables last).
    monomials: Vec<Vec<usize>>,
    /// Products `(a, b, c)`: monomial a times monomial b is monomial c, for every pair whose
    /// product is kept.
    products: Vec<(u32, u32, u32)>,
    /// The monomial of each multiset.
    index: HashMap<Vec<usize>, usize>,
    /// Each monomial's tail (its variables but the first), as a monomial; 0 for the constant.
    tails: Vec<usize>,
    /// Each monomial's product of the factorials of its multiplicities.
    factorials: Vec<f64>,
}

impl JetShape {
    /// The shape of jets in `primary` variables to total degree `order`, each monomial of
    /// degree at most one in `linear` further variables (numbered `primary..primary + linear`).
    pub fn new(primary: usize, linear: usize, order: usize) -> JetShape {
        let mut monomials = vec![Vec::new()];
        let mut last = vec![Vec::new()];
        for _ in 0..order {
            let mut next = Vec::new();
            for monomial in &last {
                let from = monomial.last().copied().unwrap_or(0);
                for variable in from..primary + linear {
                    let mut grown: Vec<usize> = monomial.clone();
                    grown.push(variable);
                    if grown.iter().filter(|&&v| v >= primary).count() <= 1 {
                        next.push(grown);
                    }
                }
            }
            monomials.extend(next.iter().cloned());
            last = next;
        }
        let index: HashMap<Vec<usize>, usize> = monomials
            .iter()
            .enumerate()
            .map(|(i, m)| (m.clone(), i))
            .collect();
        let mut products = Vec::new();
        for (a, left) in monomials.iter().enumerate() {
            for (b, right) in monomials.iter().enumerate() {
                if left.len() + right.len() > order {
                    break;
                }
                let mut product: Vec<usize> = left.iter().chain(right).copied().collect();
                product.sort_unstable();
                if let Some(&c) = index.get(&product) {
                    products.push((a as u32, b as u32, c as u32));
                }
            }
        }
        let tails = (monomials.iter())
            .map(|m| {
                m.get(1..)
                    .and_then(|tail| index.get(tail))
                    .copied()
                    .unwrap_or(0)
            })
            .collect();
        let factorials = monomials.iter().map(|m| factorial_of(m)).collect();
        JetShape {
            primary,
            linear,
            order,
            monomials,
            products,
            index,
            tails,
            factorials,
        }
    }

    /// The number of coefficients of a jet of this shape.
    pub fn len(&self) -> usize {
        self.monomials.len()
    }

    /// Whether jets of this shape have only their value (no variables or order 0).
    pub fn is_empty(&self) -> bool {
        self.monomials.len() <= 1
    }

    /// The number of primary variables.
    pub fn primary(&self) -> usize {
        self.primary
    }

    /// The number of variables kept to first order.
    pub fn linear(&self) -> usize {
        self.linear
    }

    /// The highest total degree kept.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Each monomial as its sorted variable indices, graded.
    pub fn monomials(&self) -> &[Vec<usize>] {
        &self.monomials
    }

    /// The monomial of the sorted multiset `variables`, if kept.
    pub fn monomial(&self, variables: &[usize]) -> Option<usize> {
        self.index.get(variables).copied()
    }

    /// The products `(a, b, c)` of kept monomials: a b = c.
    pub(super) fn products(&self) -> &[(u32, u32, u32)] {
        &self.products
    }

    /// The product of the factorials of a monomial's multiplicities: the factor from its Taylor
    /// coefficient to its partial derivative.
    pub fn multiplicity_factorial(&self, monomial: usize) -> f64 {
        self.factorials[monomial]
    }

    /// The monomial of `monomial`'s variables but its first (the constant for a monomial of one
    /// variable or none).
    pub fn tail(&self, monomial: usize) -> usize {
        self.tails[monomial]
    }
}

/// The product of the factorials of the multiplicities of the sorted `variables`.
fn factorial_of(variables: &[usize]) -> f64 {
    let mut factor = 1.0;
    let mut run = 0.0;
    for (k, variable) in variables.iter().enumerate() {
        run = if k > 0 && variables[k - 1] == *variable {
            run + 1.0
        } else {
            1.0
        };
        factor *= run;
    }
    factor
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binomial(n: usize, k: usize) -> usize {
        (0..k).fold(1, |acc, i| acc * (n - i) / (i + 1))
    }

    #[test]
    fn a_full_shape_keeps_every_monomial_up_to_its_order() {
        for (vars, order) in [(1, 4), (3, 3), (4, 4), (6, 2)] {
            let shape = JetShape::new(vars, 0, order);
            assert_eq!(shape.len(), binomial(vars + order, order));
            assert!(shape
                .monomials()
                .windows(2)
                .all(|w| w[0].len() <= w[1].len()));
        }
    }

    #[test]
    fn linear_variables_appear_at_most_once_per_monomial() {
        let shape = JetShape::new(2, 2, 3);
        assert!(shape
            .monomials()
            .iter()
            .all(|m| m.iter().filter(|&&v| v >= 2).count() <= 1));
        assert!(shape.monomial(&[0, 2]).is_some());
        assert!(shape.monomial(&[2, 3]).is_none());
        assert!(shape.monomial(&[0, 1, 3]).is_some());
        // Degree 0: 1; primary only: 2 + 3 + 4; one linear: 2 * (1 + 2 + 3).
        assert_eq!(shape.len(), 1 + 9 + 12);
    }

    #[test]
    fn multiplicities_give_the_taylor_factor() {
        let shape = JetShape::new(3, 0, 4);
        let factor = |m: &[usize]| shape.multiplicity_factorial(shape.monomial(m).unwrap());
        assert_eq!(factor(&[]), 1.0);
        assert_eq!(factor(&[0, 1, 2]), 1.0);
        assert_eq!(factor(&[1, 1]), 2.0);
        assert_eq!(factor(&[0, 0, 2, 2]), 4.0);
        assert_eq!(factor(&[2, 2, 2, 2]), 24.0);
    }
}
