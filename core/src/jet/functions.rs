//! Smooth functions of jets: a function of one variable composes through its derivatives at the
//! jet's value, f(x0 + h) = sum_k f^(k)(x0) h^k / k!, truncated at the shape's order.

use super::{Jet, MAX_ORDER};

impl<'s> Jet<'s> {
    /// f(self) for a function f whose derivatives at `self.value()` are `derivatives` (f, f',
    /// f'', ...). Derivatives beyond the shape's order are not read; missing ones count as 0.
    pub fn compose(&self, derivatives: &[f64]) -> Jet<'s> {
        let order = self.shape.order();
        let mut step = self.clone();
        step.coefficients[0] = 0.0;
        let term = |k: usize| derivatives.get(k).copied().unwrap_or(0.0) / factorial(k);
        // Horner's rule in the nilpotent step h = self - x0.
        let mut result = Jet::constant(self.shape, term(order));
        for k in (0..order).rev() {
            result = &result * &step;
            result.coefficients[0] += term(k);
        }
        result
    }

    /// sqrt(self); the value must be positive.
    pub fn sqrt(&self) -> Jet<'s> {
        self.power(0.5)
    }

    /// 1 / self; the value must be non-zero.
    pub fn recip(&self) -> Jet<'s> {
        self.power(-1.0)
    }

    /// self / other; the value of `other` must be non-zero.
    pub fn div(&self, other: &Jet<'s>) -> Jet<'s> {
        self * &other.recip()
    }

    /// self^exponent for a real exponent; the value must be positive unless the exponent is an
    /// integer.
    pub fn power(&self, exponent: f64) -> Jet<'s> {
        let x = self.value();
        let order = self.shape.order();
        // x^(e - k) from x^e by repeated division (one powf per jet, not one per order); at
        // x = 0 (an integer exponent) each power on its own.
        let mut derivatives = [0.0; MAX_ORDER + 1];
        let (mut factor, mut value) = (1.0, x.powf(exponent));
        for (k, derivative) in derivatives.iter_mut().enumerate().take(order + 1) {
            let power = if x == 0.0 {
                x.powf(exponent - k as f64)
            } else {
                value
            };
            *derivative = factor * power;
            factor *= exponent - k as f64;
            value /= x;
        }
        self.compose(&derivatives[..=order])
    }

    /// acos(self); the value must lie strictly inside (-1, 1).
    pub fn acos(&self) -> Jet<'s> {
        let y = self.value();
        let s = 1.0 - y * y;
        // s^(-1/2 - k) from one square root.
        let r1 = s.sqrt().recip();
        let r3 = r1 / s;
        let (r5, r7) = (r3 / s, r3 / (s * s));
        self.compose(&[
            y.acos(),
            -r1,
            -y * r3,
            -(1.0 + 2.0 * y * y) * r5,
            -(9.0 * y + 6.0 * y.powi(3)) * r7,
        ])
    }

    /// The angle of the plane vector (x, y) = (self, y), rad, as `f64::atan2`; (x, y) must not
    /// be at the origin.
    pub fn atan2(y: &Jet<'s>, x: &Jet<'s>) -> Jet<'s> {
        let (x0, y0) = (x.value(), y.value());
        // atan2(y, x) - atan2(y0, x0) = atan of the turn from (x0, y0) to (x, y), whose tangent
        // has value 0: the series of atan at 0 applies.
        let turn = &(y * x0) - &(x * y0);
        let along = &(x * x0) + &(y * y0);
        let tangent = turn.div(&along);
        let angle = tangent.compose(&[0.0, 1.0, 0.0, -2.0, 0.0]);
        angle.scaled(1.0, y0.atan2(x0))
    }

    /// (sin(self), cos(self)).
    pub fn sin_cos(&self) -> (Jet<'s>, Jet<'s>) {
        let (s, c) = self.value().sin_cos();
        (
            self.compose(&[s, c, -s, -c, s]),
            self.compose(&[c, -s, -c, s, c]),
        )
    }
}

/// k! as a float (k <= 20 in practice: the shapes' orders are small).
fn factorial(k: usize) -> f64 {
    (1..=k).map(|i| i as f64).product()
}
