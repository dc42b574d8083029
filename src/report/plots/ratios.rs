//! Values per case on a common set of axes: a radar chart (three axes or more) or a grouped bar
//! chart (any number).

use super::legend::{Key, Legend};
use super::{canvas, palette, DrawResult, Figure};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A radar chart: one spoke per axis, each case a closed polygon of its values on the spokes.
#[derive(Clone, Debug, PartialEq)]
pub struct Radar {
    /// Title above the plot.
    pub title: String,
    /// Spoke labels, clockwise from the top.
    pub axes: Vec<String>,
    /// (legend text, one value per axis as a fraction of the spoke's length, in [0, 1]).
    pub cases: Vec<(String, Vec<f64>)>,
}

impl Radar {
    /// The point at `fraction` of spoke `i`, in chart units (unit circle).
    fn at(&self, i: usize, fraction: f64) -> (f64, f64) {
        let n = self.axes.len() as f64;
        let angle = std::f64::consts::FRAC_PI_2 - std::f64::consts::TAU * i as f64 / n;
        (fraction * angle.cos(), fraction * angle.sin())
    }
}

impl Figure for Radar {
    fn title(&self) -> &str {
        &self.title
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        let legend = cases_legend(&self.cases, |colour| Key::Line(colour, false));
        let (plot, side) = canvas(svg, &self.title, (760, 640), &legend)?;
        let mut chart = ChartBuilder::on(&plot)
            .margin(20)
            .build_cartesian_2d(-1.6..1.6, -1.25..1.25)?;
        let grey = BLACK.mix(0.35);
        let n = self.axes.len();
        for ring in [0.25, 0.5, 0.75, 1.0] {
            let outline: Vec<(f64, f64)> = (0..=n).map(|i| self.at(i % n, ring)).collect();
            chart.draw_series(LineSeries::new(outline, grey.stroke_width(1)))?;
            chart.draw_series(std::iter::once(Text::new(
                format!("{ring}"),
                (0.03, ring + 0.04),
                ("sans-serif", 12).into_font().color(&grey),
            )))?;
        }
        for (i, label) in self.axes.iter().enumerate() {
            chart.draw_series(LineSeries::new(
                vec![(0.0, 0.0), self.at(i, 1.0)],
                grey.stroke_width(1),
            ))?;
            let (x, y) = self.at(i, 1.12);
            let anchor = Pos::new(
                if x > 0.05 {
                    HPos::Left
                } else if x < -0.05 {
                    HPos::Right
                } else {
                    HPos::Center
                },
                VPos::Center,
            );
            let style = ("sans-serif", 16).into_font().color(&BLACK).pos(anchor);
            chart.draw_series(std::iter::once(Text::new(label.clone(), (x, y), style)))?;
        }
        for (k, (_, values)) in self.cases.iter().enumerate() {
            let colour = palette(k);
            let outline: Vec<(f64, f64)> = (0..=n).map(|i| self.at(i % n, values[i % n])).collect();
            chart.draw_series(LineSeries::new(outline, colour.stroke_width(2)))?;
        }
        legend.draw(&side)?;
        plot.present()?;
        Ok(())
    }
}

/// A grouped bar chart: one group per axis, in it one bar per case, with the radar's data (for
/// fewer than three axes, where a radar has no area).
#[derive(Clone, Debug, PartialEq)]
pub struct Bars {
    /// Title above the plot.
    pub title: String,
    /// Group labels, left to right.
    pub axes: Vec<String>,
    /// Label of the y axis.
    pub y_label: String,
    /// (legend text, one value per axis, >= 0).
    pub cases: Vec<(String, Vec<f64>)>,
}

impl Bars {
    /// The x interval of case `k`'s bar in group `i` (group `i` centred on x = i, its bars
    /// together 0.8 wide).
    fn bar(&self, i: usize, k: usize) -> (f64, f64) {
        let width = 0.8 / self.cases.len().max(1) as f64;
        let left = i as f64 - 0.4 + k as f64 * width;
        (left + 0.1 * width, left + 0.9 * width)
    }
}

impl Figure for Bars {
    fn title(&self) -> &str {
        &self.title
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        let legend = cases_legend(&self.cases, Key::Bar);
        let (plot, side) = canvas(svg, &self.title, (760, 640), &legend)?;
        let top = self
            .cases
            .iter()
            .flat_map(|(_, values)| values.iter().copied())
            .filter(|v| v.is_finite())
            .fold(1.0, f64::max);
        let groups = self.axes.len() as f64;
        let mut chart = ChartBuilder::on(&plot)
            .margin(20)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5..groups - 0.5, 0.0..top * 1.1)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_desc(&self.y_label)
            .draw()?;
        for (i, label) in self.axes.iter().enumerate() {
            let (x, y) = chart.backend_coord(&(i as f64, 0.0));
            let style = ("sans-serif", 16)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top));
            plot.draw(&Text::new(label.clone(), (x, y + 10), style))?;
        }
        for (k, (_, values)) in self.cases.iter().enumerate() {
            let colour = palette(k);
            let bars = values.iter().enumerate().map(|(i, &value)| {
                let (left, right) = self.bar(i, k);
                Rectangle::new([(left, 0.0), (right, value)], colour.filled())
            });
            chart.draw_series(bars)?;
        }
        legend.draw(&side)?;
        plot.present()?;
        Ok(())
    }
}

/// The legend of `cases`: each case's name beside its `key` in its colour.
fn cases_legend(cases: &[(String, Vec<f64>)], key: impl Fn(RGBAColor) -> Key) -> Legend {
    let mut legend = Legend::default();
    for (k, (name, _)) in cases.iter().enumerate() {
        legend.add(key(palette(k)), name);
    }
    legend
}

#[cfg(test)]
mod tests {
    use super::super::tests::text_x;
    use super::*;

    #[test]
    fn radar_labels_its_spokes_and_cases() {
        let radar = Radar {
            title: "ratios".into(),
            axes: vec!["r1".into(), "r2".into(), "r3".into()],
            cases: vec![("case A".into(), vec![1.0, 0.5, 0.25])],
        };
        let svg = radar.to_svg().unwrap();
        for text in ["ratios", "r1", "r3", "case A", "0.75"] {
            assert!(svg.contains(text), "{text} missing");
        }
        assert!(
            text_x(&svg, "case A") > 760.0,
            "the legend beside the radar"
        );
        let top = radar.at(0, 1.0);
        assert!(top.0.abs() < 1e-12 && (top.1 - 1.0).abs() < 1e-12);
        let second = radar.at(1, 1.0);
        assert!(second.0 > 0.0, "spokes run clockwise");
    }

    #[test]
    fn bars_group_the_cases_per_axis() {
        let bars = Bars {
            title: "two ratios".into(),
            axes: vec!["r1 (max 9)".into(), "r2 (max 3)".into()],
            y_label: "r_i / upper bound".into(),
            cases: vec![
                ("case A".into(), vec![1.0, 0.5]),
                ("case B".into(), vec![0.25, 0.75]),
            ],
        };
        let svg = bars.to_svg().unwrap();
        for text in ["two ratios", "r1 (max 9)", "r2 (max 3)", "case A", "case B"] {
            assert!(svg.contains(text), "{text} missing");
        }
        assert!(text_x(&svg, "case B") > 760.0, "the legend beside the bars");
        // The bars of one group sit side by side, in case order, inside the group's 0.8.
        let (a, b) = (bars.bar(1, 0), bars.bar(1, 1));
        assert!(0.6 <= a.0 && a.0 < a.1 && a.1 < b.0 && b.0 < b.1 && b.1 <= 1.4);
        // Four filled bars and two legend keys, besides the background and the legend's box.
        let filled = |colour: RGBAColor| {
            let (r, g, b) = colour.rgb();
            svg.matches(&format!("fill=\"#{r:02X}{g:02X}{b:02X}\""))
                .count()
        };
        assert_eq!((filled(palette(0)), filled(palette(1))), (3, 3));
    }
}
