//! The front page of a results folder, `index.html`: the answer first (a chart of every case's
//! J and payload capacity before and after the co-design), then the table as HTML, then each
//! case's plots, the best design's animation and filmstrip first. One page that needs no network: the plots
//! are linked by relative paths, the style is inline, there is no script, and its content
//! security policy lets it load nothing but images beside it.

use super::summary::summary_chart;
use super::Layout;
use crate::report::motor_plots::{motor_plot_file, LINKAGE_RATIOS_FILE};
use crate::report::poses::{MOTION_FILE, POSES_FILE};
use crate::report::table::{escape_html, to_html, Block, PaperTable};
use crate::report::trajectory::PLOT_FILES;
use crate::report::ReportError;
use crate::store::files::write_atomic;
use codesign_core::problem::Space;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The page's style: readable tables, the charts two to a row at a readable size (each links to
/// its full size), the summary chart, the arm's animation and filmstrip as drawn, no wider than
/// the page.
const STYLE: &str = "body { font-family: sans-serif; margin: 1em auto; max-width: 1300px; \
     padding: 0 1em; line-height: 1.4; } \
     table { border-collapse: collapse; font-size: 0.85em; margin: 1em 0; } \
     th, td { border: 1px solid #bbb; padding: 0.25em 0.5em; vertical-align: top; } \
     th { background: #eef; } blockquote { color: #444; border-left: 3px solid #ccd; \
     margin: 0.8em 0; padding-left: 0.8em; } code { background: #f3f3f3; } \
     figure { display: inline-block; margin: 0.5em; vertical-align: top; width: 620px; \
     max-width: 100%; } figure.arm, figure.summary { width: auto; } \
     #summary { max-width: 100%; height: auto; } \
     img { width: 100%; max-width: 100%; height: auto; border: 1px solid #ddd; } \
     figure.arm img { width: auto; } \
     figcaption { font-size: 0.8em; color: #555; }";

/// The policy that keeps the page offline: images from beside it, the inline style, nothing
/// else.
const POLICY: &str = "default-src 'none'; img-src 'self'; style-src 'unsafe-inline'";

/// The plots of a design in `folder` in the order shown: the animation and the filmstrip, the
/// charts, each motor's torque-speed figure, the linkage rows' ratios (those it holds).
fn plot_order(folder: &Path) -> Vec<PathBuf> {
    let motors = (0..).map(motor_plot_file);
    let motors = motors.take_while(|file| folder.join(file).is_file());
    let files = [MOTION_FILE, POSES_FILE].into_iter().chain(PLOT_FILES);
    let mut files: Vec<String> = files.map(String::from).chain(motors).collect();
    files.push(LINKAGE_RATIOS_FILE.to_owned());
    let files = files.into_iter().map(|file| folder.join(file));
    files.filter(|plot| plot.is_file()).collect()
}

/// Writes `index.html` into the results folder of `layout`: `table`, and the plots of each of
/// its cases that the folder holds.
pub fn write_index(layout: &Layout, table: &PaperTable) -> Result<(), ReportError> {
    write_atomic(&layout.index(), index_page(layout, table).as_bytes())?;
    Ok(())
}

/// The page of `table` and the plots under `layout`.
pub fn index_page(layout: &Layout, table: &PaperTable) -> String {
    let mut page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta http-equiv=\"Content-Security-Policy\" content=\"{POLICY}\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n",
        escape_html(&table.title)
    );
    let blocks = table.blocks();
    let title = usize::from(matches!(blocks.first(), Some(Block::Heading(1, _))));
    page.push_str(&to_html(&blocks[..title]));
    if let Some(chart) = summary_chart(table) {
        page.push_str("<h2>Every case, before and after</h2>\n");
        let _ = writeln!(page, "<figure class=\"summary\">{chart}</figure>");
    }
    page.push_str(&to_html(&blocks[title..]));
    page.push_str(&files_paragraph(layout, table));
    let mut cases = Vec::new();
    for row in &table.rows {
        if !cases.contains(&(row.payload_kg, row.space)) {
            cases.push((row.payload_kg, row.space));
        }
    }
    let sections: Vec<String> = cases
        .iter()
        .filter_map(|&(payload, space)| case_section(layout, payload, space))
        .collect();
    if !sections.is_empty() {
        page.push_str("<h2>Plots</h2>\n<p>Each plot opens full size on click.</p>\n");
        page.push_str(&sections.concat());
    }
    let ratios = layout.optimal_ratios();
    if ratios.is_file() {
        page.push_str("<h3>The best design of every case</h3>\n");
        page.push_str(&figure(layout, &ratios));
    }
    page.push_str("</body>\n</html>\n");
    page
}

/// The paragraph that links the table's files and, when it has one, the hold section's page.
fn files_paragraph(layout: &Layout, table: &PaperTable) -> String {
    let mut files = Vec::new();
    for path in [layout.table_markdown(), layout.table_json()] {
        files.push(link(layout, &path, &file_name(&path)));
    }
    let hold = layout.hold().index();
    if !table.hold.is_empty() && hold.is_file() {
        files.push(link(
            layout,
            &hold,
            "the same cases with the load held at rest",
        ));
    }
    format!("<p>The table in files: {}.</p>\n", files.join(", "))
}

/// The plots of one case: the best design's, the cost per evaluation of its co-design, the
/// original design's; None when the folder holds none.
fn case_section(layout: &Layout, payload_kg: f64, space: Space) -> Option<String> {
    let existing = |plots: Vec<PathBuf>| -> Vec<PathBuf> {
        plots.into_iter().filter(|plot| plot.is_file()).collect()
    };
    let of_design = |folder: PathBuf| plot_order(&folder);
    let parts = [
        (
            "Best design (CMA-ES)",
            of_design(layout.best_plots(space, payload_kg)),
        ),
        (
            "Cost per evaluation of the co-design",
            existing(vec![layout.cost_evolution(space, payload_kg)]),
        ),
        (
            "Original design",
            of_design(layout.original_plots(space, payload_kg)),
        ),
    ];
    let mut body = String::new();
    for (name, plots) in parts.iter().filter(|(_, plots)| !plots.is_empty()) {
        let _ = writeln!(body, "<h4>{name}</h4>");
        body.extend(plots.iter().map(|plot| figure(layout, plot)));
    }
    if body.is_empty() {
        return None;
    }
    Some(format!(
        "<section id=\"{space}-{payload_kg}kg\">\n<h3>{payload_kg} kg, {space} space</h3>\n{body}</section>\n"
    ))
}

/// One plot as an image with its file's name below, linked to the file; the arm's animation
/// and filmstrip at their size.
fn figure(layout: &Layout, plot: &Path) -> String {
    let name = file_name(plot);
    let href = relative_href(layout, plot);
    let class = if [MOTION_FILE, POSES_FILE].contains(&name.as_str()) {
        " class=\"arm\""
    } else {
        ""
    };
    format!(
        "<figure{class}><a href=\"{href}\"><img src=\"{href}\" alt=\"{}\"></a><figcaption>{}</figcaption></figure>\n",
        escape_html(&name),
        escape_html(&name)
    )
}

/// A link to `path` saying `text`.
fn link(layout: &Layout, path: &Path, text: &str) -> String {
    format!(
        "<a href=\"{}\">{}</a>",
        relative_href(layout, path),
        escape_html(text)
    )
}

/// The last component of `path`, as text.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// `path` relative to the results folder as a URL path: components joined by `/`, each byte
/// outside the characters a URL leaves as they are percent-encoded.
fn relative_href(layout: &Layout, path: &Path) -> String {
    let relative = path.strip_prefix(layout.root()).unwrap_or(path);
    let components: Vec<String> = relative
        .components()
        .map(|c| {
            let mut encoded = String::new();
            for byte in c.as_os_str().to_string_lossy().bytes() {
                match byte {
                    b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' => {
                        encoded.push(byte as char)
                    }
                    _ => {
                        let _ = write!(encoded, "%{byte:02X}");
                    }
                }
            }
            encoded
        })
        .collect();
    components.join("/")
}

#[cfg(test)]
mod tests {
    use super::{index_page, relative_href};
    use crate::experiment::Layout;
    use crate::report::table::{build_table, read_result_file};
    use std::path::Path;

    #[test]
    fn links_are_relative_and_encoded() {
        let layout = Layout::new("/tmp/out");
        let plot = Path::new("/tmp/out/plots/best-joint-1.5kg/a b#<c>.svg");
        assert_eq!(
            relative_href(&layout, plot),
            "plots/best-joint-1.5kg/a%20b%23%3Cc%3E.svg"
        );
    }

    /// The committed quick results: the table, and each case's plots that exist, linked relative
    /// to the folder, the best design's animation and filmstrip first.
    #[test]
    fn the_page_shows_the_table_and_the_plots_it_finds() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/quick");
        let mut files = Vec::new();
        for folder in ["original", "runs", "capacity"] {
            for entry in std::fs::read_dir(root.join(folder)).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "json") {
                    files.push(read_result_file(&path).unwrap());
                }
            }
        }
        let table = build_table(&files, vec!["A <note> & more".to_owned()]);
        let page = index_page(&Layout::new(&root), &table);
        assert!(page.contains("<blockquote>A &lt;note&gt; &amp; more</blockquote>"));
        // Table II, beyond the paper, the payload ranges and the graded penalty.
        assert_eq!(page.matches("<table>").count(), 4, "{page}");
        for plot in [
            "plots/best-actuation-1kg/joint_torques.svg",
            "plots/cost_evolution-joint-3kg.svg",
            "plots/original-joint-0kg/tcp_path.svg",
            "plots/optimal_ratios.svg",
            "plots/best-actuation-1kg/motion.svg",
            "plots/best-actuation-1kg/poses.svg",
        ] {
            assert!(page.contains(&format!("<img src=\"{plot}\"")), "{plot}");
        }
        let animation = page.find("best-actuation-1kg/motion.svg").unwrap();
        assert!(animation < page.find("best-actuation-1kg/joint_torques.svg").unwrap());
        assert!(!page.contains(root.to_str().unwrap()), "{page}");
        assert!(page.contains("<h3>1 kg, joint space</h3>"));
        // The answer first: the chart of every case before the tables, a bar per value.
        let chart = page.find("<svg id=\"summary\"").unwrap();
        assert!(chart < page.find("<table>").unwrap());
        assert!(page.find("<h1>").unwrap() < chart);
        assert!(
            page.contains("<text x=\"8\" y=\"69.0\">0 kg, joint space</text>"),
            "{page}"
        );
    }
}
