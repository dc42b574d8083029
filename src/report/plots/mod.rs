//! SVG figures: line charts of trajectories (the paper's figures 4 and 5) and co-design
//! histories, and the radar or bar chart of values per case ([`ratios`]).

mod ratios;

pub use ratios::{Bars, Radar};

use super::ReportError;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A line through the points in order.
    Line,
    /// A dot at each point (many unordered samples).
    Dots,
}

/// One named curve of (x, y) points.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Line or dots.
    pub mark: Mark,
}

impl Series {
    /// A series drawn as a line.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            name: name.into(),
            points,
            mark: Mark::Line,
        }
    }
}

/// A dashed reference line: a limit, a box edge or an edge of a motor's torque-speed envelope.
#[derive(Clone, Debug, PartialEq)]
pub enum Guide {
    /// y = value across the chart.
    Horizontal(f64),
    /// x = value across the chart.
    Vertical(f64),
    /// The segment between two points (x, y); the chart's range takes in both.
    Segment((f64, f64), (f64, f64)),
}

impl Guide {
    /// The x values the chart's range must take in.
    fn xs(&self) -> Vec<f64> {
        match *self {
            Guide::Horizontal(_) => Vec::new(),
            Guide::Vertical(x) => vec![x],
            Guide::Segment(from, to) => vec![from.0, to.0],
        }
    }

    /// The y values the chart's range must take in.
    fn ys(&self) -> Vec<f64> {
        match *self {
            Guide::Horizontal(y) => vec![y],
            Guide::Vertical(_) => Vec::new(),
            Guide::Segment(from, to) => vec![from.1, to.1],
        }
    }
}

/// A chart to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// Label of the x axis, with units.
    pub x_label: String,
    /// Label of the y axis, with units.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Dashed guides (limits, box edges), drawn in grey.
    pub guides: Vec<Guide>,
    /// Draw the y axis in log scale (all y must be positive).
    pub log_y: bool,
}

fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5_f64.max(lo.abs() * 0.1)
    };
    (lo - pad, hi + pad)
}

/// The outcome of drawing a figure.
pub type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The series colours, in order: Palette99's first six (the colours of every committed plot),
/// then six dark ones that stay readable on white.
const PALETTE: [RGBColor; 12] = [
    RGBColor(230, 25, 75),
    RGBColor(60, 180, 75),
    RGBColor(255, 225, 25),
    RGBColor(0, 130, 200),
    RGBColor(245, 130, 48),
    RGBColor(145, 30, 180),
    RGBColor(0, 128, 128),
    RGBColor(128, 0, 0),
    RGBColor(0, 0, 128),
    RGBColor(170, 110, 40),
    RGBColor(128, 128, 0),
    RGBColor(240, 50, 230),
];

/// The colour of the `i`-th series (or case) of a figure, cycling through [`PALETTE`].
fn palette(i: usize) -> RGBAColor {
    PALETTE[i % PALETTE.len()].to_rgba()
}

/// Whether the `i`-th line of a chart is dashed: those of the palette's second round, fourth
/// and so on, so that no two of 24 lines look alike.
fn dashed(i: usize) -> bool {
    (i / PALETTE.len()) % 2 == 1
}

/// The colour of the `i`-th series of its mark (so the k-th dots and the k-th line of a chart
/// match): dots a lighter shade, so lines over them stay readable.
fn colour(i: usize, mark: Mark) -> RGBAColor {
    let colour = palette(i);
    match mark {
        Mark::Line => colour,
        Mark::Dots => colour.mix(0.45),
    }
}

/// The font size (plotters' points) of the caption `title` over a figure `width` pixels wide
/// with `margin` pixels each side: 22, or less for a title too long to fit (many ratios in a
/// design), down to 10. An SVG viewer lays the text out, so its width is estimated: 0.55 em per
/// character, and plotters writes 1/1.24 of the size as the SVG font size.
fn caption_size(title: &str, width: u32, margin: u32) -> f64 {
    const LARGEST: f64 = 22.0;
    const SMALLEST: f64 = 10.0;
    let pixels_per_point = 0.55 / 1.24;
    let room = f64::from(width.saturating_sub(2 * margin));
    let fit = room / (pixels_per_point * title.chars().count().max(1) as f64);
    fit.clamp(SMALLEST, LARGEST)
}

/// A figure drawn as SVG.
pub trait Figure {
    /// The title above the plot.
    fn title(&self) -> &str;

    /// Draws the figure into `svg`.
    fn draw(&self, svg: &mut String) -> DrawResult;

    /// Renders the figure as an SVG document.
    fn to_svg(&self) -> Result<String, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg).map_err(|error| ReportError::Draw {
            title: self.title().to_owned(),
            why: error.to_string(),
        })?;
        Ok(svg)
    }

    /// Renders the figure and writes it atomically to `path`.
    fn write(&self, path: &Path) -> Result<(), ReportError> {
        Ok(crate::store::files::write_atomic(
            path,
            self.to_svg()?.as_bytes(),
        )?)
    }
}

impl Figure for Chart {
    fn title(&self) -> &str {
        &self.title
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        let points = || self.series.iter().flat_map(|s| s.points.iter());
        let (x0, x1) = span(
            points()
                .map(|p| p.0)
                .chain(self.guides.iter().flat_map(Guide::xs)),
        );
        let (y0, y1) = span(
            points()
                .map(|p| p.1)
                .chain(self.guides.iter().flat_map(Guide::ys)),
        );
        let root = SVGBackend::with_string(svg, (900, 540)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(
                &self.title,
                ("sans-serif", caption_size(&self.title, 900, 12)),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70);
        if self.log_y {
            let low = points()
                .map(|p| p.1)
                .filter(|y| *y > 0.0)
                .fold(f64::INFINITY, f64::min);
            let low = if low.is_finite() { low * 0.5 } else { 1e-3 };
            let chart =
                builder.build_cartesian_2d(x0..x1, (low..y1.max(low * 10.0)).log_scale())?;
            self.draw_on(chart, (x0, x1), (low, y1))?;
        } else {
            let chart = builder.build_cartesian_2d(x0..x1, y0..y1)?;
            self.draw_on(chart, (x0, x1), (y0, y1))?;
        }
        root.present()?;
        Ok(())
    }
}

impl Chart {
    /// Mesh, guides, series and legend on a chart of either y scale.
    fn draw_on<'a, Y>(
        &self,
        mut chart: ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, Y>>,
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
    ) -> DrawResult
    where
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .draw()?;
        for guide in &self.guides {
            let line = match *guide {
                Guide::Horizontal(y) => vec![(x0, y), (x1, y)],
                Guide::Vertical(x) => vec![(x, y0), (x, y1)],
                Guide::Segment(from, to) => vec![from, to],
            };
            chart.draw_series(DashedLineSeries::new(
                line,
                6,
                4,
                BLACK.mix(0.45).stroke_width(1),
            ))?;
        }
        // Dots first, so that lines are drawn over them.
        let mut order: Vec<usize> = (0..self.series.len()).collect();
        order.sort_by_key(|&i| self.series[i].mark == Mark::Line);
        for i in order {
            let series = &self.series[i];
            let ordinal = self.series[..i]
                .iter()
                .filter(|s| s.mark == series.mark)
                .count();
            let colour = colour(ordinal, series.mark);
            match series.mark {
                Mark::Line => draw_line(&mut chart, series, colour, dashed(ordinal))?,
                Mark::Dots => {
                    chart
                        .draw_series(
                            series
                                .points
                                .iter()
                                .map(|&(x, y)| Circle::new((x, y), 2, colour.filled())),
                        )?
                        .label(&series.name)
                        .legend(move |(x, y)| Circle::new((x + 10, y), 3, colour.filled()));
                }
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}

/// Draws `series` as a line of `colour`, solid or dashed, with its legend entry.
fn draw_line<'a, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, Y>>,
    series: &Series,
    colour: RGBAColor,
    dashed: bool,
) -> DrawResult
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let style = colour.stroke_width(2);
    let points = series.points.iter().copied();
    if dashed {
        chart
            .draw_series(DashedLineSeries::new(points, 8, 5, style))?
            .label(&series.name)
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (8, 0)], style)
                    + PathElement::new(vec![(13, 0), (20, 0)], style)
            });
    } else {
        chart
            .draw_series(LineSeries::new(points, style))?
            .label(&series.name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_series_guides_and_labels() {
        let chart = Chart {
            title: "test chart".into(),
            x_label: "t [s]".into(),
            y_label: "q [rad]".into(),
            series: vec![
                Series::line("joint 1", vec![(0.0, 0.0), (1.0, 2.0)]),
                Series {
                    name: "samples".into(),
                    points: vec![(0.5, 1.0)],
                    mark: Mark::Dots,
                },
            ],
            guides: vec![Guide::Horizontal(1.5)],
            log_y: false,
        };
        let svg = chart.to_svg().unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("test chart") && svg.contains("joint 1"));
        let log = Chart {
            log_y: true,
            guides: vec![],
            ..chart
        };
        assert!(log.to_svg().unwrap().contains("<svg"));
    }

    #[test]
    fn many_series_cycle_through_the_palette_then_dash() {
        assert_eq!(palette(0), palette(PALETTE.len()));
        assert_ne!(palette(5), palette(6));
        assert!((0..PALETTE.len()).all(|i| !dashed(i)));
        assert!(dashed(PALETTE.len()) && dashed(2 * PALETTE.len() - 1));
        assert!(!dashed(2 * PALETTE.len()));
        let series = (0..14)
            .map(|i| Series::line(format!("joint_{i}"), vec![(0.0, i as f64), (1.0, 0.0)]))
            .collect();
        let chart = Chart {
            title: "fourteen joints".into(),
            x_label: "t [s]".into(),
            y_label: "q [rad]".into(),
            series,
            guides: vec![],
            log_y: false,
        };
        let svg = chart.to_svg().unwrap();
        assert!((0..14).all(|i| svg.contains(&format!("joint_{i}"))));
        // The 13th line (the palette's first colour again) is drawn in dashes: many segments.
        let red = svg.matches("stroke=\"#E6194B\"").count();
        assert!(red > 6, "{red} red strokes");
    }

    #[test]
    fn a_long_title_gets_a_smaller_caption() {
        let design = |n: usize| vec!["6.514"; n].join(", ");
        let title = |n: usize| {
            format!(
                "Joint positions: actuation space, r = ({}), payload 3 kg",
                design(n)
            )
        };
        assert_eq!(caption_size(&title(4), 900, 12), 22.0);
        let eight = caption_size(&title(8), 900, 12);
        assert!(10.0 < eight && eight < 22.0, "{eight}");
        assert_eq!(caption_size(&title(60), 900, 12), 10.0);
    }
}
