//! `index.html`, the page `reproduce` writes into its results folder, rendered in headless
//! Chromium: it loads with no error (no exception, no `console.error`, no failed or blocked
//! load), leads with the summary chart (no text of it clipped), shows the table and every plot
//! at a readable size, and the best design's arm moves in its animation
//! while its filmstrip stands still.

use crate::plot_figures_cli::texts_outside;
use crate::support;

use codesign::experiment::write_index;
use codesign::experiment::Layout;
use codesign::report::table::{build_table, read_result_file, PaperTable};
use codesign_core::problem::Space;
use serde_json::Value;
use std::path::Path;
use std::time::Duration;
use support::chromium::Browser;
use support::{codesign, root, scratch};

/// The table of the committed quick reproduction (`results/quick`).
fn quick_table() -> PaperTable {
    let mut files = Vec::new();
    for folder in ["original", "runs", "capacity"] {
        let folder = root().join("results/quick").join(folder);
        for entry in std::fs::read_dir(folder).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "json") {
                files.push(read_result_file(&path).unwrap());
            }
        }
    }
    build_table(&files, Vec::new())
}

/// The SVG files in `folder` and below, copied to `to` when given.
fn svg_files(folder: &Path, to: Option<&Path>) -> usize {
    let mut count = 0;
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        let copy = to.map(|to| to.join(path.file_name().unwrap()));
        if path.is_dir() {
            if let Some(copy) = &copy {
                std::fs::create_dir_all(copy).unwrap();
            }
            count += svg_files(&path, copy.as_deref());
        } else if path.extension().is_some_and(|e| e == "svg") {
            if let Some(copy) = &copy {
                std::fs::copy(&path, copy).unwrap();
            }
            count += 1;
        }
    }
    count
}

/// A results folder in `dir` with its page: the quick reproduction's table and plots, with the
/// plots of its best design at 1 kg in the actuation space solved afresh (the committed ones
/// predate the arm's animation).
fn results_folder(dir: &Path) -> Layout {
    let layout = Layout::new(dir.join("results"));
    std::fs::create_dir_all(layout.plots()).unwrap();
    svg_files(&root().join("results/quick/plots"), Some(&layout.plots()));
    let table = quick_table();
    let row = table
        .rows
        .iter()
        .find(|r| r.payload_kg == 1.0 && r.space == Space::Actuation && r.after.is_some());
    let best = row.and_then(|r| r.after.as_ref()?.best.as_ref()).unwrap();
    let ratios: Vec<String> = best.ratios.iter().map(|r| r.to_string()).collect();
    let plots = layout.best_plots(Space::Actuation, 1.0);
    let output = codesign(&[
        "solve",
        "--space",
        "actuation",
        "--payload",
        "1",
        "--ratios",
        &ratios.join(","),
        "--plot",
        plots.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    write_index(&layout, &table).unwrap();
    layout
}

/// The region of the page's image whose source ends with `file`, in CSS px from the page's
/// top left corner, scrolled into view (Chromium plays no animation out of view).
fn region(browser: &mut Browser, file: &str) -> Value {
    browser.evaluate(&format!(
        "(() => {{ const image = document.querySelector('img[src$=\"/{file}\"]'); \
         image.scrollIntoView({{ block: 'center' }}); const r = image.getBoundingClientRect(); \
         return {{ x: r.x + scrollX, y: r.y + scrollY, width: r.width, height: r.height }}; }})()"
    ))
}

#[test]
fn the_page_loads_without_error_and_the_arm_moves() {
    let dir = scratch("page");
    let layout = results_folder(&dir);
    let mut browser = Browser::start(&dir.join("profile"), 1300, 900);
    browser.open(&layout.index());
    let errors = browser.errors();
    assert!(errors.is_empty(), "{errors:#?}");
    let title = browser.evaluate("document.title");
    assert_eq!(
        title,
        "Table II reproduced: gear ratios and cost per payload"
    );
    // The answer first: the summary chart leads the page's charts, images and tables, and its
    // texts stay inside it; the line plots are shown at a readable width.
    let first = browser.evaluate("document.querySelector('svg, img, table').id");
    assert_eq!(first, "summary");
    let outside = texts_outside(&mut browser);
    assert_eq!(outside, serde_json::json!([]));
    let narrowest = browser.evaluate(
        "Math.min(...Array.from(document.querySelectorAll('img[src$=\"/joint_torques.svg\"]')) \
         .map(i => i.getBoundingClientRect().width))",
    );
    assert!(narrowest.as_f64() >= Some(500.0), "{narrowest}");
    let tables = browser.evaluate("document.querySelectorAll('table').length");
    assert!(tables.as_u64() >= Some(2), "{tables}");
    // Every plot shown, every image decoded.
    let broken = browser.evaluate(
        "Array.from(document.images).filter(i => !i.complete || i.naturalWidth == 0).length",
    );
    assert_eq!(broken, 0);
    let images = browser.evaluate("document.images.length").as_u64().unwrap();
    assert_eq!(images as usize, svg_files(&layout.plots(), None));
    // The filmstrip stands still: two screenshots of it are the same, so a difference in the
    // animation's is its motion.
    let filmstrip = region(&mut browser, "poses.svg");
    let still = browser.screenshot(&filmstrip);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(browser.screenshot(&filmstrip), still);
    let animation = region(&mut browser, "motion.svg");
    assert!(animation["width"].as_f64() > Some(100.0), "{animation}");
    let first = browser.screenshot(&animation);
    let moved = (0..10).any(|_| {
        std::thread::sleep(Duration::from_millis(200));
        browser.screenshot(&animation) != first
    });
    assert!(moved, "the arm stood still for 2 s in {animation}");
    let errors = browser.errors();
    assert!(errors.is_empty(), "{errors:#?}");
    // The animation's caption whole: no text of it leaves its picture.
    browser.open(&layout.best_plots(Space::Actuation, 1.0).join("motion.svg"));
    assert_eq!(texts_outside(&mut browser), serde_json::json!([]));
    drop(browser);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The committed pages of the full and the quick reproduction and of a linkage example's (the
/// ball-screw elbow's quick reproduction), as a reader opens them: no error, the summary chart
/// first with its texts inside it, every image decoded.
#[test]
fn the_committed_pages_lead_with_the_summary_and_load_whole() {
    let dir = scratch("committed");
    let mut browser = Browser::start(&dir.join("profile"), 1300, 900);
    for folder in [
        "results",
        "results/quick",
        "results/linkage/ball_screw_quick",
    ] {
        browser.open(&root().join(folder).join("index.html"));
        let first = browser.evaluate("document.querySelector('svg, img, table').id");
        assert_eq!(first, "summary", "{folder}");
        assert_eq!(
            texts_outside(&mut browser),
            serde_json::json!([]),
            "{folder}"
        );
        let broken = browser.evaluate(
            "Array.from(document.images).filter(i => !i.complete || i.naturalWidth == 0).length",
        );
        assert_eq!(broken, 0, "{folder}");
        let errors = browser.errors();
        assert!(errors.is_empty(), "{folder}: {errors:#?}");
    }
    drop(browser);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The check above sees an error: a page with an exception, a `console.error`, a missing image
/// and one its content security policy blocks reports each.
#[test]
fn the_browser_reports_a_page_s_errors() {
    let dir = scratch("errors");
    let page = dir.join("broken.html");
    std::fs::write(
        &page,
        "<!DOCTYPE html><html><head><meta http-equiv=\"Content-Security-Policy\" \
         content=\"default-src 'none'; img-src 'self'; script-src 'unsafe-inline'\"><title>broken</title></head>\
         <body><img src=\"missing.svg\"><img src=\"https://example.com/a.png\">\
         <script>console.error('from the console'); undefined_function();</script></body></html>",
    )
    .unwrap();
    let mut browser = Browser::start(&dir.join("profile"), 800, 600);
    browser.open(&page);
    let errors = browser.errors().join("\n");
    for expected in [
        "from the console",
        "undefined_function is not defined",
        "missing.svg",
        "violates the following Content Security Policy",
    ] {
        assert!(errors.contains(expected), "{expected}: {errors}");
    }
    drop(browser);
    std::fs::remove_dir_all(&dir).unwrap();
}
