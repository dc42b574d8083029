//! The legend of a figure, drawn in a column of its own beside the plot, so that it never covers
//! the data: one entry a row (a long text wrapped onto more), a key and its text, in as many
//! columns as the height needs.

use super::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// What an entry's key shows.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Key {
    /// A line of the colour, dashed when `true`.
    Line(RGBAColor, bool),
    /// A dot of the colour.
    Dot(RGBAColor),
    /// A filled bar of the colour.
    Bar(RGBAColor),
    /// Dashes taking turns in the colours: a limit of the curves of those colours (one grey
    /// colour for a guide of no curve).
    Dashes(Vec<RGBAColor>),
    /// The start of a path: a black disc.
    Start,
    /// The goal of a path: a black square.
    Goal,
    /// A vertical tick of the colour (a penalised evaluation).
    Tick(RGBAColor),
}

/// One row of a legend.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Entry {
    /// What is drawn beside the text.
    pub key: Key,
    /// The text.
    pub text: String,
}

/// A figure's legend: its entries in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Legend {
    pub entries: Vec<Entry>,
}

/// A row's height, px.
const ROW: u32 = 18;
/// Space above the first row, px.
const TOP: u32 = 16;
/// The key's width and the gap after it, px.
const KEY: u32 = 32;
/// The text's size, plotters' points (the SVG's font size is 1/1.24 of it).
const TEXT: f64 = 15.0;
/// A character's estimated width, px: 0.55 em of the SVG's font size.
const CHAR: f64 = 0.55 * TEXT / 1.24;
/// The widest column, px: longer texts are wrapped at spaces (a word longer than that runs past
/// its end, still outside the plot).
const WIDEST: u32 = 320;

/// One row of a drawn legend: where it stands, its key (on an entry's first row) and its text.
struct Row<'a> {
    column: usize,
    row: usize,
    key: Option<&'a Key>,
    text: String,
}

/// `text` in lines of at most `width` characters, broken at spaces.
pub(super) fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

impl Legend {
    /// An entry of `key` and `text`, unless one of that text is there already.
    pub fn add(&mut self, key: Key, text: impl Into<String>) {
        let text = text.into();
        if !self.entries.iter().any(|entry| entry.text == text) {
            self.entries.push(Entry { key, text });
        }
    }

    /// Rows in a column of a legend `height` px high.
    fn rows(height: u32) -> usize {
        (height.saturating_sub(TOP + ROW) / ROW).max(1) as usize
    }

    /// The rows of the legend in columns of `rows` rows: each entry's text wrapped to fit
    /// [`WIDEST`], all of an entry in one column.
    fn layout(&self, rows: usize) -> Vec<Row<'_>> {
        let width = (f64::from(WIDEST - KEY - 16) / CHAR) as usize;
        let mut laid: Vec<Row<'_>> = Vec::new();
        let (mut column, mut row) = (0, 0);
        for entry in &self.entries {
            let lines = wrap(&entry.text, width);
            if row > 0 && row + lines.len() > rows {
                (column, row) = (column + 1, 0);
            }
            for (i, text) in lines.into_iter().enumerate() {
                let key = (i == 0).then_some(&entry.key);
                laid.push(Row {
                    column,
                    row,
                    key,
                    text,
                });
                row += 1;
            }
        }
        laid
    }

    /// The width of a column, px: the key, the longest line and a margin, at most [`WIDEST`].
    fn column_width(&self, rows: usize) -> u32 {
        let layout = self.layout(rows);
        let longest = layout.iter().map(|row| row.text.chars().count()).max();
        (KEY + (CHAR * longest.unwrap_or(0) as f64).ceil() as u32 + 16).min(WIDEST)
    }

    /// The legend's width beside a plot `height` px high, px: 0 without entries.
    pub fn width(&self, height: u32) -> u32 {
        let rows = Legend::rows(height);
        let columns = self.layout(rows).last().map_or(0, |row| row.column + 1);
        columns as u32 * self.column_width(rows)
    }

    /// Draws the entries into `area`, top to bottom, then the next column.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let rows = Legend::rows(area.dim_in_pixel().1);
        let width = self.column_width(rows) as i32;
        let style = ("sans-serif", TEXT)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        for row in self.layout(rows) {
            let x = row.column as i32 * width + 6;
            let y = (row.row as u32 * ROW + TOP + ROW / 2) as i32;
            if let Some(key) = row.key {
                draw_key(area, key, (x, y))?;
            }
            area.draw(&Text::new(row.text, (x + KEY as i32, y), style.clone()))?;
        }
        Ok(())
    }
}

/// Draws `key` at `(x, y)`, the left end of its row's middle, 24 px wide.
fn draw_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    key: &Key,
    (x, y): (i32, i32),
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    match key {
        Key::Line(colour, false) => {
            area.draw(&PathElement::new(
                vec![(x, y), (x + 24, y)],
                colour.stroke_width(2),
            ))?;
        }
        Key::Line(colour, true) => {
            for left in [x, x + 14] {
                area.draw(&PathElement::new(
                    vec![(left, y), (left + 10, y)],
                    colour.stroke_width(2),
                ))?;
            }
        }
        Key::Dot(colour) => area.draw(&Circle::new((x + 12, y), 4, colour.filled()))?,
        Key::Bar(colour) => {
            area.draw(&Rectangle::new(
                [(x + 4, y - 5), (x + 20, y + 5)],
                colour.filled(),
            ))?;
        }
        Key::Dashes(colours) => {
            // Three dashes, or one per colour up to six, across the key's 24 px.
            let dashes = colours.len().clamp(3, 6) as i32;
            let step = 24 / dashes + 1;
            for k in 0..dashes {
                let colour = colours[k as usize % colours.len().max(1)];
                let left = x + k * step;
                area.draw(&PathElement::new(
                    vec![(left, y), (left + step - 2, y)],
                    colour.stroke_width(2),
                ))?;
            }
        }
        Key::Start => area.draw(&Circle::new((x + 12, y), 5, BLACK.filled()))?,
        Key::Goal => {
            area.draw(&Rectangle::new(
                [(x + 7, y - 5), (x + 17, y + 5)],
                BLACK.filled(),
            ))?;
        }
        Key::Tick(colour) => {
            area.draw(&PathElement::new(
                vec![(x + 12, y - 6), (x + 12, y + 6)],
                colour.stroke_width(2),
            ))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn legend(texts: &[&str]) -> Legend {
        let mut legend = Legend::default();
        for text in texts {
            legend.add(Key::Start, *text);
        }
        legend
    }

    #[test]
    fn entries_are_one_per_text_and_columns_fill_the_height() {
        assert_eq!(legend(&[]).width(540), 0);
        let one = legend(&["joint 1", "joint 1 limit", "joint 1"]);
        assert_eq!(one.entries.len(), 2);
        let width = one.width(540);
        assert!(width > KEY + 50 && width < 200, "{width}");
        // 540 px hold 28 rows: 60 entries need three columns.
        let texts: Vec<String> = (0..60).map(|i| format!("joint {i:02}")).collect();
        let many = legend(&texts.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(Legend::rows(540), 28);
        assert_eq!(many.width(540), 3 * many.column_width(28));
        let long = legend(&[&"x".repeat(400)]);
        assert_eq!(long.width(540), WIDEST);
    }

    /// A limit's key shows a dash in each colour of its curves (three dashes at least).
    #[test]
    fn a_shared_limit_shows_each_colour_in_its_key() {
        let colours: Vec<RGBAColor> = (0..4).map(super::super::palette).collect();
        let mut legend = Legend::default();
        legend.add(
            Key::Dashes(colours.clone()),
            "limit of motor 1, motor 2, motor 3, motor 4",
        );
        legend.add(Key::Dashes(vec![colours[0]]), "motor 1 limit");
        let mut svg = String::new();
        {
            let area = SVGBackend::with_string(&mut svg, (400, 100)).into_drawing_area();
            legend.draw(&area).unwrap();
            area.present().unwrap();
        }
        let strokes = |colour: RGBAColor| {
            let (r, g, b) = colour.rgb();
            svg.matches(&format!("stroke=\"#{r:02X}{g:02X}{b:02X}\""))
                .count()
        };
        assert_eq!(strokes(colours[0]), 1 + 3);
        assert!(colours[1..].iter().all(|&c| strokes(c) == 1));
    }

    /// A long text is wrapped at spaces onto rows of its own, its key on the first, and an
    /// entry is never split between columns.
    #[test]
    fn long_texts_wrap_within_the_widest_column() {
        let names: Vec<String> = (1..=8).map(|i| format!("joint_arm_{i}")).collect();
        let text = format!("limit of {}", names.join(", "));
        let lines = wrap(&text, 40);
        assert_eq!(lines.join(" "), text);
        assert!(lines.len() == 3 && lines.iter().all(|l| l.chars().count() <= 40));
        let shared = legend(&["motor 1", &text]);
        let rows = shared.layout(28);
        assert_eq!(rows.len(), 1 + lines.len());
        assert!(rows[1].key.is_some() && rows[2].key.is_none());
        assert!(shared.width(540) <= WIDEST);
        // A column of three rows with one taken: the wrapped entry starts the next column.
        let two = legend(&["a", &text]);
        let moved = two.layout(3);
        assert_eq!((moved[1].column, moved[1].row), (1, 0));
    }
}
