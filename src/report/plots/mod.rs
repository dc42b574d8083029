//! SVG figures: line charts of trajectories (the paper's figures 4 and 5), the cost of
//! co-design runs ([`CostEvolution`]), and the radar or bar chart of values per case
//! ([`ratios`]). Every figure's legend stands in a column beside its plot, never over the data.

mod cost;
mod guide;
mod legend;
mod ratios;

pub use cost::{CostEvolution, CostRun};
pub use guide::{Guide, Line};
pub use ratios::{Bars, Radar};

use super::ReportError;
use codesign_core::text::{markup_safe, number, rounded};
use guide::draw_dashes;
use legend::{Key, Legend};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A line through the points in order.
    Line,
    /// A dot at each point (many unordered samples), in a lighter shade.
    Dots,
    /// A disc ringed in black at each point, in full colour: a few points that matter (a
    /// front's designs), each series usually one point with its own legend entry.
    Point,
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
    /// Whether the first point is marked as the start (a disc) and the last as the goal (a
    /// square): a path.
    pub ends: bool,
}

impl Series {
    /// A series drawn as a line.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            name: name.into(),
            points,
            mark: Mark::Line,
            ends: false,
        }
    }

    /// A path: a line with its start and goal marked.
    pub fn path(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            ends: true,
            ..Series::line(name, points)
        }
    }

    /// A series drawn as discs ringed in black.
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            mark: Mark::Point,
            ..Series::line(name, points)
        }
    }

    /// A series drawn as dots.
    pub fn dots(name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            mark: Mark::Dots,
            ..Series::line(name, points)
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
    /// Dashed guides (limits, box edges), each in the colours of its series.
    pub guides: Vec<Guide>,
    /// Draw the y axis in log scale (only positive y are drawn).
    pub log_y: bool,
}

/// The range of `values` (the finite ones) with 5 % to spare each side; (0, 1) for none.
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

/// The range of a log axis over `values` (the positive finite ones): half the least to twice
/// the largest, at least a decade; (1e-3, 1) for none.
fn log_span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    (0.5 * lo, (2.0 * hi).max(10.0 * lo))
}

/// A log axis' tick label: the value to three digits, as messages write numbers (`20`, `1000`,
/// `0.003`, `1e-9`).
fn log_tick(value: &f64) -> String {
    rounded(*value).to_string()
}

/// The outcome of drawing a figure.
pub type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The series colours, in order: Okabe and Ito's palette for colour-blind readers, without its
/// yellow, which is hard to read on white: blue, vermillion, bluish green, reddish purple,
/// orange, sky blue, black.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// The colour of guides of no series.
const GREY: RGBAColor = RGBAColor(0, 0, 0, 0.45);

/// The colour of the `i`-th series (or case) of a figure, cycling through [`PALETTE`].
fn palette(i: usize) -> RGBAColor {
    PALETTE[i % PALETTE.len()].to_rgba()
}

/// Whether the `i`-th line of a chart is dashed: those of the palette's second round, fourth
/// and so on, so that no two of 14 lines look alike.
fn dashed(i: usize) -> bool {
    (i / PALETTE.len()) % 2 == 1
}

/// The colour of the `i`-th series of its mark (so the k-th dots and the k-th line of a chart
/// match): dots a lighter shade, so lines over them stay readable.
fn colour(i: usize, mark: Mark) -> RGBAColor {
    let colour = palette(i);
    match mark {
        Mark::Line | Mark::Point => colour,
        Mark::Dots => colour.mix(0.45),
    }
}

/// The font size (plotters' points) of the caption `title` over a figure `width` pixels wide
/// with `margin` pixels each side: 22, or less for a title too long to fit (many ratios in a
/// design), down to [`WRAPPED`], below which [`caption_lines`] wraps it. An SVG viewer lays the text out, so its width is estimated: 0.55 em per
/// character, and plotters writes 1/1.24 of the size as the SVG font size.
fn caption_size(title: &str, width: u32, margin: u32) -> f64 {
    const LARGEST: f64 = 22.0;
    caption_fit(title, width, margin).clamp(WRAPPED, LARGEST)
}

/// The largest font size (plotters' points) at which `title` fits on one line over a figure
/// `width` pixels wide with `margin` pixels each side, as [`caption_size`] estimates it.
fn caption_fit(title: &str, width: u32, margin: u32) -> f64 {
    let room = f64::from(width.saturating_sub(2 * margin));
    room / (CAPTION_EM / 1.24 * title.chars().count().max(1) as f64)
}

/// A caption character's estimated width, em.
const CAPTION_EM: f64 = 0.55;

/// An area of an SVG figure, in pixels.
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The areas of a figure drawn into `svg`: its plot column, `size.0` px wide under `title`, and
/// the column of `legend` beside it, both `size.1` px high.
fn canvas<'a>(
    svg: &'a mut String,
    title: &str,
    (width, height): (u32, u32),
    legend: &Legend,
) -> Result<(Area<'a>, Area<'a>), Box<dyn std::error::Error>> {
    let root =
        SVGBackend::with_string(svg, (width + legend.width(height), height)).into_drawing_area();
    root.fill(&WHITE)?;
    let (mut plot, side) = root.split_horizontally(width);
    for line in caption_lines(title, width, 12) {
        plot = plot.titled(&line, ("sans-serif", caption_size(title, width, 12)))?;
    }
    Ok((plot, side))
}

/// The least size of a caption wrapped onto more lines, plotters' points.
const WRAPPED: f64 = 14.0;

/// The lines of the caption `title` over a figure `width` pixels wide with `margin` pixels each
/// side: one, at [`caption_size`], unless that is below [`WRAPPED`]; then as many as it takes
/// at that size, broken at spaces (an infeasible design's reason makes a long title).
fn caption_lines(title: &str, width: u32, margin: u32) -> Vec<String> {
    if caption_fit(title, width, margin) >= WRAPPED {
        return vec![title.to_owned()];
    }
    let room = f64::from(width.saturating_sub(2 * margin));
    legend::wrap(title, (room / (WRAPPED * CAPTION_EM / 1.24)) as usize)
}

/// A figure drawn as SVG.
pub trait Figure {
    /// The title above the plot.
    fn title(&self) -> &str;

    /// Draws the figure into `svg`.
    fn draw(&self, svg: &mut String) -> DrawResult;

    /// Renders the figure as an SVG document. plotters escapes the characters XML reserves in
    /// the texts it draws (titles, names, labels), not those XML refuses: the document is made
    /// [`markup_safe`] whole, so that no text drawn into it can leave it ill-formed.
    fn to_svg(&self) -> Result<String, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg).map_err(|error| ReportError::Draw {
            title: self.title().to_owned(),
            why: error.to_string(),
        })?;
        Ok(markup_safe(&svg).into_owned())
    }

    /// Renders the figure and writes it atomically to `path`.
    fn write(&self, path: &Path) -> Result<(), ReportError> {
        Ok(crate::store::files::write_atomic(
            path,
            self.to_svg()?.as_bytes(),
        )?)
    }
}

/// A chart's plot column, px: its width and the figure's height.
const CHART: (u32, u32) = (900, 540);

impl Figure for Chart {
    fn title(&self) -> &str {
        &self.title
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        let legend = self.legend();
        let (plot, side) = canvas(svg, &self.title, CHART, &legend)?;
        self.plot(&plot, self.x_range())?;
        legend.draw(&side)?;
        plot.present()?;
        Ok(())
    }
}

impl Chart {
    /// The colour of series `i` and whether its line is dashed: the k-th series of its mark
    /// takes the k-th colour.
    fn style(&self, i: usize) -> (RGBAColor, bool) {
        let mark = self.series[i].mark;
        let ordinal = self.series[..i].iter().filter(|s| s.mark == mark).count();
        (colour(ordinal, mark), mark == Mark::Line && dashed(ordinal))
    }

    /// The colours `guide`'s dashes take turns in: its owners', or grey.
    fn guide_colours(&self, guide: &Guide) -> Vec<RGBAColor> {
        let owners = guide.owners.iter().filter(|&&i| i < self.series.len());
        let colours: Vec<RGBAColor> = owners.map(|&i| self.style(i).0).collect();
        if colours.is_empty() {
            vec![GREY]
        } else {
            colours
        }
    }

    /// One entry per series drawn (one with points), per guide label, and the start and goal where a path is drawn.
    fn legend(&self) -> Legend {
        let mut legend = Legend::default();
        for (i, series) in self.series.iter().enumerate() {
            if series.points.is_empty() {
                continue;
            }
            let (colour, dashed) = self.style(i);
            let key = match series.mark {
                Mark::Line => Key::Line(colour, dashed),
                Mark::Dots | Mark::Point => Key::Dot(colour),
            };
            legend.add(key, &series.name);
        }
        for guide in &self.guides {
            legend.add(Key::Dashes(self.guide_colours(guide)), &guide.label);
        }
        if self.series.iter().any(|s| s.ends && !s.points.is_empty()) {
            legend.add(Key::Start, "start");
            legend.add(Key::Goal, "goal");
        }
        legend
    }

    /// The chart as data, for a drawing elsewhere (Python's `Solution.plot`): `title`,
    /// `x_label`, `y_label`, `log_y`; `series`, each with its `name`, `points` ([x, y] pairs),
    /// `mark` (`line` or `dots`), `ends` (a path's start and goal marked), `colour` (`#rrggbb`)
    /// and `dashed`; `guides`, each with its `label`, `line` (`{"horizontal": y}`,
    /// `{"vertical": x}` or `{"segment": [[x, y], [x, y]]}`) and the `colours` its dashes take
    /// turns in, as the SVG draws them (`#rrggbbaa` where translucent). A number that is not
    /// finite is null.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let hex = |c: RGBAColor| {
            let (r, g, b) = c.rgb();
            match c.alpha() < 1.0 {
                true => format!(
                    "#{r:02x}{g:02x}{b:02x}{:02x}",
                    (c.alpha() * 255.0).round() as u8
                ),
                false => format!("#{r:02x}{g:02x}{b:02x}"),
            }
        };
        let series = self.series.iter().enumerate().map(|(i, series)| {
            let (colour, dashed) = self.style(i);
            let mark = match series.mark {
                Mark::Line => "line",
                Mark::Dots => "dots",
                Mark::Point => "points",
            };
            json!({
                "name": series.name, "points": series.points, "mark": mark,
                "ends": series.ends, "colour": hex(colour), "dashed": dashed,
            })
        });
        let guides = self.guides.iter().map(|guide| {
            let line = match guide.line {
                Line::Horizontal(y) => json!({ "horizontal": y }),
                Line::Vertical(x) => json!({ "vertical": x }),
                Line::Segment(from, to) => json!({ "segment": [from, to] }),
            };
            let colours: Vec<String> = self.guide_colours(guide).into_iter().map(hex).collect();
            json!({ "label": guide.label, "line": line, "colours": colours })
        });
        json!({
            "title": self.title, "x_label": self.x_label, "y_label": self.y_label,
            "log_y": self.log_y, "series": series.collect::<Vec<_>>(),
            "guides": guides.collect::<Vec<_>>(),
        })
    }

    /// The x range of the series and guides.
    fn x_range(&self) -> (f64, f64) {
        let points = self.series.iter().flat_map(|s| s.points.iter());
        span(
            points
                .map(|p| p.0)
                .chain(self.guides.iter().flat_map(|g| g.line.xs())),
        )
    }

    /// Draws the axes, guides and series into `area` over x range `x`, the y range the data's.
    fn plot(&self, area: &Area<'_>, x: (f64, f64)) -> DrawResult {
        let ys = || {
            let points = self.series.iter().flat_map(|s| s.points.iter());
            points
                .map(|p| p.1)
                .chain(self.guides.iter().flat_map(|g| g.line.ys()))
        };
        let mut builder = ChartBuilder::on(area);
        builder
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70);
        if self.log_y {
            let y = log_span(ys());
            let chart = builder.build_cartesian_2d(x.0..x.1, (y.0..y.1).log_scale())?;
            self.draw_on(chart, x, y)
        } else {
            let y = span(ys());
            let chart = builder.build_cartesian_2d(x.0..x.1, y.0..y.1)?;
            self.draw_on(chart, x, y)
        }
    }

    /// Mesh, guides, series and the paths' ends on a chart of either y scale.
    fn draw_on<Y>(
        &self,
        mut chart: ChartContext<'_, SVGBackend<'_>, Cartesian2d<RangedCoordf64, Y>>,
        x: (f64, f64),
        y: (f64, f64),
    ) -> DrawResult
    where
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(&self.x_label).y_desc(&self.y_label);
        if self.log_y {
            mesh.y_label_formatter(&log_tick);
        }
        mesh.draw()?;
        for guide in &self.guides {
            let width = if guide.owners.is_empty() { 1 } else { 2 };
            let colours = self.guide_colours(guide);
            draw_dashes(&mut chart, guide.line.ends(x, y), &colours, width)?;
        }
        // Dots first, so that lines are drawn over them, and discs over the lines.
        let mut order: Vec<usize> = (0..self.series.len()).collect();
        order.sort_by_key(|&i| match self.series[i].mark {
            Mark::Dots => 0,
            Mark::Line => 1,
            Mark::Point => 2,
        });
        for i in order {
            let series = &self.series[i];
            let points = series.points.iter().copied();
            let points = points.filter(|&(_, y)| !self.log_y || y > 0.0);
            let (colour, dashed) = self.style(i);
            match series.mark {
                Mark::Line if dashed => {
                    chart.draw_series(DashedLineSeries::new(
                        points,
                        8,
                        5,
                        colour.stroke_width(2),
                    ))?;
                }
                Mark::Line => {
                    chart.draw_series(LineSeries::new(points, colour.stroke_width(2)))?;
                }
                Mark::Dots => {
                    let dots = points.map(|p| Circle::new(p, 2, colour.filled()));
                    chart.draw_series(dots)?;
                }
                Mark::Point => {
                    let ring = BLACK.stroke_width(1);
                    let discs = points.flat_map(|p| {
                        [Circle::new(p, 5, colour.filled()), Circle::new(p, 5, ring)]
                    });
                    chart.draw_series(discs)?;
                }
            }
        }
        for (i, series) in self.series.iter().enumerate() {
            if let (true, Some(&start), Some(&goal)) =
                (series.ends, series.points.first(), series.points.last())
            {
                draw_ends(&mut chart, (start, goal), self.style(i).0)?;
            }
        }
        Ok(())
    }
}

/// Marks a path's start with a disc and its goal with a square, in `colour` ringed in black.
fn draw_ends<Y>(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<RangedCoordf64, Y>>,
    (start, goal): ((f64, f64), (f64, f64)),
    colour: RGBAColor,
) -> DrawResult
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let ring = BLACK.stroke_width(1);
    chart.draw_series([
        Circle::new(start, 6, colour.filled()),
        Circle::new(start, 6, ring),
    ])?;
    let square =
        |style: ShapeStyle| EmptyElement::at(goal) + Rectangle::new([(-6, -6), (6, 6)], style);
    chart.draw_series([square(colour.filled()), square(ring)])?;
    Ok(())
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The x of the text `label` in `svg` (plotters writes `<text x="..." ...>\nlabel\n</text>`).
    pub(in crate::report) fn text_x(svg: &str, label: &str) -> f64 {
        let end = svg
            .find(&format!(">\n{label}\n</text>"))
            .unwrap_or_else(|| panic!("no text {label}"));
        let start = svg[..end].rfind("<text x=\"").unwrap() + "<text x=\"".len();
        let x = &svg[start..];
        x[..x.find('"').unwrap()].parse().unwrap()
    }

    /// The x of every point of the lines and segments `svg` strokes in `colour`.
    pub(in crate::report) fn stroke_xs(svg: &str, colour: RGBAColor) -> Vec<f64> {
        let (r, g, b) = colour.rgb();
        let stroke = format!("stroke=\"#{r:02X}{g:02X}{b:02X}\"");
        svg.split("<polyline")
            .skip(1)
            .filter(|element| element[..element.find("/>").unwrap()].contains(&stroke))
            .flat_map(|element| {
                let points = &element[element.find("points=\"").unwrap() + 8..];
                let points = &points[..points.find('"').unwrap()];
                points
                    .split_whitespace()
                    .map(|p| p.split(',').next().unwrap().parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    fn two_joints() -> Chart {
        let names = vec!["joint_a".to_owned(), "joint_b".to_owned()];
        let limits = [(0, -3.0), (0, 3.0), (1, -3.0), (1, 2.0), (1, f64::INFINITY)];
        let guides = limits.map(|(i, v)| (i, Line::Horizontal(v)));
        Chart {
            title: "two joints".into(),
            x_label: "t [s]".into(),
            y_label: "q [rad]".into(),
            series: vec![
                Series::line("joint_a", vec![(0.0, -1.0), (1.0, 2.5)]),
                Series::line("joint_b", vec![(0.0, 1.0), (1.0, -2.0)]),
            ],
            guides: Guide::owned(guides, "limit", &names),
            log_y: false,
        }
    }

    /// A limit is drawn in its curve's colour and named after it; one that curves share takes
    /// turns in their colours; an infinite one is left out.
    #[test]
    fn limits_take_their_curves_colours_and_names() {
        let chart = two_joints();
        let lines: Vec<(Line, Vec<usize>, &str)> = chart
            .guides
            .iter()
            .map(|g| (g.line, g.owners.clone(), g.label.as_str()))
            .collect();
        assert_eq!(
            lines,
            vec![
                (
                    Line::Horizontal(-3.0),
                    vec![0, 1],
                    "limit of joint_a, joint_b"
                ),
                (Line::Horizontal(3.0), vec![0], "joint_a limit"),
                (Line::Horizontal(2.0), vec![1], "joint_b limit"),
            ]
        );
        assert_eq!(
            chart.guide_colours(&chart.guides[0]),
            [palette(0), palette(1)]
        );
        assert_eq!(chart.guide_colours(&chart.guides[2]), [palette(1)]);
        let svg = chart.to_svg().unwrap();
        for label in [
            "joint_a limit",
            "joint_b limit",
            "limit of joint_a, joint_b",
        ] {
            assert!(text_x(&svg, label) > 900.0, "{label}");
        }
        // Each limit's dashes, 2 px wide in the colour of its curve: many short strokes.
        let dashes = |colour: RGBAColor| {
            let (r, g, b) = colour.rgb();
            let stroke = format!("stroke=\"#{r:02X}{g:02X}{b:02X}\" stroke-width=\"2\"");
            svg.matches(&stroke).count()
        };
        assert!(dashes(palette(0)) > 60 && dashes(palette(1)) > 60);
    }

    /// The legend stands in a column right of the plot (900 px, its data within a margin of
    /// 12 px): every stroke of a curve's colour is the curve, left of 888 px, or its legend key,
    /// right of 900 px, beside the curve's name.
    #[test]
    fn the_legend_stands_beside_the_plot() {
        let chart = two_joints();
        let svg = chart.to_svg().unwrap();
        let (plot, key): (Vec<f64>, Vec<f64>) = stroke_xs(&svg, palette(0))
            .into_iter()
            .partition(|&x| x < 900.0);
        let right = plot.iter().copied().fold(f64::MIN, f64::max);
        assert!(right > 800.0 && right <= 888.0, "the plot ends at {right}");
        let key_left = key.iter().copied().fold(f64::MAX, f64::min);
        assert!(key_left > 900.0, "the key at {key_left}");
        assert!(text_x(&svg, "joint_a") > key_left);
        assert_eq!(Legend::default().width(540), 0);
        assert!(svg.contains(&format!("width=\"{}\"", 900 + chart.legend().width(540))));
    }

    /// A path's start is a disc and its goal a square, at its first and last points, and the
    /// legend says which is which.
    #[test]
    fn a_path_marks_its_start_and_goal() {
        let chart = Chart {
            title: "path".into(),
            x_label: "world y [m]".into(),
            y_label: "world z [m]".into(),
            series: vec![Series::path(
                "TCP",
                vec![(0.0, 0.0), (0.5, 1.0), (1.0, 0.0)],
            )],
            guides: Vec::new(),
            log_y: false,
        };
        let svg = chart.to_svg().unwrap();
        let discs = svg.matches("<circle").count();
        assert_eq!(discs, 3, "the start's disc and ring, and the legend's disc");
        assert_eq!(svg.matches("width=\"12\" height=\"12\"").count(), 2);
        assert!(text_x(&svg, "start") > 900.0 && text_x(&svg, "goal") > 900.0);
        let line = Chart {
            series: vec![Series::line("TCP", vec![(0.0, 0.0), (1.0, 0.0)])],
            ..chart
        };
        let svg = line.to_svg().unwrap();
        assert!(!svg.contains("<circle") && !svg.contains(">\nstart\n"));
    }

    /// A log axis labels its decades plainly and leaves out what it cannot show (y <= 0).
    #[test]
    fn a_log_axis_labels_its_decades() {
        let chart = Chart {
            title: "log".into(),
            x_label: "evaluation".into(),
            y_label: "cost J".into(),
            series: vec![Series::dots(
                "J",
                vec![(0.0, 12.0), (1.0, 950.0), (2.0, 0.0)],
            )],
            guides: Vec::new(),
            log_y: true,
        };
        let svg = chart.to_svg().unwrap();
        for tick in ["10", "100", "1000"] {
            assert!(svg.contains(&format!(">\n{tick}\n</text>")), "{tick}");
        }
        assert_eq!(
            log_span([12.0, 950.0, 0.0, f64::NAN].into_iter()),
            (6.0, 1900.0)
        );
        assert_eq!(log_span([5.0].into_iter()), (2.5, 50.0));
        assert_eq!(log_tick(&(0.1 * 3.0)), "0.3");
    }

    #[test]
    fn draws_series_guides_and_labels() {
        let chart = Chart {
            title: "test chart".into(),
            x_label: "t [s]".into(),
            y_label: "q [rad]".into(),
            series: vec![
                Series::line("joint 1", vec![(0.0, 0.0), (1.0, 2.0)]),
                Series::dots("samples", vec![(0.5, 1.0)]),
            ],
            guides: vec![Guide::plain(Line::Horizontal(1.5), "box")],
            log_y: false,
        };
        let svg = chart.to_svg().unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("test chart") && svg.contains("joint 1"));
        assert!(svg.contains(">\nbox\n</text>"), "the guide's legend entry");
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
        // Every colour reads on white (WCAG contrast at least 2: the palette's yellow, 1.3,
        // and Palette99's, 1.2, would not).
        let linear = |c: u8| {
            let c = f64::from(c) / 255.0;
            match c <= 0.03928 {
                true => c / 12.92,
                false => ((c + 0.055) / 1.055).powf(2.4),
            }
        };
        for RGBColor(r, g, b) in PALETTE {
            let luminance = 0.2126 * linear(r) + 0.7152 * linear(g) + 0.0722 * linear(b);
            let contrast = 1.05 / (luminance + 0.05);
            assert!(contrast >= 2.0, "({r}, {g}, {b}): contrast {contrast:.2}");
        }
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
        // The 8th line (the palette's first colour again) is drawn in dashes: many segments.
        let blue = svg.matches("stroke=\"#0072B2\"").count();
        assert!(blue > 6, "{blue} blue strokes");
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
        assert_eq!(caption_size(&title(60), 900, 12), WRAPPED);
        // Too long for one line at 14: wrapped onto lines that fit, nothing lost.
        assert_eq!(caption_lines(&title(8), 900, 12), [title(8)]);
        let lines = caption_lines(&title(60), 900, 12);
        assert!((3..=5).contains(&lines.len()), "{lines:?}");
        assert!(lines.iter().all(|l| caption_fit(l, 900, 12) >= WRAPPED));
        assert_eq!(lines.join(" "), title(60));
    }
}
