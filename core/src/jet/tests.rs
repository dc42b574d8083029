//! Jets against polynomials whose derivatives are known, identities that hold at every order,
//! and finite differences.

use super::*;

fn assert_same(a: &Jet<'_>, b: &Jet<'_>, tolerance: f64) {
    for (k, (x, y)) in a.coefficients().iter().zip(b.coefficients()).enumerate() {
        assert!(
            (x - y).abs() <= tolerance * (1.0 + x.abs().max(y.abs())),
            "coefficient {k} ({:?}): {x} against {y}",
            a.shape().monomials()[k]
        );
    }
}

#[test]
fn products_give_the_derivatives_of_polynomials() {
    let shape = JetShape::new(4, 0, 4);
    let x: Vec<Jet<'_>> = (0..4).map(|i| Jet::variable(&shape, i, 0.0)).collect();
    fn square<'s>(j: &Jet<'s>) -> Jet<'s> {
        j * j
    }
    let f = &square(&x[0]) * &square(&x[1]);
    assert_eq!(f.derivative(&[0, 0, 1, 1]), 4.0);
    assert_eq!(f.derivative(&[0, 1]), 0.0);
    assert_eq!(square(&square(&x[2])).derivative(&[2, 2, 2, 2]), 24.0);
    let product = &(&x[0] * &x[1]) * &(&x[2] * &x[3]);
    assert_eq!(product.derivative(&[0, 1, 2, 3]), 1.0);
    // Truncation: a fifth-degree product vanishes.
    assert!((&product * &x[0]).coefficients().iter().all(|&c| c == 0.0));
}

#[test]
fn products_expand_around_the_value() {
    let shape = JetShape::new(2, 0, 3);
    let (a, b) = (1.5, -0.5);
    let x = Jet::variable(&shape, 0, a);
    let y = Jet::variable(&shape, 1, b);
    // f = x^2 y: f_x = 2 x y, f_y = x^2, f_xy = 2 x, f_xx = 2 y, f_xxy = 2.
    let f = &(&x * &x) * &y;
    assert_eq!(f.value(), a * a * b);
    assert_eq!(f.derivative(&[0]), 2.0 * a * b);
    assert_eq!(f.derivative(&[1]), a * a);
    assert_eq!(f.derivative(&[0, 1]), 2.0 * a);
    assert_eq!(f.derivative(&[0, 0]), 2.0 * b);
    assert_eq!(f.derivative(&[0, 0, 1]), 2.0);
    assert_eq!(f.derivative(&[1, 1]), 0.0);
}

/// A jet in three variables away from special values.
fn sample<'s>(shape: &'s JetShape) -> Jet<'s> {
    let x = Jet::variable(shape, 0, 0.7);
    let y = Jet::variable(shape, 1, -0.3);
    let z = Jet::variable(shape, 2, 0.2);
    &(&(&x * &y) + &(&z * &z).scaled(0.5, 0.0)) + &x.scaled(0.1, 0.05)
}

#[test]
fn functions_satisfy_their_identities_at_every_order() {
    let shape = JetShape::new(3, 0, 4);
    let f = sample(&shape);
    let (sin, cos) = f.sin_cos();
    assert_same(
        &(&(&sin * &sin) + &(&cos * &cos)),
        &Jet::constant(&shape, 1.0),
        1e-14,
    );
    assert_same(&Jet::atan2(&sin, &cos), &f, 1e-14);
    let positive = f.scaled(1.0, 1.0);
    assert_same(&positive.sin_cos().1.acos(), &positive, 1e-13);
    assert_same(&(&positive.sqrt() * &positive.sqrt()), &positive, 1e-14);
    assert_same(
        &(&positive.recip() * &positive),
        &Jet::constant(&shape, 1.0),
        1e-14,
    );
    assert_same(
        &(&positive.power(0.3) * &positive.power(-1.7)),
        &positive.power(-1.4),
        1e-14,
    );
    // atan2 on the other side of the branch cut and in every quadrant.
    for angle in [3.0, -3.0, 2.0, -1.0] {
        let turned = f.scaled(1.0, angle - f.value());
        let (s, c) = turned.sin_cos();
        assert_same(&Jet::atan2(&s, &c), &turned, 1e-13);
    }
}

#[test]
fn first_and_second_derivatives_match_finite_differences() {
    let shape = JetShape::new(2, 0, 4);
    let f = |x: f64, y: f64| {
        let xj = Jet::variable(&shape, 0, x);
        let yj = Jet::variable(&shape, 1, y);
        let r = (&(&xj * &xj) + &(&yj * &yj)).scaled(1.0, 0.5).sqrt();
        Jet::atan2(&yj, &r).scaled(0.3, 0.0).acos()
    };
    let (x, y, h) = (0.4, 0.9, 1e-4);
    let value = |x, y| f(x, y).value();
    let jet = f(x, y);
    let fx = (value(x + h, y) - value(x - h, y)) / (2.0 * h);
    let fxy = (value(x + h, y + h) - value(x + h, y - h) - value(x - h, y + h)
        + value(x - h, y - h))
        / (4.0 * h * h);
    assert!((jet.derivative(&[0]) - fx).abs() < 1e-8);
    assert!((jet.derivative(&[0, 1]) - fxy).abs() < 1e-6);
    // Third and fourth: central differences of the jet's own lower derivatives.
    let d = |x, y, v: &[usize]| f(x, y).derivative(v);
    let fxyy = (d(x + h, y, &[1, 1]) - d(x - h, y, &[1, 1])) / (2.0 * h);
    assert!((jet.derivative(&[0, 1, 1]) - fxyy).abs() < 1e-6);
    let fxxyy = (d(x + h, y, &[0, 1, 1]) - d(x - h, y, &[0, 1, 1])) / (2.0 * h);
    assert!((jet.derivative(&[0, 0, 1, 1]) - fxxyy).abs() < 1e-5);
}

#[test]
fn linear_variables_give_mixed_first_order_sensitivities() {
    // f = r * x^3 with x primary and r linear: f_r = x^3, f_rx = 3 x^2, f_rxx = 6 x; f_rr is not
    // kept.
    let shape = JetShape::new(1, 1, 3);
    let x = Jet::variable(&shape, 0, 2.0);
    let r = Jet::variable(&shape, 1, 0.5);
    let f = &(&(&x * &x) * &x) * &r;
    assert_eq!(f.derivative(&[1]), 8.0);
    assert_eq!(f.derivative(&[0, 1]), 12.0);
    assert_eq!(f.derivative(&[0, 0, 1]), 12.0);
    assert_eq!(f.derivative(&[0, 0, 0]), 3.0);
    assert_eq!((&r * &r).derivative(&[1, 1]), 0.0);
}
