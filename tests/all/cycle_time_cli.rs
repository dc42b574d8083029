//! The cycle-time co-design (issue 52, item 2), end to end: `optimize --objective time` with both
//! methods, and `tradeoff`, whose every point is the capacity `capacity --duration T` finds.

use crate::support;

use serde_json::{json, Value};
use support::{codesign, read_json, scratch, task_with};

/// Runs codesign in the repository's root, failing the test on an error; its stdout.
fn succeed(args: &[&str]) -> String {
    support::succeed_in(support::root(), args)
}

/// `optimize --objective time` on the repository's task (20 intervals, 0 kg, its fixed 0.8 s
/// freed to [0.24, 1.2] s): recorded as the objective's kind, the best and original costs are the
/// durations T* of their re-solved results, the best no longer than the original's, and the
/// summary speaks of T*. The gradient method, then a small CMA-ES run.
#[test]
fn the_time_objective_minimises_the_duration_with_both_methods() {
    let dir = scratch("cycle_time_optimize");
    let task = task_with(&dir, |task| task["motion"]["steps"] = json!(20));
    let task = task.to_str().unwrap();
    let methods: [&[&str]; 2] = [
        &["--method", "gradient", "--gradient-iterations", "2"],
        &["--population", "5", "--generations", "1", "--workers", "2"],
    ];
    for (i, method) in methods.into_iter().enumerate() {
        let out = dir.join(format!("time-{i}.json"));
        let args = [
            "optimize",
            "--objective",
            "time",
            "--payload",
            "0",
            "--task",
            task,
            "--out",
            out.to_str().unwrap(),
        ];
        let text = succeed(&[&args[..], method].concat());
        assert!(text.contains("with T* = ") && text.contains(" s (original design: T* = "));
        let document = read_json(&out);
        assert_eq!(document["inputs"]["objective"], json!({"kind": "time"}));
        let number = |value: &Value| value.as_f64().unwrap();
        let (best, original) = (&document["best_result"], &document["original_result"]);
        for result in [best, original] {
            let t_star = number(&result["horizon_s"]);
            assert_eq!(number(&result["cost"]), t_star, "J* = T*");
            assert!((0.24..=1.2).contains(&t_star), "{t_star}");
        }
        assert_eq!(
            number(&document["original_cost"]),
            number(&original["cost"])
        );
        let best_cost = number(&document["best_cost"]);
        assert!(
            best_cost <= number(&document["original_cost"]),
            "{document}"
        );
        assert!(
            (best_cost - number(&best["cost"])).abs() <= 1e-6 * best_cost,
            "{best_cost} vs {}",
            best["cost"]
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The capacity search's outcome without its timings, as `capacity --out` writes it at its top
/// level and a trade-off in each point.
fn untimed(document: &Value) -> Value {
    let mut search = json!({});
    for key in [
        "capacity_kg",
        "first_infeasible_kg",
        "hold_kg",
        "limited_by",
    ] {
        search[key] = document.get(key).cloned().unwrap_or(Value::Null);
    }
    let mut probes = document["probes"].as_array().unwrap().clone();
    for probe in &mut probes {
        probe.as_object_mut().unwrap().remove("seconds");
    }
    search["probes"] = Value::Array(probes);
    search
}

/// `tradeoff --durations` (the repository's task on 20 intervals) writes schema `codesign/tradeoff` version 1 with its plot beside it;
/// each point equals `capacity --duration T` run alone, and the capacity does not fall as T grows
/// here. A migration finds the file current; `--payload`, an empty list and a .svg result are
/// refused as usage.
#[test]
fn each_point_of_a_tradeoff_is_the_capacity_within_its_duration() {
    let dir = scratch("cycle_time_tradeoff");
    let task = task_with(&dir, |task| task["motion"]["steps"] = json!(20));
    let out = dir.join("tradeoff.json");
    let search = [
        "--resolution",
        "0.1",
        "--ratios",
        "8,5,2,2",
        "--task",
        task.to_str().unwrap(),
    ];
    let args = ["tradeoff", "--durations", "0.6,1"];
    let out_text = out.to_str().unwrap();
    succeed(&[&args[..], &search[..], &["--out", out_text]].concat());
    let document = read_json(&out);
    assert_eq!(document["schema"], "codesign/tradeoff");
    assert_eq!(document["version"], 1);
    assert_eq!(document["inputs"]["durations_s"], json!([0.6, 1.0]));
    assert_eq!(document["inputs"]["ratios"], json!([8.0, 5.0, 2.0, 2.0]));
    let svg = std::fs::read_to_string(dir.join("tradeoff.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("payload capacity"));
    let points = document["points"].as_array().unwrap();
    let mut capacities = Vec::new();
    for (point, duration) in points.iter().zip(["0.6", "1"]) {
        let alone = dir.join(format!("capacity-{duration}.json"));
        let args = ["capacity", "--duration", duration, "--out"];
        succeed(&[&args[..], &[alone.to_str().unwrap()], &search[..]].concat());
        let alone = read_json(&alone);
        assert_eq!(untimed(point), untimed(&alone), "at {duration} s");
        assert_eq!(point["duration_s"], alone["inputs"]["duration_s"]);
        capacities.push(point["capacity_kg"].as_f64().unwrap());
    }
    assert!(capacities[0] <= capacities[1], "{capacities:?}");
    let migrated = codesign(&["migrate", out_text]);
    let said = String::from_utf8_lossy(&migrated.stdout);
    assert!(said.contains("0 migrated, 1 current"), "{said}");
    for (bad, expected) in [
        (&["--durations", "0.6", "--payload", "1"][..], "--payload"),
        (&["--durations", "0.6", "--out", "x.svg"][..], "--out x.svg"),
        (&["--durations", "0"][..], "--durations: duration 0"),
    ] {
        let output = codesign(&[&["tradeoff"][..], bad].concat());
        support::refused_as_usage(&output, expected);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `tradeoff --payloads` (issue 52, item 5; the repository's task, the original design and one
/// compared): schema `codesign/time_curve` with its plot; each point's T* equals
/// `solve` of the task's pure minimum-time problem at that payload, written as a task file;
/// the original's T* does not fall as the payload grows; a payload it cannot move ends its curve.
/// Durations with payloads, payloads that do not increase and `--compare` alone are refused.
#[test]
fn each_point_of_a_time_curve_is_the_minimum_time_solve_at_its_payload() {
    let dir = scratch("cycle_time_curve");
    let task = task_with(&dir, |_| {});
    let fastest = dir.join("fastest.json");
    let mut pure = read_json(&task);
    pure["motion"]["horizon_s"] = json!({"free": [0.3 * 0.8, 1.5 * 0.8]});
    pure["weights"] = json!({"position": 0, "velocity": 0, "control": 0, "time": 1});
    pure["cartesian_box"] = json!({});
    std::fs::write(&fastest, pure.to_string()).unwrap();
    let out = dir.join("curve.json");
    let task = task.to_str().unwrap();
    let args = ["tradeoff", "--payloads", "0,1,2,6", "--task", task];
    let compare = ["--compare", "9,3,1,2", "--out", out.to_str().unwrap()];
    let text = succeed(&[&args[..], &compare[..]].concat());
    assert!(text.contains("least duration T* against payload"), "{text}");
    let document = read_json(&out);
    assert_eq!(document["schema"], "codesign/time_curve");
    assert_eq!(document["version"], 1);
    assert_eq!(
        document["inputs"]["payloads_kg"],
        json!([0.0, 1.0, 2.0, 6.0])
    );
    let svg = std::fs::read_to_string(dir.join("curve.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("r = (9.000, 3.000, 1.000, 2.000)"));
    let curves = document["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 2);
    assert_eq!(curves[0]["ratios"], json!([6.0, 3.0, 1.0, 1.0]));
    let original = curves[0]["points"].as_array().unwrap();
    assert_eq!(curves[0]["ends_at_kg"], json!(6.0), "{document}");
    assert_eq!(original.len(), 4);
    assert_eq!(original[3]["feasible"], json!(false));
    assert_eq!(original[3]["minimum_time_s"], Value::Null);
    let mut previous = 0.0;
    for point in &original[..3] {
        let kg = point["payload_kg"].as_f64().unwrap();
        let t_star = point["minimum_time_s"].as_f64().unwrap();
        assert!(
            t_star >= previous,
            "T* falls to {t_star} s at {kg} kg: {document}"
        );
        previous = t_star;
        let alone = dir.join(format!("solve-{kg}.json"));
        let payload = kg.to_string();
        let fastest = fastest.to_str().unwrap();
        let solve = ["solve", "--task", fastest, "--payload", &payload, "--out"];
        succeed(&[&solve[..], &[alone.to_str().unwrap()]].concat());
        let alone = read_json(&alone);
        assert_eq!(alone["feasible"], json!(true), "{kg} kg");
        assert_eq!(point["minimum_time_s"], alone["horizon_s"], "{kg} kg");
        assert_eq!(point["iterations"], alone["iterations"], "{kg} kg");
    }
    for (bad, expected) in [
        (
            &["--payloads", "0,1", "--durations", "0.6"][..],
            "--durations",
        ),
        (
            &["--payloads", "1,0.5"][..],
            "--payloads: payload 0.5 after 1",
        ),
        (&["--payloads", "0", "--max", "2"][..], "--max"),
        (
            &["--durations", "0.6", "--compare", "9,3,1,2"][..],
            "--compare",
        ),
    ] {
        let output = codesign(&[&["tradeoff"][..], bad].concat());
        support::refused_as_usage(&output, expected);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
