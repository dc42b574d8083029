//! SVG line charts: trajectories (the paper's figures 4 and 5) and co-design histories.

use plotters::prelude::*;
use std::path::Path;

/// One named curve of (x, y) points.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
}

/// A dashed reference line: a limit or a box edge.
#[derive(Clone, Debug, PartialEq)]
pub enum Guide {
    /// y = value across the chart.
    Horizontal(f64),
    /// x = value across the chart.
    Vertical(f64),
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

impl Chart {
    /// Renders the chart as an SVG document.
    pub fn to_svg(&self) -> Result<String, String> {
        let mut svg = String::new();
        self.draw(&mut svg)
            .map_err(|error| format!("cannot draw chart '{}': {error}", self.title))?;
        Ok(svg)
    }

    /// Renders the chart and writes it atomically to `path`.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        super::files::write_atomic(path, self.to_svg()?.as_bytes())
    }

    fn draw(&self, svg: &mut String) -> Result<(), Box<dyn std::error::Error + '_>> {
        let points = || self.series.iter().flat_map(|s| s.points.iter());
        let (x0, x1) = span(points().map(|p| p.0).chain(self.guides.iter().filter_map(
            |g| match g {
                Guide::Vertical(x) => Some(*x),
                Guide::Horizontal(_) => None,
            },
        )));
        let (y0, y1) = span(points().map(|p| p.1).chain(self.guides.iter().filter_map(
            |g| match g {
                Guide::Horizontal(y) => Some(*y),
                Guide::Vertical(_) => None,
            },
        )));
        let root = SVGBackend::with_string(svg, (900, 540)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70);
        if self.log_y {
            let low = points()
                .map(|p| p.1)
                .filter(|y| *y > 0.0)
                .fold(f64::INFINITY, f64::min);
            let low = if low.is_finite() { low * 0.5 } else { 1e-3 };
            let mut chart =
                builder.build_cartesian_2d(x0..x1, (low..y1.max(low * 10.0)).log_scale())?;
            chart
                .configure_mesh()
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .draw()?;
            for (i, series) in self.series.iter().enumerate() {
                let color = Palette99::pick(i).to_rgba();
                chart
                    .draw_series(
                        series
                            .points
                            .iter()
                            .map(|&(x, y)| Circle::new((x, y), 2, color.filled())),
                    )?
                    .label(&series.name)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        } else {
            let mut chart = builder.build_cartesian_2d(x0..x1, y0..y1)?;
            chart
                .configure_mesh()
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .draw()?;
            for guide in &self.guides {
                let line = match *guide {
                    Guide::Horizontal(y) => vec![(x0, y), (x1, y)],
                    Guide::Vertical(x) => vec![(x, y0), (x, y1)],
                };
                chart.draw_series(DashedLineSeries::new(
                    line,
                    6,
                    4,
                    BLACK.mix(0.45).stroke_width(1),
                ))?;
            }
            for (i, series) in self.series.iter().enumerate() {
                let color = Palette99::pick(i).to_rgba();
                chart
                    .draw_series(LineSeries::new(
                        series.points.iter().copied(),
                        color.stroke_width(2),
                    ))?
                    .label(&series.name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }
        root.present()?;
        Ok(())
    }
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
            series: vec![Series {
                name: "joint 1".into(),
                points: vec![(0.0, 0.0), (1.0, 2.0)],
            }],
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
}
