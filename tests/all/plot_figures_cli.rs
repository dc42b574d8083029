//! What `codesign solve --plot` says in its figures: an infeasible design's titles say so and
//! why, every motor has its torque-speed figure, and a linkage's ratios are drawn over time.

use crate::support;

use std::path::Path;
use support::chromium::Browser;
use support::{read_json, scratch, succeed_in};

/// The texts of `svg` in order (plotters writes `<text ...>\nTEXT\n</text>`), joined by spaces.
fn texts(svg: &str) -> String {
    let pieces = svg.split("</text>").filter_map(|piece| {
        let text = &piece[piece.rfind('>')? + 1..];
        Some(text.trim().to_owned())
    });
    pieces.collect::<Vec<_>>().join(" ")
}

/// The chart files of a solve's plots of `motors` motors.
fn charts(motors: usize) -> Vec<String> {
    let mut files: Vec<String> = [
        "joint_positions",
        "joint_torques",
        "motor_torques",
        "tcp_path",
    ]
    .map(|name| format!("{name}.svg"))
    .to_vec();
    files.extend((1..=motors).map(|k| format!("motor_{k}_torque_speed.svg")));
    files
}

/// Solves in `dir` with `args`, `--plot plots` and `--out r.json`; the result.
fn solve(dir: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["solve", "--plot", "plots", "--out", "r.json"];
    all.extend(args);
    succeed_in(dir, &all);
    read_json(&dir.join("r.json"))
}

#[test]
fn an_infeasible_designs_plots_say_so_and_why() {
    let dir = scratch("infeasible-plots");
    // The built-in arm's original design cannot move 3 kg.
    let result = solve(&dir, &["--payload", "3"]);
    assert_eq!(result["feasible"], false);
    let reason = result["reason"].as_str().unwrap();
    for file in charts(4) {
        let svg = std::fs::read_to_string(dir.join("plots").join(&file)).unwrap();
        let said = texts(&svg);
        assert!(
            said.contains(&format!("INFEASIBLE: {reason}")),
            "{file}: {said}"
        );
    }
    // A feasible one's do not.
    let feasible = scratch("feasible-plots");
    assert_eq!(solve(&feasible, &[])["feasible"], true);
    for file in charts(4) {
        let svg = std::fs::read_to_string(feasible.join("plots").join(&file)).unwrap();
        assert!(!svg.contains("INFEASIBLE"), "{file}");
    }
    assert!(!feasible.join("plots/motor_5_torque_speed.svg").exists());
    assert!(!feasible.join("plots/linkage_ratios.svg").exists());
}

#[test]
fn a_ball_screws_ratio_is_drawn_over_time_and_each_motor_has_its_figure() {
    let dir = scratch("linkage-plots");
    let task = support::root().join("robots/examples/planar_2dof/ball_screw.json");
    solve(&dir, &["--task", task.to_str().unwrap()]);
    let plots = dir.join("plots");
    for file in charts(2) {
        assert!(plots.join(&file).is_file(), "{file}");
    }
    let ratios = texts(&std::fs::read_to_string(plots.join("linkage_ratios.svg")).unwrap());
    // The screw drives motor 2 from the elbow alone: one curve, G[motor 2, elbow].
    assert!(ratios.contains("G[motor 2, elbow]"), "{ratios}");
    assert!(!ratios.contains("G[motor 1"), "{ratios}");
    assert!(ratios.contains("Ratios of the linkage rows, G(q) over time"));
}

/// The texts of the SVG open in `browser` whose box on screen (rotated ones turned) leaves its
/// picture, with their boxes.
pub(crate) fn texts_outside(browser: &mut Browser) -> serde_json::Value {
    browser.evaluate(
        "(() => { const svg = document.querySelector('svg'); \
         const p = svg.getBoundingClientRect(); \
         return [...svg.querySelectorAll('text')] \
         .map(t => [t.textContent.trim(), t.getBoundingClientRect()]) \
         .filter(([_, b]) => b.left < p.left || b.top < p.top || b.right > p.right \
           || b.bottom > p.bottom) \
         .map(([text, b]) => `${text}: ${b.left},${b.top} to ${b.right},${b.bottom} \
           in ${p.width}x${p.height}`); })()",
    )
}

#[test]
fn every_text_of_the_charts_stays_inside_its_picture() {
    // An infeasible design's long titles, the shared limits' legend entries, the motors'.
    let dir = scratch("texts-inside");
    solve(&dir, &["--payload", "3"]);
    let mut browser = Browser::start(&dir.join("profile"), 1400, 700);
    for file in charts(4) {
        browser.open(&dir.join("plots").join(&file));
        let outside = texts_outside(&mut browser);
        assert_eq!(outside, serde_json::json!([]), "{file}");
    }
}
