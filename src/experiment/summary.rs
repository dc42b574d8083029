//! The chart the results page opens with: every case of the table (a payload in a space) with
//! the trajectory cost J of the original design and of the best co-designed one, and their
//! payload capacities, as bars, inline in the page (an SVG element: nothing to load).

use crate::report::table::{escape_html, PaperTable, TableRow};
use codesign_core::text::rounded;
use std::fmt::Write;

/// The chart's width, px.
const WIDTH: f64 = 1000.0;

/// Where the bars of each panel start (J, capacity), px, and their longest, px.
const PANELS: [f64; 2] = [170.0, 590.0];
const LONGEST: f64 = 300.0;

/// A case's height, px, and the header's above the first.
const ROW: f64 = 34.0;
const HEADER: f64 = 50.0;

/// The colours of the original design's bars and of the best design's.
const BEFORE: &str = "#999999";
const AFTER: &str = "#0072b2";

/// One bar's value, or why it has none.
type Value = Result<f64, &'static str>;

/// J before and after, capacity before and after, of `row`.
fn values(row: &TableRow) -> [Value; 4] {
    let before = match &row.before {
        Some(cell) if cell.feasible => Ok(cell.cost),
        Some(_) => Err("infeasible"),
        None => Err("not solved"),
    };
    let after = match &row.after {
        Some(cell) => match &cell.best {
            Some(best) if best.feasible => Ok(best.cost),
            _ => Err("no feasible design"),
        },
        None => Err("not run"),
    };
    let capacity = |kg: Option<f64>| kg.ok_or("not searched");
    [
        before,
        after,
        capacity(row.capacity_before_kg),
        capacity(row.capacity_after_kg),
    ]
}

/// The chart as an inline SVG element (id `summary`), or None for a table of no case.
pub(super) fn summary_chart(table: &PaperTable) -> Option<String> {
    if table.rows.is_empty() {
        return None;
    }
    let rows: Vec<[Value; 4]> = table.rows.iter().map(values).collect();
    let largest = |k: usize| {
        let values = rows.iter().filter_map(|r| r[k].ok());
        values.fold(0.0, f64::max)
    };
    let scales = [largest(0).max(largest(1)), largest(2).max(largest(3))];
    let height = HEADER + ROW * rows.len() as f64 + 8.0;
    let mut svg = format!(
        r##"<svg id="summary" xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" viewBox="0 0 {WIDTH} {height}" font-family="sans-serif" font-size="11" role="img" aria-label="J and payload capacity of every case, before and after the co-design"><rect width="100%" height="100%" fill="white"/>"##
    );
    header(&mut svg);
    for (k, (row, values)) in table.rows.iter().zip(&rows).enumerate() {
        let top = HEADER + ROW * k as f64;
        let _ = write!(
            svg,
            r##"<text x="8" y="{:.1}">{} kg, {} space</text>"##,
            top + 19.0,
            escape_html(&row.payload_kg.to_string()),
            row.space
        );
        for (v, value) in values.iter().enumerate() {
            let panel = v / 2;
            let y = top + 4.0 + 13.0 * (v % 2) as f64;
            let colour = [BEFORE, AFTER][v % 2];
            bar(&mut svg, (PANELS[panel], y), (value, scales[panel]), colour);
        }
    }
    svg.push_str("</svg>\n");
    Some(svg)
}

/// The legend and the panels' titles.
fn header(svg: &mut String) {
    let _ = write!(
        svg,
        r##"<rect x="8" y="8" width="12" height="10" fill="{BEFORE}"/><text x="24" y="17">before: the original design</text><rect x="200" y="8" width="12" height="10" fill="{AFTER}"/><text x="216" y="17">after: the best co-designed design (CMA-ES)</text><text x="{}" y="40" font-weight="bold">J, the trajectory cost (lower is better)</text><text x="{}" y="40" font-weight="bold">payload capacity, kg (higher is better)</text>"##,
        PANELS[0], PANELS[1]
    );
}

/// A bar at (`x`, `y`) of `value` on a scale whose largest value is `largest`, with its value
/// written after it; or why it has none.
fn bar(svg: &mut String, (x, y): (f64, f64), (value, largest): (&Value, f64), colour: &str) {
    match value {
        Ok(value) => {
            let length = match largest > 0.0 {
                true => (value / largest * LONGEST).max(1.0),
                false => 1.0,
            };
            let _ = write!(
                svg,
                r##"<rect x="{x}" y="{y:.1}" width="{length:.1}" height="11" fill="{colour}"/><text x="{:.1}" y="{:.1}" font-size="10">{}</text>"##,
                x + length + 4.0,
                y + 9.5,
                rounded(*value)
            );
        }
        Err(why) => {
            let _ = write!(
                svg,
                r##"<text x="{x}" y="{:.1}" font-size="10" fill="#555">{why}</text>"##,
                y + 9.5
            );
        }
    }
}
