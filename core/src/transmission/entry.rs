//! One entry of G, or one number of a linkage: a constant or a multiple of one design ratio, as
//! parsed from the task's `transmission` section.

use crate::model::task::MatrixEntry;

/// One entry of G: a constant or a multiple of one design ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Entry {
    Constant(f64),
    /// `scale * r[index]` (index 0-based; scale finite and non-zero: +-1 for `[-]r<i>`).
    Ratio {
        index: usize,
        scale: f64,
    },
}

impl Entry {
    /// The entry's value at the design `r`.
    pub(super) fn value(&self, r: &[f64]) -> f64 {
        match *self {
            Entry::Constant(value) => value,
            Entry::Ratio { index, scale } => scale * r[index],
        }
    }

    /// The design parameter the entry is a multiple of, if any.
    pub(super) fn parameter(&self) -> Option<usize> {
        match *self {
            Entry::Constant(_) => None,
            Entry::Ratio { index, .. } => Some(index),
        }
    }
}

/// The largest magnitude of a number of the transmission (an entry of G, a factor k of `k*r<i>`,
/// a bound): 1e6, beyond any gear ratio or screw (a 1 mm lead is 6283 rad/m), and small enough
/// that every product the problem forms of them and the motors' limits stays finite (an entry
/// of 1e308 times a ratio of 9 would be infinite).
pub const MAX_MAGNITUDE: f64 = 1e6;

/// Parses `r<i>` (1-based) into a 0-based index below `count`.
pub(super) fn parse_ratio_name(text: &str, count: usize) -> Option<usize> {
    let digits = text.trim().strip_prefix('r')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let number: usize = digits.parse().ok()?;
    (1..=count).contains(&number).then(|| number - 1)
}

/// Parses `r<i>`, `-r<i>` or `k*r<i>` (k a finite non-zero number).
fn parse_entry(text: &str, count: usize) -> Option<Entry> {
    let text = text.trim();
    let (scale, name) = match text.split_once('*') {
        Some((factor, name)) => (factor.trim().parse::<f64>().ok()?, name),
        None => match text.strip_prefix('-') {
            Some(rest) => (-1.0, rest),
            None => (1.0, text),
        },
    };
    if !(scale.is_finite() && scale != 0.0 && scale.abs() <= MAX_MAGNITUDE) {
        return None;
    }
    let index = parse_ratio_name(name, count)?;
    Some(Entry::Ratio { index, scale })
}

/// Parses an entry or a linkage's number: a finite number of magnitude at most
/// [`MAX_MAGNITUDE`], or `[-]r<i>` / `k*r<i>` of one of `count` ratios.
pub(super) fn parse_number(entry: &MatrixEntry, count: usize) -> Option<Entry> {
    match entry {
        MatrixEntry::Constant(value) if value.abs() <= MAX_MAGNITUDE => {
            Some(Entry::Constant(*value))
        }
        MatrixEntry::Constant(_) => None,
        MatrixEntry::Ratio(text) => parse_entry(text, count),
    }
}
