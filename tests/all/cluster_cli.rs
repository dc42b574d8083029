//! Beyond one machine: workers started by a command of the user's (as `srun` or `ssh` would),
//! workers of another build refused, and the experiment's plan run by GNU parallel and merged
//! into the table a single `reproduce` writes.

use crate::support;

use serde_json::Value;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use support::{codesign_in, read_json, scratch, succeed_in, task_with};

/// The repository's task on 8 intervals instead of 50: the same problem, solved in
/// milliseconds.
fn small_task(dir: &Path) -> PathBuf {
    task_with(dir, |task| task["motion"]["steps"] = 8.into())
}

/// An executable shell script `name` in `dir`.
fn script(dir: &Path, name: &str, body: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

/// A small co-design on `task`, written to `dir/NAME.json`, with `extra` flags.
fn optimize(dir: &Path, task: &Path, name: &str, extra: &[&str]) -> Value {
    let out = dir.join(format!("{name}.json"));
    let mut args = vec![
        "optimize",
        "--task",
        task.to_str().unwrap(),
        "--space",
        "actuation",
        "--payload",
        "1",
        "--seed",
        "3",
        "--population",
        "8",
        "--generations",
        "3",
        "--workers",
        "2",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    succeed_in(dir, &args);
    read_json(&out)
}

#[test]
fn workers_started_by_a_command_give_the_same_results() {
    let dir = scratch("wrapper");
    let task = small_task(&dir);
    let log = dir.join("wrapper.log");
    let wrapper = script(
        &dir,
        "wrapper.sh",
        &format!("echo started >> '{}'\nexec \"$@\"", log.display()),
    );
    let command = format!("{} {{}} worker", wrapper.display());
    let wrapped = optimize(&dir, &task, "wrapped", &["--worker-command", &command]);
    let direct = optimize(&dir, &task, "direct", &[]);
    for key in [
        "best_ratios",
        "best_cost",
        "costs",
        "generations",
        "stop_reason",
    ] {
        assert_eq!(wrapped[key], direct[key], "{key}");
    }
    let started = std::fs::read_to_string(&log).unwrap();
    assert_eq!(started.lines().count(), 2, "one line per worker: {started}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_worker_of_another_build_is_refused() {
    let dir = scratch("other-build");
    let task = small_task(&dir);
    let command = r#"{} worker | sed -u 's/"codesign":"[^"]*"/"codesign":"0.0.1"/'"#;
    let out = dir.join("refused.json");
    let output = codesign_in(
        &dir,
        &[
            "optimize",
            "--task",
            task.to_str().unwrap(),
            "--payload",
            "1",
            "--population",
            "5",
            "--generations",
            "0",
            "--workers",
            "1",
            "--worker-command",
            command,
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("refused the worker started by"), "{stderr}");
    assert!(stderr.contains("it is codesign 0.0.1"), "{stderr}");
    assert!(!out.exists(), "no result from a refused worker");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A worker command that ends at once (bad flags, no such program, `false`) fails the run
/// before any evaluation, every time the same way: naming the command and how it ended, and
/// leaving no log (issue 38, probe D9: "cannot send the setup to a worker: Broken pipe", or,
/// by timing, evaluations scored as crashed and a log left behind).
#[test]
fn a_worker_that_ends_at_once_is_named_with_its_exit() {
    let dir = scratch("ends-at-once");
    let task = small_task(&dir);
    let out = dir.join("never.json");
    for (command, status) in [
        ("{} worker --bogus", "exit status: 2"),
        ("false", "exit status: 1"),
        ("/nonexistent/worker", "exit status: 127"),
    ] {
        let output = codesign_in(
            &dir,
            &[
                "optimize",
                "--task",
                task.to_str().unwrap(),
                "--payload",
                "1",
                "--population",
                "5",
                "--generations",
                "0",
                "--workers",
                "1",
                "--worker-command",
                command,
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("ended before its hello"), "{stderr}");
        assert!(stderr.contains(status), "{command}: {stderr}");
        assert!(
            !out.exists() && !dir.join("never.log.jsonl").exists(),
            "{command}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The table with every time (a number before "ms", "s", "min" or "h") blanked, and the note on
/// the run's wall time left out: what two runs of one experiment must share.
fn table_without_times(folder: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(folder.join("paper_table.md")).unwrap();
    let is_unit = |word: &str| {
        let word = word.trim_end_matches(|c: char| c.is_ascii_punctuation());
        ["ms", "s", "min", "h"].contains(&word)
    };
    text.lines()
        .filter(|line| !line.contains("Wall time") && !line.contains("Merged by"))
        .map(|line| {
            let words: Vec<&str> = line.split(' ').collect();
            (0..words.len())
                .map(|i| {
                    let timed = words.get(i + 1).is_some_and(|next| is_unit(next));
                    if timed && words[i].parse::<f64>().is_ok() {
                        "T"
                    } else {
                        words[i]
                    }
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect()
}

/// [`small_task`] with an experiment of every kind of stage at payloads every design carries
/// (0 and 1 kg, the range 0.5 to 1 kg): the plan and its merge cover the paper's stages and
/// those beyond it, and the graded runs, without the 3 kg cases, where most designs are
/// solved from every start of the rule of feasibility (a quarter of the time).
fn light_experiment(dir: &Path) -> PathBuf {
    task_with(dir, |task| {
        task["motion"]["steps"] = 8.into();
        task["experiment"] = serde_json::json!({
            "original_payloads_kg": [0, 1],
            "codesign_payloads_kg": [1],
            "graded_payloads_kg": [1],
            "range_payloads_kg": [0.5, 1],
        });
    })
}

/// A reproduction run whole and the same plan run by GNU parallel and merged give the same
/// tables and runs. The longest test (about 45 s on 2 cores): it needs every kind of stage of
/// the experiment, each solved twice, to show that the plan and the merge cover them all.
#[test]
fn the_plan_run_by_gnu_parallel_and_merged_matches_one_reproduction() {
    let dir = scratch("plan");
    let task = light_experiment(&dir);
    let task = task.to_str().unwrap();
    let sizes = [
        "--quick",
        "--seeds",
        "1",
        "--population",
        "5",
        "--generations",
        "1",
        "--task",
        task,
    ];
    let whole = dir.join("whole");
    let whole_flags = [&sizes[..], &["--out-dir", whole.to_str().unwrap()]].concat();
    succeed_in(&dir, &[&["reproduce"], &whole_flags[..]].concat());

    let split = dir.join("split");
    let plan_flags = [&sizes[..], &["--out-dir", split.to_str().unwrap()]].concat();
    let plan = succeed_in(&dir, &[&["reproduce", "--plan"], &plan_flags[..]].concat());
    assert_eq!(
        plan.lines().count(),
        // Originals, CMA-ES and gradient runs (plain and graded), the capacity co-designs,
        // the range, the graded CMA-ES runs, the originals' capacities; then, under `hold`,
        // its originals, runs and capacities.
        4 + 2 + (2 + 2) + 2 + 1 + 2 + 2 + (4 + 2 + 2),
        "{plan}"
    );
    std::fs::write(dir.join("plan.txt"), &plan).unwrap();
    // A gradient run that finds no feasible start fails its command, as `reproduce` reports and
    // skips it; every result the merge needs is checked there.
    Command::new("parallel")
        .args(["-j", "2"])
        .stdin(std::fs::File::open(dir.join("plan.txt")).unwrap())
        .current_dir(&dir)
        .status()
        .expect("GNU parallel runs (Debian package `parallel`; .ci/setup installs it)");
    let merge_flags = [&sizes[..], &["--from-runs", split.to_str().unwrap()]].concat();
    succeed_in(&dir, &[&["reproduce"], &merge_flags[..]].concat());

    assert_eq!(table_without_times(&split), table_without_times(&whole));
    for run in [
        "runs/actuation-1kg-seed0",
        "runs/joint-1kg-graded-gradient",
        "runs/actuation-range-0.5-1kg-seed0",
        "runs/joint-capacity-seed0",
        "hold/runs/actuation-1kg-seed0",
    ] {
        let file = format!("{run}.json");
        let (a, b) = (read_json(&whole.join(&file)), read_json(&split.join(&file)));
        for key in ["best_ratios", "best_cost", "costs", "inputs"] {
            assert_eq!(a[key], b[key], "{run}: {key}");
        }
    }
    // The capacities, searched side by side in one process and one a command elsewhere, make
    // the same probes.
    for space in ["joint", "actuation"] {
        let file = format!("capacity/{space}-original.json");
        let (a, b) = (read_json(&whole.join(&file)), read_json(&split.join(&file)));
        let probes = |document: &Value| -> Vec<(Value, Value, Value)> {
            let probes = document["probes"].as_array().unwrap();
            let each = probes.iter();
            each.map(|p| {
                (
                    p["payload_kg"].clone(),
                    p["feasible"].clone(),
                    p["cost"].clone(),
                )
            })
            .collect()
        };
        assert_eq!(
            a["capacity"]["capacity_kg"], b["capacity"]["capacity_kg"],
            "{file}"
        );
        assert_eq!(probes(&a), probes(&b), "{file}");
    }
    // The merge's inputs are no outputs: a table linked to a run's result is refused before
    // anything is written, and the run's result is kept.
    let run = split.join("runs/actuation-1kg-seed0.json");
    let before = std::fs::read(&run).unwrap();
    let table = split.join("paper_table.json");
    std::fs::remove_file(&table).unwrap();
    std::os::unix::fs::symlink(&run, &table).unwrap();
    let output = codesign_in(&dir, &[&["reproduce"], &merge_flags[..]].concat());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("--from-runs"), "{stderr}");
    assert!(stderr.contains("that is an input"), "{stderr}");
    assert_eq!(std::fs::read(&run).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}
