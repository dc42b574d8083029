//! The cost of every evaluation of co-design runs (the paper's figure 6): the feasible ones on a
//! log axis, the penalised ones in a band of their own above it, so that the penalty (1e6) does
//! not squash the feasible costs into a line at the bottom.

use super::legend::Key;
use super::{canvas, number, palette, span, Area, Chart, DrawResult, Figure, Series, CHART};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One co-design run's evaluations.
#[derive(Clone, Debug, PartialEq)]
pub struct CostRun {
    /// Its name in the legend, e.g. `seed 3`.
    pub name: String,
    /// Every evaluation's cost J, in order.
    pub costs: Vec<f64>,
    /// The run's penalty: an evaluation that costs this or more (or is not finite) was
    /// penalised, its design invalid or infeasible.
    pub penalty: f64,
}

impl CostRun {
    /// Whether evaluation `cost` was penalised.
    fn penalised(&self, cost: f64) -> bool {
        !(cost.is_finite() && cost < self.penalty)
    }

    /// How many of its evaluations were penalised.
    fn penalised_count(&self) -> usize {
        self.costs.iter().filter(|&&c| self.penalised(c)).count()
    }

    /// The (evaluation, cost) of its feasible evaluations with a positive cost (a log axis shows
    /// no other).
    fn feasible(&self) -> Vec<(f64, f64)> {
        let costs = self.costs.iter().enumerate();
        costs
            .filter(|&(_, &c)| !self.penalised(c) && c > 0.0)
            .map(|(i, &c)| (i as f64, c))
            .collect()
    }

    /// The least feasible cost so far, from the first feasible evaluation on.
    fn best_so_far(&self) -> Vec<(f64, f64)> {
        let mut best = f64::INFINITY;
        let mut line = Vec::new();
        for (i, &c) in self.costs.iter().enumerate() {
            if !self.penalised(c) && c > 0.0 {
                best = best.min(c);
            }
            if best.is_finite() {
                line.push((i as f64, best));
            }
        }
        line
    }
}

/// The cost of every evaluation of co-design runs, one run per seed: each run's feasible
/// evaluations as dots and its best so far as a line on a log axis of the cost; its penalised
/// evaluations as ticks in a band labelled `penalised` above it. Where no evaluation was
/// feasible, the plot says so.
#[derive(Clone, Debug, PartialEq)]
pub struct CostEvolution {
    /// Title above the plot.
    pub title: String,
    /// The runs.
    pub runs: Vec<CostRun>,
}

/// The band of the penalised evaluations, px high.
const BAND: u32 = 70;

impl CostEvolution {
    /// The feasible costs as a log chart: each run's dots, then each run's best so far.
    fn feasible_chart(&self) -> Chart {
        let dots = self
            .runs
            .iter()
            .map(|run| Series::dots(format!("{}: feasible evaluation", run.name), run.feasible()));
        let best = self
            .runs
            .iter()
            .map(|run| Series::line(format!("{}: best so far", run.name), run.best_so_far()));
        Chart {
            title: self.title.clone(),
            x_label: "evaluation".into(),
            y_label: "cost J of feasible designs (log scale)".into(),
            series: dots.chain(best).collect(),
            guides: Vec::new(),
            log_y: true,
        }
    }

    /// (penalised evaluations, all evaluations) over the runs.
    fn counts(&self) -> (usize, usize) {
        self.runs.iter().fold((0, 0), |(penalised, all), run| {
            (penalised + run.penalised_count(), all + run.costs.len())
        })
    }

    /// The penalty named in the texts: the runs' least.
    fn penalty(&self) -> f64 {
        self.runs
            .iter()
            .map(|run| run.penalty)
            .fold(f64::INFINITY, f64::min)
    }

    /// The penalised evaluations as ticks in `area`, a row per run, over x range `x`, with
    /// the margins and the y label area of the chart below, so that their evaluations line up.
    fn draw_band(&self, area: &Area<'_>, x: (f64, f64)) -> DrawResult {
        let rows = self.runs.len().max(1) as f64;
        let mut band = ChartBuilder::on(area)
            .margin_top(6)
            .margin_left(12)
            .margin_right(12)
            .y_label_area_size(70)
            .build_cartesian_2d(x.0..x.1, -0.5..rows - 0.5)?;
        band.configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .draw()?;
        let style = ("sans-serif", 15)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let middle = (6 + area.dim_in_pixel().1 as i32) / 2;
        area.draw(&Text::new("penalised", (14, middle), style))?;
        for (k, run) in self.runs.iter().enumerate() {
            let colour = palette(k);
            let row = rows - 1.0 - k as f64;
            let costs = run.costs.iter().enumerate();
            let ticks = costs.filter(|&(_, &c)| run.penalised(c)).map(|(i, _)| {
                let i = i as f64;
                PathElement::new(
                    vec![(i, row - 0.35), (i, row + 0.35)],
                    colour.stroke_width(1),
                )
            });
            band.draw_series(ticks)?;
        }
        Ok(())
    }

    /// The main area when no evaluation was feasible: the evaluation axis and a sentence.
    fn draw_none_feasible(&self, area: &Area<'_>, x: (f64, f64)) -> DrawResult {
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(x.0..x.1, 0.0..1.0)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .y_labels(0)
            .x_desc("evaluation")
            .y_desc("cost J of feasible designs")
            .draw()?;
        let (_, all) = self.counts();
        let text = format!(
            "no evaluation was feasible: all {all} were penalised (cost ≥ {})",
            number(self.penalty())
        );
        let style = ("sans-serif", 20)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        chart.draw_series([Text::new(text, ((x.0 + x.1) / 2.0, 0.5), style)])?;
        Ok(())
    }
}

impl Figure for CostEvolution {
    fn title(&self) -> &str {
        &self.title
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        let chart = self.feasible_chart();
        let mut legend = chart.legend();
        let penalty = format!("penalised: cost ≥ {}", number(self.penalty()));
        legend.add(Key::Tick(BLACK.to_rgba()), penalty);
        for (k, run) in self.runs.iter().enumerate() {
            let (penalised, all) = (run.penalised_count(), run.costs.len());
            let text = format!("{}: {penalised} of {all} penalised", run.name);
            legend.add(Key::Tick(palette(k)), text);
        }
        let longest = self.runs.iter().map(|run| run.costs.len()).max();
        let x = span([0.0, longest.unwrap_or(1).saturating_sub(1) as f64].into_iter());
        let (plot, side) = canvas(svg, &self.title, CHART, &legend)?;
        let (band, main) = plot.split_vertically(BAND);
        self.draw_band(&band, x)?;
        if chart.series.iter().all(|s| s.points.is_empty()) {
            self.draw_none_feasible(&main, x)?;
        } else {
            chart.plot(&main, x)?;
        }
        legend.draw(&side)?;
        plot.present()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::text_x;
    use super::*;

    fn run(name: &str, costs: &[f64]) -> CostRun {
        CostRun {
            name: name.into(),
            costs: costs.to_vec(),
            penalty: 1e6,
        }
    }

    #[test]
    fn the_best_so_far_starts_at_the_first_feasible_evaluation() {
        let run = run("seed 0", &[1e6, 1e6, 50.0, 1e6, 80.0, 20.0, f64::NAN, 2e6]);
        assert_eq!(run.feasible(), [(2.0, 50.0), (4.0, 80.0), (5.0, 20.0)]);
        let best = run.best_so_far();
        assert_eq!(best.first(), Some(&(2.0, 50.0)));
        assert_eq!(best[3], (5.0, 20.0));
        assert_eq!(best.last(), Some(&(7.0, 20.0)));
        let figure = CostEvolution {
            title: "t".into(),
            runs: vec![run],
        };
        assert_eq!(figure.counts(), (5, 8));
    }

    /// Feasible costs on a log axis of their own range (the penalty is not on it), penalised
    /// evaluations in the band, counted in the legend beside the plot.
    #[test]
    fn penalised_evaluations_stand_apart_from_the_feasible_ones() {
        let figure = CostEvolution {
            title: "CMA-ES cost per evaluation".into(),
            runs: vec![
                run("seed 0", &[1e6, 900.0, 1e6, 120.0, 15.0]),
                run("seed 1", &[40.0, 1e6, 30.0]),
            ],
        };
        let svg = figure.to_svg().unwrap();
        for tick in ["100", "1000"] {
            assert!(svg.contains(&format!(">\n{tick}\n</text>")), "{tick}");
        }
        assert!(
            !svg.contains(">\n1000000\n</text>"),
            "the penalty is off the axis"
        );
        assert!(
            text_x(&svg, "penalised") < 80.0,
            "the band's label, left of it"
        );
        for legend in ["penalised: cost ≥ 1000000", "seed 0: 2 of 5 penalised"] {
            assert!(text_x(&svg, legend) > 900.0, "{legend}");
        }
        assert!(text_x(&svg, "seed 1: best so far") > 900.0);
        assert!(!svg.contains("no evaluation was feasible"));
    }

    /// A run whose every evaluation was penalised draws no line at the penalty: it says so.
    #[test]
    fn a_run_with_no_feasible_evaluation_says_so() {
        let figure = CostEvolution {
            title: "CMA-ES cost per evaluation: joint space, 3 kg".into(),
            runs: vec![run("seed 0", &[1e6; 6])],
        };
        let svg = figure.to_svg().unwrap();
        assert!(
            svg.contains("no evaluation was feasible: all 6 were penalised (cost ≥ 1000000)"),
            "{svg}"
        );
        assert!(!svg.contains("best so far"));
        assert!(text_x(&svg, "seed 0: 6 of 6 penalised") > 900.0);
    }
}
