//! How numbers are written in messages: as people write them, never a 300-digit expansion.

use std::fmt;

/// `x` as written in messages: plainly (`0.3`, `600`) in the usual range, in exponent form
/// (`1e300`, `1e-300`) far outside it.
pub fn number(x: f64) -> impl fmt::Display {
    Number(x)
}

/// `values` as written in messages ([`number`]), separated by commas: `1.7, 0.5, 100`.
pub fn numbers(values: &[f64]) -> String {
    let texts: Vec<String> = values.iter().map(|&v| number(v).to_string()).collect();
    texts.join(", ")
}

struct Number(f64);

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let size = self.0.abs();
        if size == 0.0 || !size.is_finite() || (1e-4..1e15).contains(&size) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{number, numbers};

    #[test]
    fn plain_in_the_usual_range_and_exponents_outside() {
        let shown = |x: f64| number(x).to_string();
        assert_eq!(shown(0.3), "0.3");
        assert_eq!(shown(600.0), "600");
        assert_eq!(shown(-1.0), "-1");
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-1e-300), "-1e-300");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(numbers(&[1.7, 1e-300, 100.0]), "1.7, 1e-300, 100");
        assert_eq!(numbers(&[]), "");
    }
}
