//! The marks of the poses' drawings: a panel's map from the world to px, the base, the
//! linkages, the scale bar, and texts kept inside the picture (wrapped, or moved in from its
//! edges).

use codesign_core::text::markup_safe;
use nalgebra::Vector3;
use std::fmt::Write;

use super::Plane;

/// The width of a character of sans-serif text per px of its size, taken wide: texts placed
/// by it stay inside their picture at every common sans-serif font.
const CHARACTER: f64 = 0.62;

/// `text` with the characters XML reserves escaped, and those it refuses written as their
/// escapes ([`markup_safe`]).
fn escape(text: &str) -> String {
    markup_safe(text)
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The width `text` takes at `size` px, at most, px.
fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * size * CHARACTER
}

/// `text` cut at spaces into lines no wider than `width` px at `size` px (a word longer than a
/// line keeps a line of its own).
pub(super) fn wrap(text: &str, size: f64, width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), size) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

/// Writes `lines` at `size` px from (`x`, `top`), one under the other; returns the height
/// they take, px.
pub(super) fn text_lines(
    svg: &mut String,
    lines: &[String],
    (x, top): (f64, f64),
    size: f64,
) -> f64 {
    let step = size * 1.3;
    for (k, line) in lines.iter().enumerate() {
        let _ = write!(
            svg,
            r##"<text x="{x:.1}" y="{:.1}" font-size="{size}">{}</text>"##,
            top + size + step * k as f64,
            escape(line)
        );
    }
    step * lines.len() as f64
}

/// A square panel of a drawing: the map from a plane of the world (m) to `size` px at
/// (`left`, `top`), one scale for both axes, the vertical axis pointing up, a margin of 12 %.
pub(super) struct Panel<'p> {
    plane: &'p Plane,
    left: f64,
    top: f64,
    size: f64,
    /// px per m.
    scale: f64,
    centre: [f64; 2],
}

impl<'p> Panel<'p> {
    /// The panel of `plane` at (`left`, `top`), `size` px square.
    pub(super) fn new(plane: &'p Plane, (left, top): (f64, f64), size: f64) -> Panel<'p> {
        let (lower, upper) = plane.bounds;
        let span = (upper[0] - lower[0]).max(upper[1] - lower[1]).max(1e-6);
        Panel {
            plane,
            left,
            top,
            size,
            scale: 0.76 * size / span,
            centre: [(lower[0] + upper[0]) / 2.0, (lower[1] + upper[1]) / 2.0],
        }
    }

    /// A world point's place in the panel, px.
    pub(super) fn at(&self, point: &Vector3<f64>) -> (f64, f64) {
        let p = self.plane.project(point);
        (
            self.left + self.size / 2.0 + (p[0] - self.centre[0]) * self.scale,
            self.top + self.size / 2.0 - (p[1] - self.centre[1]) * self.scale,
        )
    }

    /// World points as SVG's `points` attribute.
    pub(super) fn points(&self, of: &[Vector3<f64>]) -> String {
        let pairs: Vec<String> = of
            .iter()
            .map(|p| {
                let (x, y) = self.at(p);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        pairs.join(" ")
    }

    /// A label of `size` px whose start is at (`x`, `y`), moved in so that it stays inside
    /// the panel.
    pub(super) fn label(&self, svg: &mut String, (x, y): (f64, f64), text: &str, size: f64) {
        let right = self.left + self.size - 2.0 - text_width(text, size);
        let x = x.min(right).max(self.left + 2.0);
        let y = y.clamp(self.top + size + 2.0, self.top + self.size - 2.0);
        let _ = write!(
            svg,
            r##"<text x="{x:.1}" y="{y:.1}" font-size="{size}">{}</text>"##,
            escape(text)
        );
    }

    /// The plane's name in the panel's top left corner, as `side: world x-z`.
    pub(super) fn name(&self, svg: &mut String) {
        if let Some(view) = self.plane.view {
            let (h, v) = self.plane.axes;
            let text = format!("{view} view: world {}-{}", h.name(), v.name());
            self.label(svg, (self.left + 4.0, self.top + 14.0), &text, 11.0);
        }
    }

    /// The base at the world origin: a triangle on a hatched ground.
    pub(super) fn base(&self, svg: &mut String) {
        let (x, y) = self.at(&Vector3::zeros());
        let _ = write!(
            svg,
            r##"<g class="base"><path d="M{x:.1},{y:.1} l8,12 h-16 z" fill="#333"/><path d="M{:.1},{:.1} h28 M{:.1},{:.1} l-5,6 m10,-6 l-5,6 m10,-6 l-5,6 m10,-6 l-5,6 m10,-6 l-5,6" stroke="#333" fill="none"/></g>"##,
            x - 14.0,
            y + 12.0,
            x - 12.0,
            y + 12.0
        );
    }

    /// A bar in the panel's bottom right corner of a round length (1, 2 or 5 times a power of
    /// ten m) near a fifth of the panel, with its length.
    pub(super) fn scale_bar(&self, svg: &mut String) {
        let wanted = 0.2 * self.size / self.scale;
        let power = 10f64.powf(wanted.log10().floor());
        let length = [5.0, 2.0, 1.0]
            .into_iter()
            .map(|m| m * power)
            .find(|l| *l <= wanted)
            .unwrap_or(power);
        let px = length * self.scale;
        let right = self.left + self.size - 8.0;
        let y = self.top + self.size - 8.0;
        let _ = write!(
            svg,
            r##"<g class="scale-bar"><path d="M{:.1},{:.1} v4 h{px:.1} v-4" stroke="#333" fill="none" stroke-width="1.5"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="middle">{} m</text></g>"##,
            right - px,
            y - 4.0,
            right - px / 2.0,
            y - 7.0,
            codesign_core::text::rounded(length)
        );
    }
}

/// What a linkage row is drawn as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// A screw between two anchors (`linear`).
    Screw,
    /// A crank and rod (`crank_rod`).
    CrankRod,
}

impl Kind {
    /// Its class in the SVG: `linkage screw` or `linkage crank-rod`.
    pub(super) fn class(self) -> &'static str {
        match self {
            Kind::Screw => "linkage screw",
            Kind::CrankRod => "linkage crank-rod",
        }
    }
}

/// Linkage `row`'s marks at one pose in `panel`: a screw's anchors, the line between them and
/// its length; a crank's circle, the crank to its pin and the rod to the driven link.
pub(super) fn linkage(
    svg: &mut String,
    panel: &Panel,
    (kind, row): (Kind, usize),
    points: &[Vector3<f64>],
) {
    let _ = write!(
        svg,
        r##"<g class="{}" id="linkage-{}-{row}">"##,
        kind.class(),
        panel_id(panel)
    );
    match (kind, points) {
        (Kind::Screw, [from, to]) => {
            let ((x1, y1), (x2, y2)) = (panel.at(from), panel.at(to));
            let _ = write!(
                svg,
                r##"<line class="screw-body" x1="{x1:.1}" y1="{y1:.1}" x2="{x2:.1}" y2="{y2:.1}" stroke="#d55e00" stroke-width="3"/><circle class="anchor" cx="{x1:.1}" cy="{y1:.1}" r="3" fill="#d55e00"/><circle class="anchor" cx="{x2:.1}" cy="{y2:.1}" r="3" fill="#d55e00"/>"##
            );
            let length = format!("{:.3} m", (to - from).norm());
            let middle = ((x1 + x2) / 2.0 + 5.0, (y1 + y2) / 2.0 - 4.0);
            panel.label(svg, middle, &length, 9.0);
        }
        (Kind::CrankRod, [centre, pin, end]) => {
            let (cx, cy) = panel.at(centre);
            let (px, py) = panel.at(pin);
            let (ex, ey) = panel.at(end);
            let radius = (pin - centre).norm() * panel.scale;
            let _ = write!(
                svg,
                r##"<circle class="crank-circle" cx="{cx:.1}" cy="{cy:.1}" r="{radius:.1}" fill="none" stroke="#009e73" stroke-dasharray="2 2"/><line class="crank" x1="{cx:.1}" y1="{cy:.1}" x2="{px:.1}" y2="{py:.1}" stroke="#009e73" stroke-width="3"/><line class="rod" x1="{px:.1}" y1="{py:.1}" x2="{ex:.1}" y2="{ey:.1}" stroke="#cc79a7" stroke-width="2"/><circle class="pin" cx="{px:.1}" cy="{py:.1}" r="2.5" fill="#009e73"/>"##
            );
        }
        _ => {}
    }
    svg.push_str("</g>");
}

/// The panel's place as a name for ids: `x-y` of its top left corner, px.
fn panel_id(panel: &Panel) -> String {
    format!("{:.0}-{:.0}", panel.left, panel.top)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_lines_fit_their_width_and_keep_every_word() {
        let text = "links between joint origins (circles) from the base (triangle) in the world \
                    y-z plane; TCP path dashed";
        let lines = wrap(text, 10.0, 200.0);
        assert!(lines.len() > 1);
        assert!(
            lines.iter().all(|l| text_width(l, 10.0) <= 200.0),
            "{lines:?}"
        );
        assert_eq!(lines.join(" "), text);
        assert_eq!(wrap("a-very-long-word b", 10.0, 20.0).len(), 2);
    }
}
