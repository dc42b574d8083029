//! Issue 54, item 4: a co-design run says where its solver time went. Its summary line and its
//! result give the total solver time beside the median solve, the shares of invalid and
//! infeasible designs and the IPOPT iterations of each kind of verdict, counted from the
//! evaluation log (a resumed run's replayed evaluations as the log holds them); nothing of the
//! terminal's progress line reaches a pipe.

use crate::support;

use serde_json::Value;
use std::path::Path;
use support::{codesign, read_json, scratch, task_with};

/// One kind of verdict counted from a log: designs, iterations, seconds.
#[derive(Default)]
struct Count {
    designs: u64,
    iterations: u64,
    seconds: f64,
}

/// The log's evaluations counted by kind of verdict, by status and feasibility as the log
/// writes them: feasible, infeasible, invalid, not judged.
fn recount(out: &Path) -> [Count; 4] {
    let text = std::fs::read_to_string(out.with_extension("log.jsonl")).unwrap();
    let mut counts: [Count; 4] = Default::default();
    for line in text.lines().skip(1) {
        let entry: Value = serde_json::from_str(line).unwrap();
        let status = entry["status"].as_str().unwrap();
        let kind = match status {
            _ if entry["feasible"] == true => 0,
            "Invalid_Design" => 2,
            "Solver_Error" | "Worker_Failed" => 3,
            _ => 1,
        };
        counts[kind].designs += 1;
        counts[kind].iterations += entry["iterations"].as_u64().unwrap();
        counts[kind].seconds += entry["seconds"].as_f64().unwrap();
    }
    counts
}

/// Checks that the result's `verdicts` are the log's, kind by kind.
fn verdicts_are_the_logs(result: &Value, out: &Path) {
    let verdicts = &result["verdicts"];
    let kinds = ["feasible", "infeasible", "invalid", "unjudged"];
    for (kind, count) in kinds.iter().zip(recount(out)) {
        let written = &verdicts[kind];
        assert_eq!(written["designs"], count.designs, "{kind}: {verdicts}");
        assert_eq!(
            written["iterations"], count.iterations,
            "{kind}: {verdicts}"
        );
        let seconds = written["seconds"].as_f64().unwrap();
        assert!((seconds - count.seconds).abs() < 1e-9, "{kind}: {verdicts}");
    }
}

fn number(value: &Value) -> f64 {
    value.as_f64().unwrap()
}

#[test]
fn a_runs_summary_and_result_count_its_verdicts_and_their_iterations() {
    let dir = scratch("verdicts");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 10.into());
    let out = dir.join("run.json");
    let args = [
        "optimize",
        "--task",
        task.to_str().unwrap(),
        "--space",
        "actuation",
        "--payload",
        "3",
        "--population",
        "8",
        "--generations",
        "1",
        "--workers",
        "2",
        "--out",
        out.to_str().unwrap(),
    ];
    let output = codesign(&args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    // stderr is a pipe here: no progress line is drawn on it.
    assert!(
        !stderr.contains('\r') && !stderr.contains("elapsed"),
        "{stderr}"
    );
    let text = String::from_utf8_lossy(&output.stdout);
    let result = read_json(&out);
    verdicts_are_the_logs(&result, &out);
    let verdicts = &result["verdicts"];
    let designs = |kind: &str| verdicts[kind]["designs"].as_u64().unwrap();
    let kinds = ["feasible", "infeasible", "invalid", "unjudged"];
    assert_eq!(kinds.map(designs).iter().sum::<u64>(), 16, "{verdicts}");
    assert_eq!(verdicts["invalid"]["iterations"], 0);
    // The paper's rule at 3 kg: most of a uniform population breaks an order constraint.
    assert!(designs("invalid") > 0, "{verdicts}");
    let feasible: u64 = (result["generations"].as_array().unwrap().iter())
        .map(|generation| generation["feasible"].as_u64().unwrap())
        .sum();
    assert_eq!(designs("feasible"), feasible);
    // The total solver time is the solves' of every kind.
    let seconds = |kind: &str| number(&verdicts[kind]["seconds"]);
    let total = number(&result["solve_seconds_total"]);
    assert!((kinds.map(seconds).iter().sum::<f64>() - total).abs() < 1e-9);

    // The summary line says the same.
    let percent = |kind: &str| 100.0 * designs(kind) as f64 / 16.0;
    let spent = |kind: &str| {
        let iterations = &verdicts[kind]["iterations"];
        format!("{iterations} ({:.1} s)", seconds(kind))
    };
    let expected = format!(
        "16 evaluations (0 replayed), median solve {:.1} ms, total solver time {total:.1} s; \
         invalid {} of 16 ({:.1}%), infeasible {} ({:.1}%); IPOPT iterations: feasible {}, \
         infeasible {}, invalid 0; ",
        number(&result["median_solve_seconds"]) * 1e3,
        designs("invalid"),
        percent("invalid"),
        designs("infeasible"),
        percent("infeasible"),
        spent("feasible"),
        spent("infeasible"),
    );
    assert!(text.contains(&expected), "{text}\nnot found: {expected}");

    // Interrupted after 5 evaluations and resumed: the 5 replayed ones count as the log holds
    // them, and the run's verdicts are the uninterrupted run's.
    let log = out.with_extension("log.jsonl");
    let lines: Vec<String> = (std::fs::read_to_string(&log).unwrap().lines())
        .take(6)
        .map(|line| format!("{line}\n"))
        .collect();
    std::fs::write(&log, lines.concat()).unwrap();
    std::fs::remove_file(&out).unwrap();
    let mut resumed = args.to_vec();
    resumed.push("--resume");
    let output = codesign(&resumed);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let again = read_json(&out);
    assert_eq!(again["replayed"], 5);
    verdicts_are_the_logs(&again, &out);
    for kind in kinds {
        for key in ["designs", "iterations"] {
            assert_eq!(
                again["verdicts"][kind][key], verdicts[kind][key],
                "{kind} {key}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The gradient method counts its solves too: every one valid (its steps are projected onto the
/// design space), each feasible or infeasible.
#[test]
fn the_gradient_method_counts_its_verdicts() {
    let dir = scratch("gradient-verdicts");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let out = dir.join("gradient.json");
    let args = [
        "optimize",
        "--task",
        task.to_str().unwrap(),
        "--method",
        "gradient",
        "--space",
        "actuation",
        "--payload",
        "1",
        "--gradient-iterations",
        "2",
        "--out",
        out.to_str().unwrap(),
    ];
    let output = codesign(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let result = read_json(&out);
    let verdicts = &result["verdicts"];
    let designs = |kind: &str| verdicts[kind]["designs"].as_u64().unwrap();
    assert_eq!(designs("invalid"), 0, "{verdicts}");
    assert!(designs("feasible") > 0, "{verdicts}");
    assert_eq!(
        designs("feasible") + designs("infeasible") + designs("unjudged"),
        result["evaluations"].as_u64().unwrap()
    );
    let iterations = |kind: &str| verdicts[kind]["iterations"].as_u64().unwrap();
    assert!(iterations("feasible") > 0, "{verdicts}");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("total solver time"), "{text}");
    assert!(text.contains("; invalid 0 of "), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}
