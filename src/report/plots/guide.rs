//! Dashed reference lines of a chart (limits, box edges, a motor's torque-speed envelope),
//! each with the curves it belongs to, whose colours its dashes take turns in.

use super::DrawResult;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Where a guide runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Line {
    /// y = value across the chart.
    Horizontal(f64),
    /// x = value across the chart.
    Vertical(f64),
    /// The segment between two points (x, y); the chart's range takes in both.
    Segment((f64, f64), (f64, f64)),
}

impl Line {
    /// The x values the chart's range must take in.
    pub(super) fn xs(&self) -> Vec<f64> {
        match *self {
            Line::Horizontal(_) => Vec::new(),
            Line::Vertical(x) => vec![x],
            Line::Segment(from, to) => vec![from.0, to.0],
        }
    }

    /// The y values the chart's range must take in.
    pub(super) fn ys(&self) -> Vec<f64> {
        match *self {
            Line::Horizontal(y) => vec![y],
            Line::Vertical(_) => Vec::new(),
            Line::Segment(from, to) => vec![from.1, to.1],
        }
    }

    /// Its two ends on a chart of x range `(x0, x1)` and y range `(y0, y1)`.
    pub(super) fn ends(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> [(f64, f64); 2] {
        match *self {
            Line::Horizontal(y) => [(x0, y), (x1, y)],
            Line::Vertical(x) => [(x, y0), (x, y1)],
            Line::Segment(from, to) => [from, to],
        }
    }
}

/// A dashed reference line (a limit, a box edge, an edge of a motor's torque-speed envelope)
/// with the curves it belongs to: its dashes take turns in their colours.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    /// Where it runs.
    pub line: Line,
    /// The series it belongs to, as indices into the chart's series; none: drawn in grey.
    pub owners: Vec<usize>,
    /// Its legend text, e.g. `joint_arm_2 limit`; guides of one text share one entry.
    pub label: String,
}

impl Guide {
    /// A grey guide of no series.
    pub fn plain(line: Line, label: impl Into<String>) -> Guide {
        Guide {
            line,
            owners: Vec::new(),
            label: label.into(),
        }
    }

    /// The guides of `lines`, (owner, line) pairs with owners named by `names` (indexed as the
    /// series): one guide per distinct line whose values are finite, owned by every owner of it,
    /// labelled by `what` and its owners: `joint_arm_2 limit`, or `limit of motor 1, motor 2`.
    pub fn owned(
        lines: impl IntoIterator<Item = (usize, Line)>,
        what: &str,
        names: &[String],
    ) -> Vec<Guide> {
        let mut guides: Vec<Guide> = Vec::new();
        for (owner, line) in lines {
            if !line.xs().iter().chain(&line.ys()).all(|v| v.is_finite()) {
                continue;
            }
            match guides.iter_mut().find(|guide| guide.line == line) {
                Some(guide) if !guide.owners.contains(&owner) => guide.owners.push(owner),
                Some(_) => {}
                None => guides.push(Guide {
                    line,
                    owners: vec![owner],
                    label: String::new(),
                }),
            }
        }
        for guide in &mut guides {
            let named: Vec<&str> = guide
                .owners
                .iter()
                .map(|&i| names.get(i).map_or("?", String::as_str))
                .collect();
            guide.label = match named.as_slice() {
                [one] => format!("{one} {what}"),
                _ => format!("{what} of {}", named.join(", ")),
            };
        }
        guides
    }
}

/// Draws the line between `ends` in dashes 6 px long, 4 px apart, taking turns in `colours`,
/// `width` px wide. The dashes are spaced evenly in the data, which on a log axis spaces the
/// dashes of a line along it unevenly (its guides are horizontal).
pub(super) fn draw_dashes<Y>(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<RangedCoordf64, Y>>,
    [from, to]: [(f64, f64); 2],
    colours: &[RGBAColor],
    width: u32,
) -> DrawResult
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    const DASH: f64 = 6.0;
    const STEP: f64 = 10.0;
    let (a, b) = (chart.backend_coord(&from), chart.backend_coord(&to));
    let length = f64::from(b.0 - a.0).hypot(f64::from(b.1 - a.1)).max(1.0);
    let at = |s: f64| {
        let t = (s / length).min(1.0);
        (from.0 + t * (to.0 - from.0), from.1 + t * (to.1 - from.1))
    };
    let dashes = (length / STEP).ceil() as usize;
    chart.draw_series((0..dashes).map(|k| {
        let s = k as f64 * STEP;
        let colour = colours[k % colours.len().max(1)];
        PathElement::new(vec![at(s), at(s + DASH)], colour.stroke_width(width))
    }))?;
    Ok(())
}
