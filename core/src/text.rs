//! How numbers and names are written in messages: numbers as people write them, never a
//! 300-digit expansion; names from files on one line, with nothing that steers a terminal; and
//! text that reaches SVG or HTML with only the characters XML allows.

use std::borrow::Cow;
use std::fmt;

/// `x` as written in messages: plainly (`0.3`, `600`) in the usual range, in exponent form
/// (`1e300`, `1e-300`) far outside it.
///
/// ```
/// use codesign_core::text::number;
///
/// assert_eq!(number(0.3).to_string(), "0.3");
/// assert_eq!(number(1e300).to_string(), "1e300");
/// ```
pub fn number(x: f64) -> impl fmt::Display {
    Number(x)
}

/// `x` rounded to three significant digits and written as [`number`] writes it: `0.931`,
/// `1230`, `1.23e-5`; a measured value, where more digits would be noise.
pub fn rounded(x: f64) -> impl fmt::Display {
    Number(format!("{x:.2e}").parse().unwrap_or(x))
}

/// `values` as written in messages ([`number`]), separated by commas: `1.7, 0.5, 100`.
pub fn numbers(values: &[f64]) -> String {
    let texts: Vec<String> = values.iter().map(|&v| number(v).to_string()).collect();
    texts.join(", ")
}

/// The values of a list a message echoes at most ([`listed`]).
const ECHOED: usize = 16;

/// `values` (a list a user gave, echoed in a message) as [`numbers`] writes them, at most the
/// first 16 followed by how many there are: `50, 50, .., 50, ... (1000000 values)`, so that no
/// list makes a message longer than a line or two.
pub fn listed(values: &[f64]) -> String {
    if values.len() <= ECHOED {
        return numbers(values);
    }
    format!(
        "{}, ... ({} values)",
        numbers(&values[..ECHOED]),
        values.len()
    )
}

/// `name` (a link's or joint's, read from a file) as a terminal may show it: each control
/// character (a newline, an escape) and each character that reorders text (U+202A-U+202E,
/// U+2066-U+2069, U+200E, U+200F) written as its escape, `\n`, `\u{202e}`.
pub fn shown(name: &str) -> String {
    let steers = |c: char| {
        c.is_control()
            || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{200e}' | '\u{200f}')
    };
    let mut text = String::with_capacity(name.len());
    for c in name.chars() {
        if steers(c) {
            text.extend(c.escape_default());
        } else {
            text.push(c);
        }
    }
    text
}

/// `text` (a document of SVG or HTML, or text bound for one) with each control character but
/// tab, newline and carriage return (those XML 1.0 refuses, and those it discourages) and
/// U+FFFE and U+FFFF written as their escapes: an escape, U+001B, as `\u{1b}`. A name read from
/// a task (`motors.names`, a file's name) may hold any of them; a browser refuses a whole SVG
/// document over one.
pub fn markup_safe(text: &str) -> Cow<'_, str> {
    let refused = |c: char| {
        (c.is_control() && !matches!(c, '\t' | '\n' | '\r')) || matches!(c, '\u{fffe}' | '\u{ffff}')
    };
    if !text.contains(refused) {
        return Cow::Borrowed(text);
    }
    let mut safe = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match refused(c) {
            true => safe.extend(c.escape_unicode()),
            false => safe.push(c),
        }
    }
    Cow::Owned(safe)
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
    use super::{listed, markup_safe, number, numbers, rounded, shown};

    #[test]
    fn a_long_list_is_echoed_with_its_length() {
        assert_eq!(listed(&[1e308, 5e-324]), "1e308, 5e-324");
        let many = listed(&vec![50.0; 1_000_000]);
        assert!(many.ends_with("50, 50, ... (1000000 values)"), "{many}");
        assert_eq!(many.matches("50").count(), 16);
        assert_eq!(listed(&[2.0; 16]), numbers(&[2.0; 16]));
    }

    #[test]
    fn markup_holds_only_the_characters_xml_allows() {
        assert_eq!(markup_safe("el\u{1b}[31mbow"), "el\\u{1b}[31mbow");
        assert_eq!(
            markup_safe("a\u{0}b\u{7f}\u{fffe}"),
            "a\\u{0}b\\u{7f}\\u{fffe}"
        );
        assert_eq!(markup_safe("one\ttwo\nthree\r é"), "one\ttwo\nthree\r é");
    }

    #[test]
    fn names_stay_on_one_line_and_in_order() {
        assert_eq!(shown("grip\n|per"), "grip\\n|per");
        assert_eq!(shown("ab\u{202e}cd"), "ab\\u{202e}cd");
        assert_eq!(shown("link_4 é"), "link_4 é");
    }

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
        let three = |x: f64| rounded(x).to_string();
        assert_eq!(three(0.93125), "0.931");
        assert_eq!(three(1234.5), "1230");
        assert_eq!(three(0.1 * 3.0), "0.3");
        assert_eq!(three(1.23456e-5), "1.23e-5");
        assert_eq!(three(0.0), "0");
    }
}
