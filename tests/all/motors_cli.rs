//! Motors one by one, end to end: a task whose `motors.torque_limit_nm` and
//! `motors.speed_limit_rad_s` give one number per motor is solved, tabled and checked against
//! each motor's own limit; a task with a torque-speed envelope (`motors.no_load_speed_rad_s`)
//! keeps its motors inside it; lists and values that do not fit are named.

use crate::support;

use serde_json::{json, Value};
use std::path::Path;
use support::{codesign, fails_saying, read_json, scratch, task_with};

/// Runs codesign and returns its stdout, failing on a non-zero exit.
fn succeed(args: &[&str]) -> String {
    let output = codesign(args);
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Each motor's largest |value| over the rows of a trajectory's per-motor table.
fn peaks(rows: &Value) -> Vec<f64> {
    let mut largest = vec![0.0_f64; 4];
    for row in rows.as_array().unwrap() {
        for (peak, value) in largest.iter_mut().zip(row.as_array().unwrap()) {
            *peak = peak.max(value.as_f64().unwrap().abs());
        }
    }
    largest
}

/// The table's verdict on the original design of the solve result `result`.
fn motors_can_execute(dir: &Path, result: &Path) -> bool {
    let table = dir.join("table.md");
    succeed(&[
        "table",
        result.to_str().unwrap(),
        "--out",
        table.to_str().unwrap(),
    ]);
    let value = read_json(&dir.join("table.json"));
    value["rows"][0]["before"]["motors_can_execute"]
        .as_bool()
        .unwrap()
}

/// A joint-space solve with the exact torque limits: motor 3's own torque limit (1 N m, below
/// the others' 1.7) and motor 1's own speed limit (45 rad/s) bind; the result records the
/// lists as written, every motor stays within its own limits, and the table says the motors
/// can execute it although the largest motor torque is above motor 3's limit. Recorded with a
/// lower limit for motor 3, the same trajectory is one they cannot execute.
#[test]
fn a_limit_per_motor_binds_that_motor_in_solve_and_table() {
    let dir = scratch("solve");
    let torques = [1.7, 1.7, 1.0, 1.7];
    let speeds = [45.0, 100.0, 100.0, 100.0];
    let task = task_with(&dir, |task| {
        task["motors"] = json!({"torque_limit_nm": torques, "speed_limit_rad_s": speeds});
    });
    let out = dir.join("result.json");
    let stdout = succeed(&[
        "solve",
        "--task",
        task.to_str().unwrap(),
        "--space",
        "joint",
        "--torque-mode",
        "exact",
        "--payload",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(stdout.contains("(limits [1.7, 1.7, 1, 1.7])"), "{stdout}");
    assert!(stdout.contains("(limits [45, 100, 100, 100])"), "{stdout}");
    let result = read_json(&out);
    assert_eq!(result["feasible"], true);
    assert_eq!(
        result["inputs"]["task"]["motors"],
        json!({"torque_limit_nm": torques, "speed_limit_rad_s": speeds})
    );
    let torque_peaks = peaks(&result["trajectory"]["motor_torque"]);
    let speed_peaks = peaks(&result["trajectory"]["motor_speed"]);
    for motor in 0..4 {
        assert!(
            torque_peaks[motor] <= torques[motor] * (1.0 + 1e-6),
            "{torque_peaks:?}"
        );
        assert!(
            speed_peaks[motor] <= speeds[motor] * (1.0 + 1e-6),
            "{speed_peaks:?}"
        );
    }
    assert!(
        torque_peaks[2] > 0.99,
        "motor 3's limit binds: {torque_peaks:?}"
    );
    assert!(
        speed_peaks[0] > 44.9,
        "motor 1's limit binds: {speed_peaks:?}"
    );
    assert!(result["max_motor_torque"].as_f64().unwrap() > 1.5);
    assert!(motors_can_execute(&dir, &out));
    let mut recorded = result.clone();
    recorded["inputs"]["task"]["motors"]["torque_limit_nm"] = json!([1.7, 1.7, 0.9, 1.7]);
    let edited = dir.join("edited.json");
    std::fs::write(&edited, recorded.to_string()).unwrap();
    assert!(!motors_can_execute(&dir, &edited));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `check` holds the static torques to each motor's own limit and shows the limits.
#[test]
fn check_holds_each_motor_to_its_own_limit() {
    let dir = scratch("check");
    let task = task_with(&dir, |task| {
        task["motors"]["torque_limit_nm"] = json!([1.7, 1.2, 1.7, 1.7]);
    });
    let text = succeed(&["check", "--task", task.to_str().unwrap()]);
    for line in [
        "motor torque limits (1.7, 1.2, 1.7, 1.7) N m, speed limits (100, 100, 100, 100) rad/s\n",
        "ok   hold at start: motor torques (",
        ") N m within the motors' limits (1.7, 1.2, 1.7, 1.7) N m",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let task = task_with(&dir, |task| {
        task["motors"]["torque_limit_nm"] = json!([1.7, 0.5, 1.7, 1.7]);
    });
    let output = codesign(&["check", "--task", task.to_str().unwrap(), "--ends", "hold"]);
    fails_saying(
        &output,
        "hold at start: motor 2 needs 0.8921 N m (limit 0.5)",
    );
    let json = codesign(&["check", "--task", task.to_str().unwrap(), "--json"]);
    let value: Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["torque_limits_nm"], json!([1.7, 0.5, 1.7, 1.7]));
    let built_in: Value = serde_json::from_slice(&codesign(&["check", "--json"]).stdout).unwrap();
    assert_eq!(built_in["torque_limits_nm"], json!([1.7, 1.7, 1.7, 1.7]));
    assert!(built_in.get("no_load_speeds_rad_s").is_none());
    assert!(!text.contains("torque-speed envelope"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `check` shows a torque-speed envelope's no-load speeds and the share of its torque each motor
/// keeps at its speed limit, and fails on a motor with no torque left before that limit.
#[test]
fn check_shows_what_the_envelope_leaves_at_the_speed_limit() {
    let dir = scratch("check-envelope");
    let task = task_with(&dir, |task| {
        task["motors"]["no_load_speed_rad_s"] = json!([149, 149, 200, 400]);
    });
    let text = succeed(&["check", "--task", task.to_str().unwrap()]);
    for line in [
        "speed limits (100, 100, 100, 100) rad/s, no-load speeds (149, 149, 200, 400) rad/s\n",
        "ok   torque-speed envelope: at its speed limit each motor keeps (33%, 33%, 50%, 75%) \
         of its torque limit",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let json = codesign(&["check", "--task", task.to_str().unwrap(), "--json"]);
    let value: Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(
        value["no_load_speeds_rad_s"],
        json!([149.0, 149.0, 200.0, 400.0])
    );
    let task = task_with(&dir, |task| {
        task["motors"]["no_load_speed_rad_s"] = json!([149, 100, 149, 149]);
    });
    let output = codesign(&["check", "--task", task.to_str().unwrap()]);
    fails_saying(
        &output,
        "torque-speed envelope: motor 2's no-load speed 100 rad/s is not above its speed limit \
         100 rad/s: it has no torque left before that limit",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A list of another length than G has rows, a value that is not > 0 or beyond its limit, and
/// a value that is neither a number nor a list are errors naming the field.
#[test]
fn lists_that_do_not_fit_are_named() {
    let dir = scratch("bad");
    let cases = [
        (
            json!({"torque_limit_nm": [1.7, 1.7, 1.7], "speed_limit_rad_s": 100}),
            "motors.torque_limit_nm has 3 values but transmission.matrix has 4 rows",
        ),
        (
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": [100, 100, -5, 100]}),
            "motors.speed_limit_rad_s[2] = -5 must be > 0",
        ),
        (
            json!({"torque_limit_nm": "1.7", "speed_limit_rad_s": 100}),
            "expected a number (every motor) or an array with one number per motor",
        ),
        (
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100, "no_load_speed_rad_s": 0}),
            "motors.no_load_speed_rad_s = 0 must be > 0",
        ),
        (
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100, "no_load_speed_rad_s": [150, 150]}),
            "motors.no_load_speed_rad_s has 2 values but transmission.matrix has 4 rows",
        ),
        // Values that overflowed the dynamics into null results (probe D2), and a subnormal one.
        (
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100, "rotor_inertia_kgm2": 1e308}),
            "motors.rotor_inertia_kgm2 = 1e308 must be >= 0 and <= 1 kg m^2",
        ),
        (
            json!({"torque_limit_nm": 1e308, "speed_limit_rad_s": 100}),
            "motors.torque_limit_nm = 1e308 must be > 0 and <= 1000000 N m",
        ),
        (
            json!({"torque_limit_nm": 1.7, "speed_limit_rad_s": 100, "no_load_speed_rad_s": 1e-320}),
            "motors.no_load_speed_rad_s = 1e-320 must be at least 0.001 rad/s",
        ),
    ];
    for (motors, expected) in cases {
        let task = task_with(&dir, |task| task["motors"] = motors.clone());
        let task = task.to_str().unwrap();
        for command in ["solve", "check"] {
            fails_saying(&codesign(&[command, "--task", task]), expected);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Motor i's margin inside its envelope, tau_max (1 - |w|/w_0) - |tau|, N m.
fn envelope_margin(torque: f64, speed: f64, no_load: f64) -> f64 {
    1.7 * (1.0 - speed.abs() / no_load) - torque.abs()
}

/// A task with `motors.no_load_speed_rad_s`: the solve keeps every motor inside its envelope
/// at the inner nodes and reaches it at speed, costs more than without it, records the key
/// (so its task hash differs from the built-in task's) and reports the envelope's violation;
/// the summary says where it is reached, and `--plot` draws the torque-speed plane only where
/// there is an envelope. At a no-load speed the motion cannot keep, the elastic solve names the
/// envelope and reports its violation.
#[test]
fn the_torque_speed_envelope_bounds_the_motors_at_speed() {
    let dir = scratch("envelope");
    let no_load = 120.0;
    let task = task_with(&dir, |task| {
        task["motors"]["no_load_speed_rad_s"] = json!(no_load);
    });
    let (out, plain) = (dir.join("envelope.json"), dir.join("plain.json"));
    let solve = |task: &str, out: &Path, extra: &[&str]| {
        let mut args = vec![
            "solve",
            "--task",
            task,
            "--space",
            "actuation",
            "--payload",
            "0.5",
            "--out",
        ];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        succeed(&args)
    };
    let plots = [dir.join("envelope-plots"), dir.join("plain-plots")];
    let plot = |i: usize| ["--plot", plots[i].to_str().unwrap()];
    let stdout = solve(task.to_str().unwrap(), &out, &plot(0));
    assert!(
        stdout.contains("torque-speed envelope (no-load speed 120 rad/s): reached"),
        "{stdout}"
    );
    solve(support::task_path().to_str().unwrap(), &plain, &plot(1));
    // Each motor its own torque-speed figure, envelope or not; the envelope's diamond only with
    // one.
    let figure = |i: usize| std::fs::read_to_string(plots[i].join("motor_2_torque_speed.svg"));
    let (enveloped, plain_figure) = (figure(0).unwrap(), figure(1).unwrap());
    assert!(enveloped.contains("torque-speed envelope (no-load speed 120"));
    assert!(!plain_figure.contains("torque-speed envelope"));
    assert!(plain_figure.contains("speed limit -+100 rad/s"));
    let (result, ideal) = (read_json(&out), read_json(&plain));
    assert_eq!(result["feasible"], true);
    assert_eq!(
        result["inputs"]["task"]["motors"]["no_load_speed_rad_s"],
        120.0
    );
    assert!(ideal["inputs"]["task"]["motors"]
        .get("no_load_speed_rad_s")
        .is_none());
    assert_ne!(result["inputs"]["task_hash"], ideal["inputs"]["task_hash"]);
    assert!(ideal["violations"].get("motor_envelope").is_none());
    assert!(result["violations"]["motor_envelope"].as_f64().unwrap() <= 1e-6);
    assert!(result["cost"].as_f64().unwrap() > ideal["cost"].as_f64().unwrap());
    let t = &result["trajectory"];
    let (torques, speeds) = (
        t["motor_torque"].as_array().unwrap(),
        t["motor_speed"].as_array().unwrap(),
    );
    let mut reached_at_speed = false;
    for k in 1..torques.len() {
        for motor in 0..4 {
            let (torque, speed) = (
                torques[k][motor].as_f64().unwrap(),
                speeds[k][motor].as_f64().unwrap(),
            );
            let margin = envelope_margin(torque, speed, no_load);
            assert!(margin >= -1e-6, "node {k} motor {motor}: {margin}");
            reached_at_speed |= margin < 1e-6 && speed.abs() > 10.0;
        }
    }
    assert!(reached_at_speed, "the envelope is never reached at speed");
    let slow = task_with(&dir, |task| {
        task["motors"]["no_load_speed_rad_s"] = json!([40, 100, 100, 100]);
    });
    let elastic = dir.join("elastic.json");
    let stdout = solve(slow.to_str().unwrap(), &elastic, &["--elastic"]);
    assert!(stdout.contains("EXCEEDED by"), "{stdout}");
    let result = read_json(&elastic);
    assert_eq!(result["feasible"], false);
    assert!(result["reason"]
        .as_str()
        .unwrap()
        .contains("the speed limit or the torque-speed envelope"));
    assert!(result["violations"]["motor_envelope"].as_f64().unwrap() > 0.01);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task with the motors' torque constants and resistances: every result reports their
/// currents, copper losses and electrical energy, consistent with its mechanical figures
/// (copper losses R / k_t^2 times the torque-squared integral; net energy the work plus them),
/// and the task hash of a task without them is unchanged. One without the other is named.
#[test]
fn electrical_figures_follow_the_motors_constants() {
    let dir = scratch("electrical");
    let (k_t, r) = ([0.05, 0.05, 0.03, 0.03], 1.2);
    let task = task_with(&dir, |task| {
        task["motors"]["torque_constant_nm_per_a"] = json!(k_t);
        task["motors"]["resistance_ohm"] = json!(r);
    });
    let out = dir.join("solve.json");
    let args = [
        "solve",
        "--task",
        task.to_str().unwrap(),
        "--space",
        "actuation",
    ];
    succeed(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    let figures = read_json(&out)["figures"].clone();
    let mut copper_total = 0.0;
    for (i, motor) in figures["motors"].as_array().unwrap().iter().enumerate() {
        let e = &motor["electrical"];
        let number = |value: &Value| value.as_f64().unwrap();
        let copper = r / (k_t[i] * k_t[i]) * number(&motor["torque_squared_integral"]);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
        assert!(close(number(&e["copper_loss_j"]), copper), "motor {i}: {e}");
        let net = number(&motor["work_j"]) + number(&e["copper_loss_j"]);
        assert!(close(number(&e["energy_j"]), net), "motor {i}: {e}");
        assert!(number(&e["drawn_energy_j"]) >= number(&e["energy_j"]) - 1e-12);
        assert!(
            number(&e["peak_current_a"]) * k_t[i]
                >= number(&motor["peak_torque_nm"]) * (1.0 - 1e-12)
        );
        copper_total += number(&e["copper_loss_j"]);
    }
    let total = figures["electrical"]["copper_loss_j"].as_f64().unwrap();
    assert!((total - copper_total).abs() <= 1e-9 * copper_total);
    // Without the constants, no electrical figures.
    let plain = task_with(&dir, |_| {});
    let plain_out = dir.join("plain.json");
    let plain_args = [
        "solve",
        "--task",
        plain.to_str().unwrap(),
        "--space",
        "actuation",
    ];
    succeed(&[&plain_args[..], &["--out", plain_out.to_str().unwrap()]].concat());
    let plain_doc = read_json(&plain_out);
    assert!(plain_doc["figures"]["motors"][0]
        .get("electrical")
        .is_none());
    assert!(plain_doc["figures"].get("electrical").is_none());
    assert!(plain_doc["figures"]["motors"][0]["work_j"].is_number());
    // One constant without the other is refused, naming the missing field.
    let half = task_with(&dir, |task| {
        task["motors"]["torque_constant_nm_per_a"] = json!(0.05);
    });
    fails_saying(
        &codesign(&["solve", "--task", half.to_str().unwrap()]),
        "motors.resistance_ohm is missing",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task with transmission efficiencies: the result records each motor's loss torque per
/// interval and the energy lost in the transmissions, per motor and in total; a task without
/// them records none. An efficiency outside (0, 1], or a list of the wrong length, is refused
/// naming the field.
#[test]
fn transmission_losses_are_reported_and_bad_efficiencies_named() {
    let dir = scratch("efficiency");
    let task = task_with(&dir, |task| {
        task["motors"]["efficiency"] = json!([0.95, 0.95, 0.9, 0.9]);
    });
    let out = dir.join("solve.json");
    let args = [
        "solve",
        "--task",
        task.to_str().unwrap(),
        "--space",
        "actuation",
    ];
    succeed(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    let result = read_json(&out);
    assert_eq!(
        result["inputs"]["task"]["motors"]["efficiency"],
        json!([0.95, 0.95, 0.9, 0.9])
    );
    let losses = result["trajectory"]["transmission_loss"]
        .as_array()
        .unwrap();
    assert_eq!(
        losses.len(),
        result["trajectory"]["motor_torque"]
            .as_array()
            .unwrap()
            .len()
    );
    let figures = &result["figures"];
    let per_motor: f64 = (figures["motors"].as_array().unwrap().iter())
        .map(|motor| motor["transmission_loss_j"].as_f64().unwrap())
        .sum();
    let total = figures["transmission_loss_j"].as_f64().unwrap();
    assert!(
        total > 0.0 && (total - per_motor).abs() <= 1e-12 * total,
        "{figures}"
    );
    let plain = task_with(&dir, |_| {});
    let plain_out = dir.join("plain.json");
    let plain_args = [
        "solve",
        "--task",
        plain.to_str().unwrap(),
        "--space",
        "actuation",
    ];
    succeed(&[&plain_args[..], &["--out", plain_out.to_str().unwrap()]].concat());
    let plain = read_json(&plain_out);
    assert!(plain["trajectory"].get("transmission_loss").is_none());
    assert!(plain["figures"].get("transmission_loss_j").is_none());
    for (value, expected) in [
        (json!(1.5), "motors.efficiency = 1.5 must be > 0 and <= 1"),
        (json!([0.9, 0.9, 0]), "motors.efficiency has 3 values"),
        (
            json!([0.9, 0.9, 0.9, 0]),
            "motors.efficiency[3] = 0 must be > 0",
        ),
    ] {
        let bad = task_with(&dir, |task| task["motors"]["efficiency"] = value.clone());
        fails_saying(
            &codesign(&["solve", "--task", bad.to_str().unwrap()]),
            expected,
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `optimize --objective energy`: the gradient method on the motors' copper losses, recorded
/// as the objective's kind; the best design's cost is its copper losses (as its figures compute
/// them) plus the soft box's penalty. Refused in the joint space and without the
/// motors' constants, each error naming what to give.
#[test]
fn the_energy_objective_minimises_the_copper_losses() {
    let dir = scratch("energy");
    let task = task_with(&dir, |task| {
        task["motion"]["steps"] = json!(20);
        task["motors"]["torque_constant_nm_per_a"] = json!(0.1);
        task["motors"]["resistance_ohm"] = json!([1.2, 1.2, 2.0, 2.0]);
    });
    let out = dir.join("energy.json");
    let task_arg = task.to_str().unwrap();
    let args = [
        "optimize",
        "--method",
        "gradient",
        "--objective",
        "energy",
        "--task",
        task_arg,
    ];
    let run = [
        &args[..],
        &["--gradient-iterations", "3", "--out", out.to_str().unwrap()],
    ];
    succeed(&run.concat());
    let document = read_json(&out);
    assert_eq!(document["inputs"]["objective"], json!({"kind": "energy"}));
    let best = &document["best_result"];
    let number = |value: &Value| value.as_f64().unwrap();
    let copper = number(&best["figures"]["electrical"]["copper_loss_j"]);
    let terms = &best["cost_terms"];
    assert!(
        (number(&terms["control"]) - copper).abs() <= 1e-9 * copper,
        "{terms}"
    );
    // The best design solved again from the standard guess: its cost, its figures.
    let cost = number(&best["cost"]);
    let sum = copper + number(&terms["cartesian_box"]);
    assert!((cost - sum).abs() <= 1e-7 * cost, "{cost} vs {sum}");
    let joint = [
        &args[..],
        &["--space", "joint", "--out", out.to_str().unwrap()],
    ]
    .concat();
    fails_saying(
        &codesign(&[&joint[..], &["--overwrite"]].concat()),
        "--space actuation",
    );
    let plain = task_with(&dir, |_| {});
    let bare = [
        "optimize",
        "--method",
        "gradient",
        "--objective",
        "energy",
        "--task",
    ];
    fails_saying(
        &codesign(&[&bare[..], &[plain.to_str().unwrap()]].concat()),
        "motors.torque_constant_nm_per_a and motors.resistance_ohm",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
