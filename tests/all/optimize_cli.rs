//! Co-design end to end through the worker processes: a killed worker, an interrupted run and
//! the number of workers change nothing in the result.

use crate::support;

use serde_json::Value;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use support::{codesign_command, read_json, scratch};

/// Starts the tiny co-design with `workers` worker processes and an optional `--resume` or
/// `--overwrite`.
fn start(out: &Path, flag: Option<&str>, workers: usize) -> Child {
    let mut command = codesign_command(support::root(), &[]);
    command
        .args([
            "optimize",
            "--space",
            "actuation",
            "--payload",
            "1",
            "--seed",
            "3",
        ])
        .args(["--population", "8", "--generations", "3", "--workers"])
        .arg(workers.to_string())
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    command.args(flag);
    command.spawn().expect("codesign starts")
}

fn finish(child: Child) {
    let output = child.wait_with_output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

fn log_entries(out: &Path) -> usize {
    std::fs::read_to_string(out.with_extension("log.jsonl"))
        .map_or(0, |text| text.lines().count().saturating_sub(1))
}

/// Waits until the run's log holds at least `count` evaluations.
fn wait_for_entries(out: &Path, count: usize) {
    let start = Instant::now();
    while log_entries(out) < count {
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "the run did not progress"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Process ids whose parent is `parent` (from /proc).
fn children(parent: u32) -> Vec<u32> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // Fields after the command name, which is in parentheses: state, ppid, ...
        let after = &stat[stat.rfind(')').unwrap() + 2..];
        if after
            .split_whitespace()
            .nth(1)
            .and_then(|p| p.parse::<u32>().ok())
            == Some(parent)
        {
            found.push(pid);
        }
    }
    found
}

fn same_result(a: &Value, b: &Value) {
    assert_eq!(a["best_ratios"], b["best_ratios"]);
    assert_eq!(a["best_cost"], b["best_cost"]);
    assert_eq!(a["costs"], b["costs"]);
    assert_eq!(a["generations"], b["generations"]);
}

#[test]
fn a_killed_worker_an_interrupted_run_and_the_worker_count_change_nothing() {
    let dir = scratch("runs");
    let plain = dir.join("plain.json");
    finish(start(&plain, None, 2));
    let reference = read_json(&plain);
    assert_eq!(reference["evaluations"], 32);
    assert_eq!(log_entries(&plain), 32);
    assert_eq!(reference["earlier_seconds"], 0.0);

    // Kill one of three workers mid-run: its design is retried on a fresh worker.
    let killed = dir.join("killed.json");
    let child = start(&killed, None, 3);
    wait_for_entries(&killed, 5);
    let workers = children(child.id());
    assert!(!workers.is_empty(), "no worker processes found");
    Command::new("kill")
        .arg("-9")
        .arg(workers[0].to_string())
        .status()
        .unwrap();
    finish(child);
    same_result(&reference, &read_json(&killed));

    // Interrupt the whole run, then resume it with one worker: nothing finished is solved again.
    let resumed = dir.join("resumed.json");
    let mut child = start(&resumed, None, 2);
    wait_for_entries(&resumed, 12);
    child.kill().unwrap();
    child.wait().unwrap();
    let before = log_entries(&resumed);
    assert!((12..32).contains(&before), "{before}");
    assert!(!resumed.exists());
    finish(start(&resumed, Some("--resume"), 1));
    let result = read_json(&resumed);
    same_result(&reference, &result);
    assert_eq!(result["replayed"].as_u64().unwrap() as usize, before);
    // The interrupted invocation's working time is carried over from the log.
    assert!(result["earlier_seconds"].as_f64().unwrap() > 0.0);
    assert_eq!(log_entries(&resumed), 32);

    // A finished run's log is never overwritten unasked; --overwrite starts it afresh.
    let again = start(&plain, None, 2).wait_with_output().unwrap();
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--resume"));
    finish(start(&plain, Some("--overwrite"), 2));
    let fresh = read_json(&plain);
    same_result(&reference, &fresh);
    assert_eq!(fresh["replayed"], 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

fn run_to_completion(args: &[&str], out: &Path) -> Value {
    let output = codesign_command(support::root(), args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    read_json(out)
}

/// The capacity objective in a small CMA-ES run on two workers (the built-in task at 8 steps).
#[test]
fn the_capacity_objective_runs_end_to_end() {
    let dir = scratch("capacity-objective");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let capacity = run_to_completion(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--objective",
            "capacity",
            "--space",
            "actuation",
            "--population",
            "5",
            "--generations",
            "1",
            "--workers",
            "2",
            "--capacity-resolution",
            "0.25",
        ],
        &dir.join("capacity.json"),
    );
    assert_eq!(capacity["inputs"]["objective"]["kind"], "capacity");
    assert_eq!(capacity["evaluations"], 10);
    // Fitness is minus the capacity: some design of the first 10 carries a payload.
    assert!(
        capacity["best_cost"].as_f64().unwrap() < 0.0,
        "{}",
        capacity["best_cost"]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The gradient method for three iterations (the built-in task at 8 steps): it lowers the
/// original design's cost and keeps no evaluation log; on worker processes (a worker command),
/// which carry each solve's warm start and merit, it makes the same solves to the bit.
#[test]
fn the_gradient_method_runs_end_to_end() {
    let dir = scratch("gradient-method");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let run = |name: &str, extra: &[&str]| {
        let mut args = vec![
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
            "3",
        ];
        args.extend(extra);
        run_to_completion(&args, &dir.join(name))
    };
    let gradient = run("gradient.json", &[]);
    assert_eq!(gradient["inputs"]["method"], "gradient");
    let best = gradient["best_cost"].as_f64().unwrap();
    assert!(best < gradient["original_cost"].as_f64().unwrap(), "{best}");
    assert!(!gradient["iterates"].as_array().unwrap().is_empty());
    assert!(!dir.join("gradient.log.jsonl").exists());
    let workers = ["--workers", "2", "--worker-command", "{} worker"];
    let pooled = run("pooled.json", &workers);
    for key in [
        "costs",
        "iterates",
        "best_ratios",
        "best_cost",
        "stop_reason",
    ] {
        assert_eq!(pooled[key], gradient[key], "{key}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn one_design_for_a_payload_range_reports_its_cost_at_each_payload() {
    let dir = scratch("range");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let out = dir.join("range.json");
    let range = run_to_completion(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--objective",
            "range",
            // Payloads the sampled designs hold at rest (the original one holds 0.585 kg).
            "--payloads",
            "0,0.5",
            "--population",
            "6",
            "--generations",
            "1",
            "--workers",
            "2",
        ],
        &out,
    );
    assert_eq!(range["inputs"]["objective"]["kind"], "range");
    assert_eq!(range["evaluations"], 12);
    let best = &range["payload_costs"]["best"];
    assert_eq!(best.as_array().unwrap().len(), 2, "{best}");
    // The fitness is the mean of the costs at the payloads, solved again for the report.
    let mean = (best[0]["cost"].as_f64().unwrap() + best[1]["cost"].as_f64().unwrap()) / 2.0;
    assert!(best[0]["feasible"].as_bool().unwrap() && best[1]["feasible"].as_bool().unwrap());
    assert_eq!(range["best_cost"].as_f64().unwrap(), mean);
    // The table shows it beyond the paper.
    let table = support::codesign(&["table", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(table.status.success(), "{text}");
    assert!(text.contains("One design for a payload range"), "{text}");
    assert!(text.contains("| 0, 0.5 kg | actuation | 0 |"), "{text}");

    let refused = support::codesign(&[
        "optimize",
        "--objective",
        "range",
        "--payloads",
        "1,2",
        "--payload",
        "1",
    ]);
    support::refused_as_usage(
        &refused,
        "--payload 1: the range objective solves every payload",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_graded_penalty_ranks_infeasible_designs_by_their_shortfall() {
    let dir = scratch("graded");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let graded = run_to_completion(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--payload",
            "3",
            "--penalty",
            "graded",
            "--population",
            "8",
            "--generations",
            "1",
            "--workers",
            "2",
        ],
        &dir.join("graded.json"),
    );
    assert_eq!(graded["inputs"]["grading"], "graded");
    let costs: Vec<f64> = graded["costs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    // Feasible designs score their cost, infeasible ones 1e6 to 2e6, invalid ones 2e6 to 3e6:
    // no two penalised designs tie at a flat 1e6.
    assert!(costs.iter().all(|&c| c < 3e6), "{costs:?}");
    let penalised: Vec<f64> = costs.iter().copied().filter(|&c| c >= 1e6).collect();
    assert!(
        penalised.iter().all(|&c| c > 1e6),
        "a penalised design with no shortfall: {costs:?}"
    );
    let flat = run_to_completion(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--payload",
            "3",
            "--population",
            "5",
            "--generations",
            "0",
        ],
        &dir.join("flat.json"),
    );
    assert!(
        flat["inputs"].get("grading").is_none(),
        "flat is the default"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn clipped_samples_are_evaluated_inside_the_design_space() {
    let dir = scratch("clip");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 4.into());
    let out = dir.join("clip.json");
    let clipped = run_to_completion(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--payload",
            "1",
            "--bounds",
            "clip",
            "--population",
            "5",
            "--generations",
            "1",
            "--workers",
            "2",
        ],
        &out,
    );
    assert_eq!(clipped["inputs"]["bounds"], "clip");
    let text = std::fs::read_to_string(out.with_extension("log.jsonl")).unwrap();
    let mut lines = text.lines();
    let header: Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    assert_eq!(header["run"]["bounds"], "clip");
    let bounds = [[1.0, 9.0], [1.0, 9.0], [1.0, 3.0], [1.0, 3.0]];
    let mut logged = 0;
    for line in lines {
        let entry: Value = serde_json::from_str(line).unwrap();
        let r: Vec<f64> = entry["ratios"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        for (value, [lo, hi]) in r.iter().zip(bounds) {
            assert!((lo..=hi).contains(value), "{r:?} outside the bounds");
        }
        // The task's order constraints: r3 <= r2 and r2 < r1.
        assert!(r[2] <= r[1] && r[1] < r[0], "{r:?} breaks the order");
        assert_ne!(entry["status"], "Invalid_Design", "{entry}");
        logged += 1;
    }
    assert_eq!(logged, 10);
    let best: Vec<f64> = clipped["best_ratios"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(best.is_empty() || (best[2] <= best[1] && best[1] < best[0]));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The statuses and designs of a run's evaluation log in (generation, index) order (the log
/// holds them in the order they finished).
fn logged_designs(out: &Path) -> Vec<(String, Vec<f64>)> {
    let text = std::fs::read_to_string(out.with_extension("log.jsonl")).unwrap();
    let entries = text.lines().skip(1);
    let mut each: Vec<Value> = entries
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    each.sort_by_key(|entry| (entry["generation"].as_u64(), entry["index"].as_u64()));
    (each.iter())
        .map(|entry| {
            let ratios = entry["ratios"].as_array().unwrap().iter();
            let ratios = ratios.map(|v| v.as_f64().unwrap()).collect();
            (entry["status"].as_str().unwrap().to_owned(), ratios)
        })
        .collect()
}

/// `--bounds map` against the paper's rule, which draws designs outside the space: the flag is
/// recorded, every design logged lies in the space, the summary and the document say no
/// evaluation was invalid (against the penalty run's count, which its log bears out), and a run
/// cut short resumes to the same result, replaying what it had finished.
#[test]
fn mapped_samples_are_designs_and_resume_alike() {
    let dir = scratch("map");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    let task = task.to_str().unwrap();
    let args = |bounds: &'static str| {
        vec![
            "optimize",
            "--task",
            task,
            "--payload",
            "1",
            "--seed",
            "0",
            "--population",
            "6",
            "--generations",
            "2",
            "--workers",
            "2",
            "--bounds",
            bounds,
        ]
    };
    let out = dir.join("map.json");
    let (stdout, mapped) = support::succeed_with_out(&args("map"), &out);
    assert_eq!(mapped["inputs"]["bounds"], "map");
    assert_eq!(mapped["evaluations"], 18);
    assert_eq!(mapped["verdicts"]["invalid"]["designs"], 0);
    assert!(stdout.contains("invalid 0 of 18 (0.0%)"), "{stdout}");
    let text = std::fs::read_to_string(out.with_extension("log.jsonl")).unwrap();
    let header: Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert_eq!(header["run"]["bounds"], "map");
    let logged = logged_designs(&out);
    assert_eq!(logged.len(), 18);
    let bounds = [[1.0, 9.0], [1.0, 9.0], [1.0, 3.0], [1.0, 3.0]];
    for (status, r) in &logged {
        assert_ne!(status, "Invalid_Design");
        for (value, [lo, hi]) in r.iter().zip(bounds) {
            assert!((lo..=hi).contains(value), "{r:?} outside the bounds");
        }
        assert!(r[2] <= r[1] && r[1] < r[0], "{r:?} breaks the order");
    }

    let penalty_out = dir.join("penalty.json");
    let (stdout, penalised) = support::succeed_with_out(&args("penalty"), &penalty_out);
    let invalid = (logged_designs(&penalty_out).iter())
        .filter(|(status, _)| status == "Invalid_Design")
        .count();
    assert!(invalid > 0, "the paper's rule drew no invalid design");
    assert_eq!(penalised["verdicts"]["invalid"]["designs"], invalid);
    let share = format!(
        "invalid {invalid} of 18 ({:.1}%)",
        100.0 * invalid as f64 / 18.0
    );
    assert!(stdout.contains(&share), "{stdout}");

    // Cut the map run's log after 7 evaluations, as an interruption would, and resume it.
    let kept: Vec<&str> = text.lines().take(8).collect();
    std::fs::write(out.with_extension("log.jsonl"), kept.join("\n") + "\n").unwrap();
    std::fs::remove_file(&out).unwrap();
    let mut resume = args("map");
    resume.push("--resume");
    let (_, resumed) = support::succeed_with_out(&resume, &out);
    same_result(&mapped, &resumed);
    assert!(!mapped["best_ratios"].as_array().unwrap().is_empty());
    assert_eq!(resumed["replayed"], 7);
    assert_eq!(resumed["verdicts"]["invalid"]["designs"], 0);
    assert_eq!(logged_designs(&out), logged);

    // The gradient method keeps its iterates in the space: it refuses the map.
    let refused = support::codesign(&["optimize", "--method", "gradient", "--bounds", "map"]);
    support::refused_as_usage(&refused, "--bounds map: the gradient method is a projected");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task whose order constraints form a cycle (r1 <= r2 <= r1) has no map from the unit box:
/// `--bounds map` is refused naming the ratios, before any generation.
#[test]
fn a_cycle_of_order_constraints_is_refused_under_the_map() {
    let dir = scratch("map-cycle");
    let task = support::task_with(&dir, |task| {
        task["motion"]["steps"] = 4.into();
        task["transmission"]["original"] = serde_json::json!([3, 3, 1, 1]);
        task["transmission"]["order"] = serde_json::json!(["r3 <= r2", "r1 <= r2", "r2 <= r1"]);
    });
    let output = codesign_command(support::root(), &[])
        .args([
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--bounds",
            "map",
        ])
        .args(["--population", "5", "--generations", "0", "--workers", "1"])
        .arg("--out")
        .arg(dir.join("cycle.json"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "--bounds map: transmission.order: the constraints among r1, r2 form a cycle"
        ),
        "{stderr}"
    );
    assert!(!dir.join("cycle.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Warm starts (the default) against `--warm-start off` on the same seed: the logs record the
/// setting, the initial population (started cold either way) is evaluated to the same costs, the
/// warm run takes fewer IPOPT iterations, and a log resumes only under its own setting.
#[test]
fn warm_starts_are_recorded_and_save_iterations() {
    let dir = scratch("warm");
    let args = |warm: &'static str| {
        vec![
            "optimize",
            "--space",
            "actuation",
            "--payload",
            "1",
            "--seed",
            "0",
            "--population",
            "16",
            "--generations",
            "4",
            "--workers",
            "2",
            "--warm-start",
            warm,
        ]
    };
    let run =
        |warm: &'static str| run_to_completion(&args(warm), &dir.join(format!("{warm}.json")));
    let (on, off) = (run("on"), run("off"));
    assert_eq!(on["inputs"]["warm_start"], "on");
    assert_eq!(off["inputs"]["warm_start"], "off", "written when off too");
    let costs = |run: &Value| run["costs"].as_array().unwrap()[..16].to_vec();
    assert_eq!(costs(&on), costs(&off), "generation 0 starts cold in both");
    let iterations = |warm: &str| {
        let text = std::fs::read_to_string(dir.join(format!("{warm}.log.jsonl"))).unwrap();
        let entries = text.lines().skip(1);
        let each = entries.map(|line| serde_json::from_str::<Value>(line).unwrap());
        each.map(|entry| entry["iterations"].as_u64().unwrap())
            .sum::<u64>()
    };
    assert!(iterations("on") < iterations("off"));
    let mut resume = args("off");
    resume.push("--resume");
    let output = codesign_command(support::root(), &resume)
        .arg("--out")
        .arg(dir.join("on.json"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("warm_start"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 57, item 8: a run that finds no feasible design reports no cost, whatever its penalty:
/// `best_cost` is null beside the empty `best_ratios`, and neither its summary nor the table
/// shows a number for it (with `--penalty 0` both showed 0, a perfect J).
#[test]
fn a_run_without_a_feasible_design_reports_no_cost() {
    let dir = scratch("no-design");
    // At 3 kg in joint space no design of the initial population is feasible.
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 4.into());
    let out = dir.join("none.json");
    let (text, result) = support::succeed_with_out(
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--space",
            "joint",
            "--payload",
            "3",
            "--population",
            "5",
            "--generations",
            "0",
            "--penalty",
            "0",
            "--workers",
            "1",
        ],
        &out,
    );
    assert!(text.starts_with("no feasible design found;"), "{text}");
    assert_eq!(result["best_ratios"], serde_json::json!([]));
    assert!(result["best_cost"].is_null(), "{}", result["best_cost"]);
    let table = support::codesign(&["table", out.to_str().unwrap()]);
    let table = String::from_utf8_lossy(&table.stdout);
    assert!(
        table.contains("| none feasible | 0: none feasible |"),
        "{table}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 57, item 9: the capacity objective's search goes up to `--max` (64 kg unless given,
/// with `capacity --max`'s range), and a run whose designs reach it says so: in the result
/// (`at_max`, the evaluations that reached it) and in its summary.
#[test]
fn the_capacity_objective_searches_up_to_max_and_says_when_designs_reach_it() {
    let dir = scratch("capacity-max");
    let task = support::task_with(&dir, |task| task["motion"]["steps"] = 8.into());
    fn capacity(max: &str) -> Vec<&str> {
        vec![
            "optimize",
            "--objective",
            "capacity",
            "--space",
            "actuation",
            "--population",
            "5",
            "--generations",
            "0",
            "--capacity-resolution",
            "0.25",
            "--max",
            max,
        ]
    }
    let mut args = capacity("0.5");
    args.extend(["--task", task.to_str().unwrap(), "--workers", "2"]);
    let (text, capped) = support::succeed_with_out(&args, &dir.join("capped.json"));
    assert_eq!(capped["inputs"]["objective"]["max_kg"], 0.5);
    assert_eq!(capped["best_cost"], -0.5, "{capped}");
    let reached = capped["at_max"].as_u64().unwrap();
    assert!(reached >= 1, "{capped}");
    assert!(
        text.contains(&format!(
            "largest payload capacity 0.500 kg at r = (8.1701, 2.8946, 1.2235, 1.5014): the \
             search's ceiling (--max 0.5 kg), reached by {reached} of 5 evaluations, whose \
             capacities may be larger"
        )),
        "{text}"
    );
    for max in ["2000", "0", "inf"] {
        support::refused_as_usage(
            &support::codesign(&capacity(max)),
            &format!("--max {max}: must be a mass from 0.000001 kg (a milligram"),
        );
    }
    support::refused_as_usage(
        &support::codesign(&["optimize", "--max", "5"]),
        "--max: only with --objective capacity",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
