//! `codesign check`'s findings and their weight: an error where a solve refuses the task or its
//! result would mean nothing (exit 1), a warning where the solve runs (exit 0, noted on stderr);
//! the limit modes judged in the solve's own words, the TCP against the soft box at both ends,
//! and where a linkage's loop opens or its ratio changes sign (issue 57, items 14 to 16).

use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;
use support::{codesign, fails_saying, scratch};

/// The shipped four-bar example (`robots/examples/planar_2dof/four_bar.json`) with its robot's
/// path made absolute and `edit` applied, written to `dir/<name>.json`.
fn four_bar(dir: &Path, name: &str, edit: impl Fn(&mut Value)) -> PathBuf {
    let example = support::root().join("robots/examples/planar_2dof");
    let mut task = support::read_json(&example.join("four_bar.json"));
    task["robot"] = example.join("robot.urdf").to_str().unwrap().into();
    edit(&mut task);
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, task.to_string()).unwrap();
    file
}

/// `codesign check --task <task>` with `more` flags.
fn check(task: &Path, more: &[&str]) -> Output {
    let args = [&["check", "--task", task.to_str().unwrap()], more].concat();
    codesign(&args)
}

/// Asserts that the command succeeded; returns its stdout and stderr.
fn passes(output: &Output) -> (String, String) {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(0), "{stdout}{stderr}");
    (stdout, stderr)
}

/// What a refused solve says, without its `error: ` and its line's end.
fn refusal(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let line = stderr.lines().last().unwrap();
    line.strip_prefix("error: ").unwrap().to_owned()
}

/// The shipped examples pass their own check: the ratios that change sign within the joint
/// limits (where the motion does not go) are warnings, each naming the elbow angles of its dead
/// points; the ball screw's lie where it lines up with the elbow, at +-pi/2 (robots/README.md).
#[test]
fn the_shipped_linkages_pass_their_check_naming_their_dead_points() {
    let examples = support::root().join("robots/examples/planar_2dof");
    let (text, notes) = passes(&check(&examples.join("four_bar.json"), &[]));
    assert!(
        notes.contains("warning: motor 2: its ratio to joint elbow changes sign"),
        "{notes}"
    );
    assert!(
        text.contains("the motor passes a dead point near elbow = "),
        "{text}"
    );
    let output = check(&examples.join("ball_screw.json"), &["--json"]);
    let (json, notes) = passes(&output);
    let value: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(value["problems"], serde_json::json!([]));
    let dead: Vec<f64> = (value["linkages"][0]["range"]["dead_points"].as_array())
        .unwrap()
        .iter()
        .map(|point| point["at"][0].as_f64().unwrap())
        .collect();
    assert_eq!(dead.len(), 2, "{dead:?}");
    for (found, expected) in dead.iter().zip([-1.0, 1.0]) {
        let expected = expected * std::f64::consts::FRAC_PI_2;
        assert!(
            (found - expected).abs() < 1e-6,
            "{found} against {expected}"
        );
    }
    let warning = "the motor passes a dead point near elbow = -1.57 rad and elbow = 1.57 rad";
    assert!(notes.contains(warning), "{notes}");
    assert_eq!(value["warnings"].as_array().unwrap().len(), 1, "{json}");
}

/// A rod of 0.15 m cannot close the four-bar for elbow angles up to about -0.08 rad: `check`
/// names that interval, a warning while the motion stays where the loop closes, an error (a
/// solve refuses it) once the start lies inside it. The interval's end agrees with the start's
/// own reading of the loop, a path of its own through G(q).
#[test]
fn check_says_where_a_loop_opens_and_fails_only_where_a_solve_would() {
    let dir = scratch("open-loop");
    let short_rod = |start: f64| {
        move |task: &mut Value| {
            task["transmission"]["matrix"][1]["crank_rod"]["rod_m"] = 0.15.into();
            task["motion"]["start"][1] = start.into();
        }
    };
    let task = four_bar(&dir, "inside", short_rod(0.5));
    let (json, notes) = passes(&check(&task, &["--json"]));
    assert!(
        notes.contains(
            "the loop does not close at 1985 of 4096 poses within the joint limits: for elbow \
             in [-2.6, -0.0806] rad"
        ),
        "{notes}"
    );
    let value: Value = serde_json::from_str(&json).unwrap();
    let open = &value["linkages"][0]["range"]["open_within"][0];
    assert_eq!(open.as_array().unwrap().len(), 1, "{open}");
    assert_eq!(open[0][0].as_f64(), Some(-2.6));
    let edge = open[0][1].as_f64().unwrap();
    let step = 5.2 / 4095.0;
    let at_edge = four_bar(&dir, "edge", short_rod(edge));
    fails_saying(
        &check(&at_edge, &[]),
        "design: at the start, the linkage of motor 2 (transmission.matrix[1]): its rod cannot \
         reach the crank pin",
    );
    let beyond = four_bar(&dir, "beyond", short_rod(edge + step));
    passes(&check(&beyond, &[]));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// With a linkage row, the box modes are refused by every solve: `check` fails on them with
/// the solve's own words, naming every mode each space refuses (the actuation space's speed
/// mode; the joint space's torque mode too).
#[test]
fn check_refuses_the_limit_modes_a_solve_refuses_in_its_words() {
    let dir = scratch("modes");
    let modes = |torque: &'static str, speed: &'static str| {
        move |task: &mut Value| {
            task["limit_modes"] = serde_json::json!({ "torque": torque, "speed": speed });
            task["motion"]["steps"] = 10.into();
        }
    };
    let both = four_bar(&dir, "both", modes("paper", "paper"));
    let solve = |task: &Path, space: &str| {
        let args = ["solve", "--space", space, "--payload", "0.1"];
        refusal(&codesign(
            &[&args[..], &["--task", task.to_str().unwrap()]].concat(),
        ))
    };
    let (actuation, joint) = (solve(&both, "actuation"), solve(&both, "joint"));
    assert!(
        joint.contains("limit_modes.torque = \"paper\" and limit_modes.speed = \"paper\" carry"),
        "{joint}"
    );
    let output = check(&both, &[]);
    fails_saying(&output, "1 problem(s) found: limit modes: ");
    fails_saying(&output, &actuation);
    fails_saying(&output, &joint);
    let torque = four_bar(&dir, "torque", modes("paper", "exact"));
    let output = check(&torque, &[]);
    fails_saying(&output, &solve(&torque, "joint"));
    let exact = four_bar(&dir, "exact", modes("exact", "exact"));
    let (text, _) = passes(&check(&exact, &[]));
    assert!(text.contains("ok   limit modes: torque \"exact\", speed \"exact\""));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The planar arm's TCP is 0.0501 m high at both ends of its task; a soft box from 0.1 m up
/// leaves both below it by 0.0499 m, which `check` warns of (the box is a penalty in J, not a
/// limit a solve refuses) and exits 0.
#[test]
fn check_warns_of_a_tcp_outside_the_soft_box_at_the_start_and_the_goal() {
    let dir = scratch("box");
    let example = support::root().join("robots/examples/planar_2dof");
    let mut task = support::read_json(&example.join("task.json"));
    task["robot"] = example.join("robot.urdf").to_str().unwrap().into();
    task["cartesian_box"]["z"]["range"] = serde_json::json!([0.1, 1.0]);
    let file = dir.join("box.json");
    std::fs::write(&file, task.to_string()).unwrap();
    let (json, _) = passes(&check(&file, &["--json"]));
    let value: Value = serde_json::from_str(&json).unwrap();
    for (pose, hold) in ["start", "goal"]
        .iter()
        .zip(value["holds"].as_array().unwrap())
    {
        let z = hold["tcp_m"][2].as_f64().unwrap();
        assert!((z - 0.0501).abs() < 5e-5, "{pose}: {z}");
        let line =
            format!("the TCP at the {pose} lies 0.0499 m below cartesian_box.z.range [0.1, 1]");
        assert!(
            value["warnings"][0].as_str().unwrap().contains(&line),
            "{line}: {json}"
        );
    }
    assert_eq!(value["problems"], serde_json::json!([]));
    let (text, notes) = passes(&check(&file, &[]));
    assert!(
        text.contains("warn box: the TCP at the start lies"),
        "{text}"
    );
    assert!(
        notes.contains("warning: box: the TCP at the start lies"),
        "{notes}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
