//! `codesign check`: the inspection of a robot and its task, a verdict per check, and every
//! problem listed with exit 1.

use crate::support;

use support::{codesign, fails_saying, scratch, task_with};

#[test]
fn the_built_in_task_passes_every_check() {
    let output = codesign(&["check"]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for line in [
        "4 moving joints, TCP on link 'link_4', payload 0 kg",
        "joint 2 'joint_arm_2'",
        "G:",
        "G^-1:",
        "ok   motion",
        "ok   design",
        "ok   hold at start",
        "ok   hold at goal",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let json = codesign(&["check", "--json"]);
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["joints"].as_array().unwrap().len(), 4);
    assert_eq!(value["g"][3][3], -1.0);
    assert_eq!(value["holds"][0]["pose"], "start");
}

/// `--ratios "9, 5.62, 3, 1.8"`, as a person types a list, is the design `9,5.62,3,1.8`.
#[test]
fn ratios_may_have_spaces_around_their_commas() {
    let spaced = codesign(&["check", "--json", "--ratios", " 9, 5.62 ,3,  1.8"]);
    let tight = codesign(&["check", "--json", "--ratios", "9,5.62,3,1.8"]);
    assert!(
        spaced.status.success(),
        "{}",
        String::from_utf8_lossy(&spaced.stderr)
    );
    assert_eq!(spaced.stdout, tight.stdout);
    let value: serde_json::Value = serde_json::from_slice(&spaced.stdout).unwrap();
    assert_eq!(value["g"][0][0], 9.0);
}

#[test]
fn every_problem_is_listed() {
    // 3 kg on the best 3 kg design of the reproduction's rows: the motors cannot hold it still,
    // a problem where the ends ask for the hold, and a line of information under the paper's.
    let output = codesign(&[
        "check",
        "--payload",
        "3",
        "--ratios",
        "9,5,3,3",
        "--ends",
        "hold",
    ]);
    fails_saying(&output, "2 problem(s) found: hold at start: motor 2 needs");
    fails_saying(&output, "hold at goal: motor 2 needs");
    let paper = codesign(&["check", "--payload", "3", "--ratios", "9,5,3,3"]);
    let text = String::from_utf8_lossy(&paper.stdout);
    assert_eq!(paper.status.code(), Some(0), "{text}");
    assert!(
        text.contains("the motors cannot hold the load still (not required: motion.ends is paper)"),
        "{text}"
    );
    let dir = scratch("check");
    let task = task_with(&dir, |task| task["motion"]["start"][1] = 9.0.into());
    let output = codesign(&[
        "check",
        "--task",
        task.to_str().unwrap(),
        "--ratios",
        "6,7,1,1",
    ]);
    fails_saying(
        &output,
        "motion: motion.start[1] = 9 rad is outside joint 'joint_arm_2'",
    );
    fails_saying(&output, "design: ");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The hold is judged at the task's `constr_viol_tol`, as the solves judge it, not at a fixed
/// default: a shortfall within the tolerance is no problem (motor 2 lacks 1.06 N m at the start
/// and 1.21 N m at the goal at 3 kg).
#[test]
fn the_hold_is_judged_at_the_tasks_constraint_tolerance() {
    let dir = scratch("tolerance");
    let check = |tolerance: f64| {
        let task = task_with(&dir, |task| {
            task["solver"]["options"]["constr_viol_tol"] = tolerance.into();
        });
        let task = task.to_str().unwrap().to_owned();
        codesign(&[
            "check",
            "--task",
            &task,
            "--payload",
            "3",
            "--ratios",
            "9,5,3,3",
            "--ends",
            "hold",
        ])
    };
    fails_saying(&check(1e-6), "hold at start: motor 2 needs");
    let loose = check(1.5);
    let text = String::from_utf8_lossy(&loose.stdout);
    assert_eq!(loose.status.code(), Some(0), "{text}");
    assert!(text.contains("ok   hold at start"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// With `--robot` and no task, the robot alone: its chain to its tip link and the notes of what
/// reading it locked.
#[test]
fn a_robot_alone_is_inspected() {
    let urdf = support::root().join("tests/data/urdf/gripper.urdf");
    let output = codesign(&["check", "--robot", urdf.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        // The tip link the TCP is read on (link_4 and the hand are fixed to it too).
        text.contains("2 moving joints, TCP on link 'link_2'"),
        "{text}"
    );
    assert!(
        text.contains("note: joint 'finger_left' (prismatic) is not on the chain"),
        "{text}"
    );
    let dynamics = codesign(&[
        "dynamics",
        "--robot",
        urdf.to_str().unwrap(),
        "--q",
        "0.1,0.2",
    ]);
    assert!(
        dynamics.status.success(),
        "{}",
        String::from_utf8_lossy(&dynamics.stderr)
    );
}

/// Names read from a URDF reach the terminal on one line and in order: a newline or a
/// right-to-left override in a link's or joint's name is printed as its escape (issue 38,
/// probe D15).
#[test]
fn names_that_steer_a_terminal_are_escaped() {
    let dir = support::scratch("names");
    let source = support::root().join("tests/data/urdf/gripper.urdf");
    let text = std::fs::read_to_string(source)
        .unwrap()
        .replace("\"link_2\"", "\"link&#10;2&#x202E;\"");
    let urdf = dir.join("names.urdf");
    std::fs::write(&urdf, text).unwrap();
    let output = codesign(&["check", "--robot", urdf.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("TCP on link 'link\\n2\\u{202e}'"),
        "{stdout}"
    );
    assert!(!stdout.contains('\u{202e}'), "{stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The planar arm's elbow driven by a ball screw (lead 10 mm) from 0.15 m up the upper arm to a
/// lever 0.10 m across the forearm: `check` shows its ratio, its length and its dead points, and
/// fails listing them.
#[test]
fn check_shows_a_ball_screws_ratio_length_and_dead_points() {
    let dir = scratch("screw");
    let example = support::root().join("robots/examples/planar_2dof");
    let text = std::fs::read_to_string(example.join("task.json")).unwrap();
    let mut task: serde_json::Value = serde_json::from_str(&text).unwrap();
    task["robot"] = example.join("robot.urdf").to_str().unwrap().into();
    task["transmission"]["matrix"][1] = serde_json::json!({"linear": {
        "from": {"link": "upper_arm", "point": [0.15, 0, 0]},
        "to": {"link": "forearm", "point": [0, 0, 0.1]},
        "lead_m": 0.01, "stroke_m": [0.06, 0.24]}});
    let file = dir.join("task.json");
    std::fs::write(&file, task.to_string()).unwrap();
    let output = codesign(&["check", "--task", file.to_str().unwrap(), "--json"]);
    // The start's screw (0.249977 m) is already beyond the stroke's 0.24 m; over the range it
    // passes its dead points.
    fails_saying(
        &output,
        "the screw of motor 2 (transmission.matrix[1]) is 0.249977 m long",
    );
    fails_saying(&output, "motor 2: its ratio to joint elbow changes sign");
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let screw = &value["linkages"][0];
    assert_eq!(screw["joints"], serde_json::json!(["elbow"]));
    // The screw's vector from the upper arm's anchor: (0.15 - 0.1 sin q, 0, 0.1 cos q) in the
    // upper arm's frame (the elbow turns about -y), so dL/dq = -0.015 cos q / L.
    for (pose, q) in [(0, -1.543_f64), (1, 1.543)] {
        let length = ((0.15 - 0.1 * q.sin()).powi(2) + (0.1 * q.cos()).powi(2)).sqrt();
        let ratio = std::f64::consts::TAU / 0.01 * (-0.015 * q.cos() / length);
        let reading = &screw["poses"][pose];
        let found = reading["ratio"][0].as_f64().unwrap();
        assert!(
            (found - ratio).abs() < 1e-9 * ratio.abs(),
            "{found} against {ratio}"
        );
        assert!((reading["measure"].as_f64().unwrap() - length).abs() < 1e-12);
    }
    let warnings = screw["warnings"].to_string();
    assert!(warnings.contains("changes sign"), "{warnings}");
    assert!(
        warnings.contains("beyond its stroke [0.06, 0.24] m"),
        "{warnings}"
    );
    let text = codesign(&["check", "--task", file.to_str().unwrap()]);
    let shown = String::from_utf8_lossy(&text.stdout);
    assert!(
        shown.contains("motor 2 (row 1): linear linkage over joint(s) elbow"),
        "{shown}"
    );
}

/// `check --ratios` reads the linkages at the design given: the ball-screw example's lead as
/// r2 = 8 mm gives the screw's ratio at the start, -(2 pi / 0.008) 0.015 cos(-1) / L(-1) with
/// L(-1)^2 = 0.0325 + 0.03 sin 1 (robots/README.md).
#[test]
fn check_reads_the_linkages_at_the_design_given() {
    let task = support::root().join("robots/examples/planar_2dof/ball_screw.json");
    let output = codesign(&[
        "check",
        "--task",
        task.to_str().unwrap(),
        "--ratios",
        "50,8",
        "--json",
    ]);
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let found = value["linkages"][0]["poses"][0]["ratio"][0]
        .as_f64()
        .unwrap();
    let length = (0.0325 + 0.03 * 1f64.sin()).sqrt();
    let ratio = -std::f64::consts::TAU / 0.008 * 0.015 * 1f64.cos() / length;
    assert!(
        (found - ratio).abs() < 1e-9 * ratio.abs(),
        "{found} against {ratio}"
    );
}

/// A task file's name reaches the messages as a terminal may show it: an escape in it written
/// `\u{1b}`, never raw (issue 57, item 12).
#[test]
fn a_task_files_name_is_escaped_in_messages() {
    let dir = scratch("escaped-name");
    let file = dir.join("task\u{1b}[2J.json");
    std::fs::write(&file, "{").unwrap();
    let output = codesign(&["check", "--task", file.to_str().unwrap()]);
    fails_saying(&output, "task\\u{1b}[2J.json: EOF while parsing");
    assert!(!output.stderr.contains(&0x1b), "{output:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task that chooses its motors from a catalogue: `check` lists each motor's part with its
/// mass and continuous torque and their mass in all, and shows the limits the parts set; a
/// field set against a part's value fails naming both.
#[test]
fn check_lists_the_motors_chosen_from_a_catalogue() {
    let task = "robots/tasks/pick_place_parts.json";
    let output = codesign(&["check", "--task", task]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for line in [
        "motor torque limits (2.33, 2.33, 1.48, 1.48) N m, speed limits (100, 100, 100, 100) rad/s, no-load speeds (121, 121, 144, 144) rad/s",
        "motor 1: Allied Motion HT02502-A00 (0.56 kg, continuous torque 0.636 N m) of catalogue robots/tasks/../catalogue/parts.json",
        "motor 4: Allied Motion HT02501-A00 (0.38 kg, continuous torque 0.442 N m)",
        "motor parts: 1.88 kg in all",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let json = codesign(&["check", "--task", task, "--json"]);
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["parts"][2]["name"], "Allied Motion HT02501-A00");
    assert_eq!(value["parts"][2]["mass_kg"], 0.38);
    let built_in = codesign(&["check", "--json"]);
    let value: serde_json::Value = serde_json::from_slice(&built_in.stdout).unwrap();
    assert!(value.get("parts").is_none());
    let dir = scratch("parts");
    let text = std::fs::read_to_string(support::root().join(task)).unwrap();
    let conflicting = text.replacen(
        "\"speed_limit_rad_s\": 100.0,",
        "\"speed_limit_rad_s\": 100.0, \"no_load_speed_rad_s\": 150,",
        1,
    );
    let path = dir.join("conflicting.json");
    std::fs::write(
        &path,
        conflicting
            .replace(
                "../catalogue",
                &support::root()
                    .join("robots/catalogue")
                    .display()
                    .to_string(),
            )
            .replace(
                "../belt_arm.urdf",
                &support::root()
                    .join("robots/belt_arm.urdf")
                    .display()
                    .to_string(),
            ),
    )
    .unwrap();
    fails_saying(
        &codesign(&["check", "--task", path.to_str().unwrap()]),
        "motors.no_load_speed_rad_s = 150 conflicts with motors.parts[0] ('Allied Motion HT02502-A00' of catalogue",
    );
}

/// A task whose links carry parts: `check` lists each with its mass at the design inspected
/// (the elbow pulley's grows with r2, `teeth_of` 2*r2: 0.428 kg of 288 teeth at the original
/// r2 = 12, 1.188 kg of 480 at r2 = 20), and a part on a link the robot does not have fails
/// naming it.
#[test]
fn check_lists_the_parts_the_links_carry() {
    let task = "robots/examples/planar_2dof/carried_pulley.json";
    let output = codesign(&["check", "--task", task]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for line in [
        "carried 1: pulley 'GT2 6 mm, aluminium pulleys' on upper_arm, 0.428 kg at this design",
        "carried 2: motor 'Allied Motion HT02501-A00' on upper_arm, 0.38 kg at this design",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let larger = codesign(&["check", "--task", task, "--ratios", "50,20", "--json"]);
    let value: serde_json::Value = serde_json::from_slice(&larger.stdout).unwrap();
    let mass = value["carried"][0]["mass_kg"].as_f64().unwrap();
    assert!((mass - 1.18809).abs() < 1e-5, "{mass}");
    let dir = scratch("carried");
    let text = std::fs::read_to_string(support::root().join(task)).unwrap();
    let elsewhere = text
        .replacen(
            "\"link\": \"upper_arm\",\n      \"at\": [0.3",
            "\"link\": \"nowhere\",\n      \"at\": [0.3",
            1,
        )
        .replace(
            "../../catalogue",
            &support::root()
                .join("robots/catalogue")
                .display()
                .to_string(),
        )
        .replace(
            "\"robot.urdf\"",
            &format!(
                "{:?}",
                support::root().join("robots/examples/planar_2dof/robot.urdf")
            ),
        );
    let path = dir.join("elsewhere.json");
    std::fs::write(&path, elsewhere).unwrap();
    let output = codesign(&["check", "--task", path.to_str().unwrap()]);
    fails_saying(
        &output,
        "carried[0].link = 'nowhere' is no link of the robot",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The paper's arm with its belt pulleys (`robots/tasks/pick_place_pulleys.json`, and with the
/// paper's ideal motors `pick_place_pulleys_ideal.json`): `check` weighs each pulley as a solid
/// GT2 disc, rho pi w R^2 with R = 12 r_l p / (2 pi), at two designs; the twin whose pulleys
/// are the test catalogue's massless series weighs them 0 and solves as the task without them
/// (`pick_place_parts.json`), bit for bit.
#[test]
fn the_arm_weighs_its_pulleys_and_its_massless_twin_solves_as_without_them() {
    let (rho, width, pitch) = (2700.0, 6e-3, 2e-3);
    // The ratio each carried pulley follows, in the task's order.
    let ratio_of = [0, 1, 2, 2, 3, 3];
    for task in ["pick_place_pulleys.json", "pick_place_pulleys_ideal.json"] {
        let task = format!("robots/tasks/{task}");
        for ratios in [[6.0, 3.0, 1.0, 1.0], [8.0, 7.5, 2.5, 1.5]] {
            let given = ratios.map(|r| r.to_string()).join(",");
            let output = codesign(&["check", "--task", &task, "--ratios", &given, "--json"]);
            let value: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
            let carried = value["carried"].as_array().unwrap();
            assert_eq!(carried.len(), ratio_of.len(), "{task}");
            for (part, &l) in carried.iter().zip(&ratio_of) {
                let radius = 12.0 * ratios[l] * pitch / (2.0 * std::f64::consts::PI);
                let expected = rho * std::f64::consts::PI * width * radius * radius;
                let mass = part["mass_kg"].as_f64().unwrap();
                assert!(
                    (mass - expected).abs() <= 1e-12 * expected,
                    "{task}: {part}"
                );
            }
        }
    }
    let dir = scratch("pulleys");
    let root = support::root();
    let text = std::fs::read_to_string(root.join("robots/tasks/pick_place_pulleys.json")).unwrap();
    let massless = format!(
        "{:?}, \"series\": \"GT2 6 mm, massless\"",
        root.join("tests/data/catalogue/ideal.json")
    );
    let twin = text
        .replace(
            "\"../catalogue/parts.json\", \"series\": \"GT2 6 mm, aluminium pulleys\"",
            &massless,
        )
        .replace(
            "\"../catalogue",
            &format!("\"{}", root.join("robots/catalogue").display()),
        )
        .replace(
            "\"../belt_arm.urdf\"",
            &format!("{:?}", root.join("robots/belt_arm.urdf")),
        );
    let twin_path = dir.join("twin.json");
    std::fs::write(&twin_path, twin).unwrap();
    let solve = |task: &str, out: &str| -> serde_json::Value {
        let out = dir.join(out);
        let args = ["solve", "--task", task, "--payload", "1", "--out"];
        let output = codesign(&[&args[..], &[out.to_str().unwrap()]].concat());
        assert!(output.status.success(), "{output:?}");
        serde_json::from_str(&std::fs::read_to_string(out).unwrap()).unwrap()
    };
    let found = solve(twin_path.to_str().unwrap(), "twin-result.json");
    let expected = solve("robots/tasks/pick_place_parts.json", "parts-result.json");
    assert!(found["carried"]
        .as_array()
        .unwrap()
        .iter()
        .all(|p| p["mass_kg"] == 0.0));
    for key in [
        "cost",
        "iterations",
        "cost_gradient",
        "cost_terms",
        "trajectory",
    ] {
        assert_eq!(found[key], expected[key], "{key}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
