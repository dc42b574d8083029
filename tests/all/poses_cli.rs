//! The arm drawn by `codesign solve --plot` (`poses.svg`, `motion.svg`): each linkage over its
//! links (a screw's anchors and length, a crank and its rod), the base and a scale bar in every
//! panel, a spatial arm in a side and a top view, and every text inside its picture.

use crate::plot_figures_cli::texts_outside;
use crate::support;

use std::path::{Path, PathBuf};
use support::chromium::Browser;
use support::{scratch, succeed_in};

/// Solves the example `robots/examples/{robot}/{task}` in `dir` at `steps` nodes with `--plot
/// plots` and more `args`; the plots folder.
fn plots_of(dir: &Path, (robot, task): (&str, &str), steps: u64, args: &[&str]) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let examples = support::root().join("robots/examples").join(robot);
    let task = support::task_with(dir, |value| {
        *value = support::read_json(&examples.join(task));
        value["robot"] = examples.join("robot.urdf").to_str().unwrap().into();
        value["motion"]["steps"] = steps.into();
    });
    let mut all = vec!["solve", "--task", task.to_str().unwrap(), "--plot", "plots"];
    all.extend(args);
    succeed_in(dir, &all);
    dir.join("plots")
}

/// The number of elements of `svg` whose class is `class`.
fn of_class(svg: &str, class: &str) -> usize {
    svg.matches(&format!("class=\"{class}\"")).count()
}

#[test]
fn a_ball_screw_is_drawn_with_its_anchors_and_length() {
    let dir = scratch("poses-screw");
    let plots = plots_of(&dir, ("planar_2dof", "ball_screw.json"), 20, &[]);
    let poses = std::fs::read_to_string(plots.join("poses.svg")).unwrap();
    // In each of the five frames: the screw, its two anchors, its length in m.
    assert_eq!(of_class(&poses, "linkage screw"), 5, "{poses}");
    assert_eq!(of_class(&poses, "screw-body"), 5);
    assert_eq!(of_class(&poses, "anchor"), 10);
    let screws = poses.split("class=\"linkage screw\"").skip(1);
    let lengths = screws.filter(|s| s.split("</g>").next().unwrap().contains(" m</text>"));
    assert_eq!(lengths.count(), 5, "{poses}");
    assert_eq!(of_class(&poses, "base"), 5);
    assert_eq!(of_class(&poses, "scale-bar"), 1);
    assert_eq!(of_class(&poses, "linkage crank-rod"), 0);
    assert!(poses.contains("in the world x-z plane") && !poses.contains("top view"));
    let motion = std::fs::read_to_string(plots.join("motion.svg")).unwrap();
    let screw = motion.split("class=\"linkage screw\"").nth(1).unwrap();
    let values = screw.split("values=\"").nth(1).unwrap();
    assert_eq!(values.split('"').next().unwrap().split(';').count(), 21);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_crank_and_rod_is_drawn_with_its_circle() {
    let dir = scratch("poses-crank");
    let plots = plots_of(&dir, ("planar_2dof", "four_bar.json"), 20, &[]);
    let poses = std::fs::read_to_string(plots.join("poses.svg")).unwrap();
    for class in ["linkage crank-rod", "crank", "rod", "crank-circle", "pin"] {
        assert_eq!(of_class(&poses, class), 5, "{class}: {poses}");
    }
    assert_eq!(of_class(&poses, "linkage screw"), 0);
    let motion = std::fs::read_to_string(plots.join("motion.svg")).unwrap();
    assert_eq!(of_class(&motion, "linkage crank-rod"), 1);
    assert_eq!(of_class(&motion, "crank"), 1);
    assert_eq!(of_class(&motion, "rod"), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_spatial_arm_is_drawn_from_the_side_and_the_top() {
    let dir = scratch("poses-ur5");
    let plots = plots_of(&dir, ("ur5_6dof", "task.json"), 10, &[]);
    let poses = std::fs::read_to_string(plots.join("poses.svg")).unwrap();
    assert!(poses.contains("side view: world"), "{poses}");
    assert!(poses.contains("top view: world x-y"), "{poses}");
    // Two rows of five frames, a scale bar in each row.
    assert_eq!(of_class(&poses, "links"), 10);
    assert_eq!(of_class(&poses, "scale-bar"), 2);
    assert_eq!(poses.matches("t = ").count(), 5);
    let motion = std::fs::read_to_string(plots.join("motion.svg")).unwrap();
    assert_eq!(of_class(&motion, "links"), 2);
    assert_eq!(of_class(&motion, "scale-bar"), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_text_of_the_poses_stays_inside_its_picture() {
    // A screw's lengths and a payload's mass near the edges; an infeasible design's long
    // title; a spatial arm's two views.
    let dir = scratch("poses-texts");
    let screw = plots_of(
        &dir.join("screw"),
        ("planar_2dof", "ball_screw.json"),
        12,
        &[],
    );
    let heavy = dir.join("heavy");
    std::fs::create_dir_all(&heavy).unwrap();
    succeed_in(&heavy, &["solve", "--payload", "3", "--plot", "plots"]);
    let ur5 = plots_of(&dir.join("ur5"), ("ur5_6dof", "task.json"), 10, &[]);
    let mut browser = Browser::start(&dir.join("profile"), 2000, 1000);
    for folder in [screw, heavy.join("plots"), ur5] {
        for file in ["poses.svg", "motion.svg"] {
            let path = folder.join(file);
            browser.open(&path);
            let outside = texts_outside(&mut browser);
            assert_eq!(outside, serde_json::json!([]), "{}", path.display());
        }
    }
    let heavy = std::fs::read_to_string(dir.join("heavy/plots/motion.svg")).unwrap();
    assert!(heavy.contains("INFEASIBLE"));
    drop(browser);
    std::fs::remove_dir_all(&dir).unwrap();
}
