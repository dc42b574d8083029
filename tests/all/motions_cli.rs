//! Several motions per design (issue 52, item 4), end to end on the planar arm's three picks
//! (`robots/examples/planar_2dof/three_picks.json`): `solve` of each motion and of one,
//! `check` of each, the gradient co-design's result listing each motion, and the commands of one
//! motion refusing the task.

use crate::support;

use serde_json::Value;
use support::{fails_saying, refused_as_usage, scratch, succeed_with_out};

/// The example task file, relative to the repository's root (where the commands run).
const TASK: &str = "robots/examples/planar_2dof/three_picks.json";

/// The motions of the example with their weights, in order.
const MOTIONS: [(&str, f64); 3] = [("low", 2.0), ("middle", 1.0), ("high", 1.0)];

/// Each motion solved alone (`solve --motion NAME --out`): feasible, its cost; the `high`
/// motion's result records its own start, payload and duration.
fn each_motion_cost(dir: &std::path::Path) -> Vec<f64> {
    (MOTIONS.iter())
        .map(|(name, _)| {
            let out = dir.join(format!("{name}.json"));
            let args = [
                "solve",
                "--task",
                TASK,
                "--space",
                "actuation",
                "--motion",
                name,
            ];
            let (text, result) = succeed_with_out(&args, &out);
            assert_eq!(result["feasible"], true, "{name}: {text}");
            if *name == "high" {
                let task = &result["inputs"]["task"];
                assert_eq!(task["payload"]["mass_kg"], 0.2, "{task}");
                assert_eq!(task["motion"]["horizon_s"], 1.2, "{task}");
                assert_eq!(task["motion"]["start"][0], 1.3918, "{task}");
                assert!(task.get("motions").is_none(), "{task}");
            }
            result["cost"].as_f64().unwrap()
        })
        .collect()
}

/// `solve` of the whole task prints each motion and the weighted sum of their costs, which is
/// the sum of the single-motion solves; the gradient co-design lists each motion's J at the best
/// and original designs, the original's the same solves' to the bit, and lowers the sum.
#[test]
fn three_picks_are_solved_each_and_co_designed_as_one() {
    let dir = scratch("motions_cli");
    let costs = each_motion_cost(&dir);
    let expected: f64 = MOTIONS.iter().zip(&costs).map(|((_, w), j)| w * j).sum();
    let output = support::codesign(&["solve", "--task", TASK, "--space", "actuation"]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}");
    for (name, weight) in MOTIONS {
        assert!(
            text.contains(&format!("motion {name} (weight {weight}")),
            "{text}"
        );
    }
    let printed = text
        .split("3 motions: J = ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .and_then(|number| number.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        (printed - expected).abs() <= 1e-6,
        "{printed} vs {expected}"
    );

    let args = [
        "optimize",
        "--task",
        TASK,
        "--space",
        "actuation",
        "--method",
        "gradient",
        "--gradient-iterations",
        "3",
    ];
    let (text, document) = succeed_with_out(&args, &dir.join("optimize.json"));
    assert!(
        text.contains("the sum of the motions' (low (w 2): "),
        "{text}"
    );
    let listed = &document["motion_costs"];
    assert_eq!(listed["score"], "sum");
    let original = listed["original"].as_array().unwrap();
    for ((entry, (name, weight)), cost) in original.iter().zip(MOTIONS).zip(&costs) {
        assert_eq!(entry["name"], name);
        assert_eq!(entry["weight"], weight);
        assert_eq!(entry["feasible"], true);
        assert_eq!(entry["cost"].as_f64(), Some(*cost), "{entry}");
        assert_eq!(entry["result"]["cost"].as_f64(), Some(*cost));
    }
    let original_cost = document["original_cost"].as_f64().unwrap();
    assert!(
        (original_cost - expected).abs() <= 1e-9 * expected,
        "{original_cost}"
    );
    assert_eq!(document["best_result"], Value::Null);
    let best = listed["best"].as_array().unwrap();
    let best_sum: f64 = (best.iter().zip(MOTIONS))
        .map(|(entry, (_, weight))| weight * entry["cost"].as_f64().unwrap())
        .sum();
    let best_cost = document["best_cost"].as_f64().unwrap();
    assert!(best_cost < original_cost, "{best_cost} vs {original_cost}");
    assert!(
        (best_sum - best_cost).abs() <= 1e-6 * best_cost,
        "{best_sum} vs {best_cost}"
    );
}

/// The time objective over the three picks: each motion's least duration, their weighted sum
/// the cell's cycle time, printed as T* in s and shorter at the best design than at the original.
#[test]
fn three_picks_are_co_designed_for_the_cells_cycle_time() {
    let dir = scratch("motions-time");
    let args = [
        "optimize",
        "--task",
        TASK,
        "--space",
        "actuation",
        "--objective",
        "time",
        "--method",
        "gradient",
        "--gradient-iterations",
        "2",
    ];
    let (text, document) = succeed_with_out(&args, &dir.join("optimize.json"));
    assert!(
        text.contains("s, the sum of the motions' (low (w 2): ") && text.contains("with T* = "),
        "{text}"
    );
    let listed = &document["motion_costs"];
    let best = listed["best"].as_array().unwrap();
    let best_sum: f64 = (best.iter().zip(MOTIONS))
        .map(|(entry, (_, weight))| weight * entry["result"]["horizon_s"].as_f64().unwrap())
        .sum();
    let best_cost = document["best_cost"].as_f64().unwrap();
    assert!(
        (best_sum - best_cost).abs() <= 1e-6 * best_cost,
        "{best_sum} vs {best_cost}"
    );
    assert!(best_cost < document["original_cost"].as_f64().unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `check` inspects each motion; the flags and commands of one motion refuse the task, saying
/// why, and `--motion` names only a motion of the list.
#[test]
fn three_picks_are_checked_each_and_refused_where_one_motion_is_meant() {
    let dir = scratch("motions_cli_refusals");
    let output = support::codesign(&["check", "--task", TASK, "--json"]);
    assert!(output.status.success());
    let inspections: Value = serde_json::from_slice(&output.stdout).unwrap();
    let names: Vec<&str> = (inspections.as_array().unwrap().iter())
        .map(|each| each["motion"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["low", "middle", "high"]);
    assert_eq!(inspections[2]["payload_kg"], 0.2);
    let out = dir.join("out.json");
    let out = out.to_str().unwrap();
    let usage = support::codesign(&["solve", "--task", TASK, "--out", out]);
    refused_as_usage(&usage, "--out is of one motion, and the task lists 3");
    let unknown = support::codesign(&["solve", "--task", TASK, "--motion", "top"]);
    fails_saying(
        &unknown,
        "no motion of that name (its motions: low, middle, high)",
    );
    let single = support::codesign(&["solve", "--motion", "low"]);
    fails_saying(&single, "--motion low: the task has no `motions` list");
    let capacity = support::codesign(&["capacity", "--task", TASK]);
    fails_saying(
        &capacity,
        "a payload capacity is the heaviest payload of one motion",
    );
    let args = [
        "optimize",
        "--task",
        TASK,
        "--objective",
        "capacity",
        "--out",
        out,
    ];
    fails_saying(
        &support::codesign(&args),
        "--objective capacity: a payload capacity",
    );
    let args = ["reproduce", "--task", TASK, "--quick", "--plan"];
    fails_saying(
        &support::codesign(&args),
        "reproduce runs an experiment of one motion",
    );
}
