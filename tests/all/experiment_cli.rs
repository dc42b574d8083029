//! The experiment of a task (its `experiment` section) drives `reproduce`, its plan and its
//! table; results record their task's hash, and `table` shows the paper's numbers only beside
//! the paper's task and never merges two tasks.

use crate::support;
use std::collections::BTreeMap;

use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use support::{
    codesign_in, fails_saying, read_json, refused_as_usage, root, scratch, succeed_in, task_with,
};

fn path(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The repository's task on 8 intervals (solved in milliseconds) with `experiment` as its
/// section, written to `dir/task.json`.
fn small_task(dir: &Path, experiment: Value) -> PathBuf {
    task_with(dir, |task| {
        task["motion"]["steps"] = 8.into();
        task["experiment"] = experiment.clone();
    })
}

/// A tiny experiment: the original design and co-design at 0.5 kg, one seed of 5 designs over
/// one generation, no graded or range runs.
fn tiny_experiment() -> Value {
    json!({
        "original_payloads_kg": [0.5],
        "codesign_payloads_kg": [0.5],
        "graded_payloads_kg": [],
        "range_payloads_kg": [],
        "budget": {
            "seeds": 1, "population": 5, "generations": 1,
            "capacity_population": 5, "capacity_generations": 1
        }
    })
}

/// A planned command's program and subcommand, then its flags with their values (`--resume`
/// with none), numbers read as numbers.
fn command_words(line: &str) -> (String, BTreeMap<String, String>) {
    let words: Vec<&str> = line.split(' ').collect();
    let mut flags = BTreeMap::new();
    let mut at = 2;
    while at < words.len() {
        let value = words.get(at + 1).filter(|word| !word.starts_with("--"));
        let value = value.map(|word| match word.parse::<f64>() {
            Ok(number) => number.to_string(),
            Err(_) => (*word).to_owned(),
        });
        flags.insert(words[at].to_owned(), value.clone().unwrap_or_default());
        at += 1 + usize::from(value.is_some());
    }
    (words[..2].join(" "), flags)
}

/// Checks that the planned command `now` poses what `was` posed: the same command with the
/// same flags and values; `optimize` may name besides them the settings at their defaults that
/// it left out before (method, objective, solve timeout, warm starts, the capacity search's
/// largest payload).
fn same_command(now: &str, was: &str) {
    let (now_program, mut now_flags) = command_words(now);
    let (was_program, was_flags) = command_words(was);
    assert_eq!(now_program, was_program, "{now}");
    if now_program.ends_with("optimize") {
        let defaults = [
            ("--method", "cmaes"),
            ("--objective", "cost"),
            ("--solve-timeout", "600"),
            ("--warm-start", "on"),
            ("--max", "64"),
        ];
        for (flag, default) in defaults {
            if !was_flags.contains_key(flag) && now_flags.get(flag).is_some_and(|v| v == default) {
                now_flags.remove(flag);
            }
        }
    }
    assert_eq!(now_flags, was_flags, "now: {now}\nwas: {was}");
}

/// `reproduce --bounds map` maps the samples of every CMA-ES run (the capacity searches among
/// them) and leaves the gradient method, a projected method, alone; without the flag no run
/// names `--bounds`: the paper's rule.
#[test]
fn reproduce_maps_the_samples_of_every_cmaes_run_when_asked() {
    let dir = scratch("map-plan");
    let plan = |extra: &[&str]| {
        let args = [
            &["reproduce", "--plan", "--quick", "--out-dir", "OUT"],
            extra,
        ]
        .concat();
        succeed_in(&dir, &args)
    };
    let mapped = plan(&["--bounds", "map"]);
    let optimize = |line: &&str| line.contains(" optimize ");
    let cmaes: Vec<&str> = mapped.lines().filter(optimize).collect();
    assert!(cmaes
        .iter()
        .any(|line| line.contains("--objective capacity")));
    for line in cmaes {
        let gradient = line.contains("--method gradient");
        assert_eq!(line.contains(" --bounds map "), !gradient, "{line}");
    }
    assert!(!plan(&[]).contains("--bounds"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_plan_of_the_built_in_task_is_the_paper_s_experiment_as_before() {
    let dir = scratch("built-in-plan");
    let program = format!("'{}'", env!("CARGO_BIN_EXE_codesign"));
    for (flags, expected) in [(&[][..], "full.txt"), (&["--quick"][..], "quick.txt")] {
        let args = [&["reproduce", "--plan", "--out-dir", "OUT"], flags].concat();
        let plan = succeed_in(&dir, &args).replace(&program, "CODESIGN");
        // Captured from `reproduce --plan` before tasks had an experiment section.
        let before =
            std::fs::read_to_string(root().join("tests/data/plan").join(expected)).unwrap();
        // The same commands, each naming the task's ends (the paper's), then the section
        // that solves Table II's cases under `hold` in OUT/hold.
        let lines: Vec<&str> = plan.lines().collect();
        let (table, hold) = lines.split_at(before.lines().count());
        for (now, was) in table.iter().zip(before.lines()) {
            same_command(&now.replace(" --ends paper", ""), was);
        }
        assert_eq!(
            table
                .iter()
                .filter(|line| line.contains(" --ends paper"))
                .count(),
            before.lines().count()
        );
        assert!(!hold.is_empty());
        for line in hold {
            assert!(
                line.contains(" --ends hold") && line.contains("'OUT/hold/"),
                "{line}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_task_s_experiment_section_makes_the_plan() {
    let dir = scratch("section-plan");
    let task = small_task(&dir, tiny_experiment());
    let base = ["reproduce", "--plan", "--task", path(&task), "--out-dir"];
    let plan = succeed_in(&dir, &[&base[..], &["out"]].concat());
    let lines: Vec<&str> = plan.lines().collect();
    // Originals 1 x 2 spaces, CMA-ES 1 x 2 x 1 seed, gradient 1 x 2, capacity designs 2,
    // original capacities 2; then under `hold` (the task's ends are the paper's) the originals,
    // the CMA-ES runs and the original capacities again.
    assert_eq!(lines.len(), 10 + 6, "{plan}");
    assert!(
        lines[10..].iter().all(|line| line.contains("--ends hold")),
        "{plan}"
    );
    assert!(
        lines[0].contains("solve --space joint --payload 0.5 --task"),
        "{plan}"
    );
    let has = |flags: &[(&str, &str)]| {
        lines.iter().any(|line| {
            let (_, words) = command_words(line);
            flags
                .iter()
                .all(|(flag, value)| words.get(*flag).is_some_and(|v| v == value))
        })
    };
    let sizes = [
        ("--seed", "0"),
        ("--population", "5"),
        ("--generations", "1"),
    ];
    let cost = [
        ("--payload", "0.5"),
        ("--ends", "paper"),
        ("--space", "actuation"),
    ];
    assert!(has(&[&cost[..], &sizes[..]].concat()), "{plan}");
    let capacity = [
        ("--objective", "capacity"),
        ("--capacity-resolution", "0.01"),
    ];
    assert!(has(&[&capacity[..], &sizes[..]].concat()), "{plan}");
    for absent in ["seed1", "graded", "range", "--payload 1 ", "--payload 3 "] {
        assert!(!plan.contains(absent), "{absent}: {plan}");
    }
    // Flags replace the section's values.
    let more = succeed_in(&dir, &[&base[..], &["out", "--seeds", "2"]].concat());
    assert!(more.contains("actuation-0.5kg-seed1.json"), "{more}");
    // --quick takes the quick budget, the paper's where the section leaves it out.
    let quick = succeed_in(&dir, &[&base[..], &["out", "--quick"]].concat());
    let quick_sizes = |line: &str| {
        let (_, words) = command_words(line);
        words.get("--population").is_some_and(|p| p == "16")
            && words.get("--generations").is_some_and(|g| g == "8")
    };
    assert!(quick.lines().any(quick_sizes), "{quick}");
    assert!(quick.contains("seed1"), "{quick}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn budgets_out_of_range_name_the_task_s_field_or_the_flag() {
    let dir = scratch("section-errors");
    // Each task is written to dir/task.json.
    let with = |edit: &dyn Fn(&mut Value)| {
        let mut experiment = tiny_experiment();
        edit(&mut experiment);
        small_task(&dir, experiment)
    };
    let task = with(&|e| e["budget"]["population"] = 2.into());
    let args = [
        "reproduce",
        "--plan",
        "--task",
        path(&task),
        "--out-dir",
        "out",
    ];
    let output = codesign_in(&dir, &args);
    fails_saying(&output, "experiment.budget.population = 2: must be 5 to");
    fails_saying(&output, path(&task));
    let output = codesign_in(&dir, &[&args[..], &["--population", "3"]].concat());
    refused_as_usage(&output, "--population 3: must be 5 to");
    with(&|e| e["codesign_payloads_kg"] = json!([0.5, 0.5]));
    let output = codesign_in(&dir, &args);
    fails_saying(
        &output,
        "experiment.codesign_payloads_kg[1] = 0.5: given twice",
    );
    with(&|e| e["budget"]["capacity_population"] = 1.into());
    let output = codesign_in(&dir, &args);
    fails_saying(
        &output,
        "experiment.budget.capacity_population = 1: must be 5 to",
    );
    assert!(!dir.join("out").exists(), "the plan's folders were made");
    // A flag that replaces a value out of range mends it.
    with(&|e| e["budget"]["population"] = 2.into());
    succeed_in(&dir, &[&args[..], &["--population", "6"]].concat());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task's own experiment, reproduced whole: its table and page name the task and its hash,
/// never the paper's numbers, and `table` refuses to merge it with the paper's results. About
/// 16 s on 2 cores: the smallest experiment still runs every stage (originals, CMA-ES, the
/// gradient method's candidate starts and descents, capacities) under both ends.
#[test]
fn a_task_s_experiment_runs_and_its_table_names_the_task_without_the_paper_s_numbers() {
    let dir = scratch("section-run");
    let task = small_task(&dir, tiny_experiment());
    let out = dir.join("out");
    let args = ["reproduce", "--task", path(&task), "--out-dir", path(&out)];
    let printed = succeed_in(&dir, &args);
    // Each co-design run's line says where its solver time went (issue 54, item 4).
    let run = read_json(&out.join("runs/actuation-0.5kg-seed0.json"));
    let work = format!(
        "({} evaluations; median solve {:.1} ms, total solver time {:.1} s; invalid {} of ",
        run["evaluations"],
        run["median_solve_seconds"].as_f64().unwrap() * 1e3,
        run["solve_seconds_total"].as_f64().unwrap(),
        run["verdicts"]["invalid"]["designs"]
    );
    let line =
        (printed.lines()).find(|line| line.starts_with("co-design, actuation space, 0.5 kg"));
    assert!(
        line.is_some_and(|line| line.contains(&work)),
        "{printed}\nnot found: {work}"
    );
    let table = std::fs::read_to_string(out.join("paper_table.md")).unwrap();
    let title = format!("# Co-design of task {} (task hash ", path(&task));
    assert!(table.starts_with(&title), "{table}");
    assert!(
        !table.contains("Table II") && !table.contains("(paper)"),
        "{table}"
    );
    assert!(
        table.contains(
            "The experiment of the task's `experiment` section: original design at 0.5 kg; \
             co-design at 0.5 kg."
        ),
        "{table}"
    );
    assert!(table.contains("| 0.5 kg | joint | ("), "{table}");
    assert!(table.contains("| 0.5 kg | actuation | ("), "{table}");
    // Its page shows the same table and the plots.
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains(&format!("<h1>Co-design of task {}", path(&task))));
    assert!(
        page.contains("<td>0.5 kg</td><td>actuation</td><td>("),
        "{page}"
    );
    assert!(page.contains("<img src=\"plots/original-joint-0.5kg/motion.svg\""));
    // Every result records the task's hash, the table too.
    let hash = read_json(&out.join("paper_table.json"))["task_hash"].clone();
    assert_eq!(hash.as_str().map(str::len), Some(16), "{hash}");
    assert!(table.contains(hash.as_str().unwrap()));
    let original = out.join("original/joint-0.5kg.json");
    for (file, key) in [
        (original.clone(), "/inputs/task_hash"),
        (
            out.join("runs/actuation-0.5kg-seed0.json"),
            "/inputs/task_hash",
        ),
        (
            out.join("runs/joint-capacity-seed0.json"),
            "/inputs/task_hash",
        ),
        (
            out.join("capacity/actuation-original.json"),
            "/inputs/task_hash",
        ),
    ] {
        assert_eq!(
            read_json(&file).pointer(key),
            Some(&hash),
            "{}",
            file.display()
        );
    }

    // `table` refuses to merge it with a result of the built-in task (written before results
    // recorded their task's hash, and taken as the built-in task's as it says it is).
    let paper = root().join("results/quick/original/joint-0kg.json");
    let output = codesign_in(&dir, &["table", path(&original), path(&paper)]);
    fails_saying(&output, "are results of different tasks");
    fails_saying(&output, path(&original));
    fails_saying(&output, path(&paper));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_paper_s_numbers_stand_beside_the_paper_s_task_only() {
    let dir = scratch("paper-task");
    let solve = |name: &str, space: &str, extra: &[&str]| {
        let out = dir.join(name);
        let args = [
            "solve",
            "--space",
            space,
            "--payload",
            "0",
            "--out",
            path(&out),
        ];
        succeed_in(&dir, &[&args[..], extra].concat());
        out
    };
    // The built-in task, and its file, which the committed logs were written with.
    let file = root().join("robots/tasks/pick_place.json");
    let built_in = solve("built-in.json", "joint", &[]);
    let from_file = solve("file.json", "actuation", &["--task", path(&file)]);
    let hash = read_json(&built_in)["inputs"]["task_hash"].clone();
    assert_eq!(read_json(&from_file)["inputs"]["task_hash"], hash);
    let table = succeed_in(&dir, &["table", path(&built_in), path(&from_file)]);
    assert!(table.starts_with("# Table II reproduced"), "{table}");
    assert!(
        table.contains("| 0 kg | actuation | (6, 3, 1, 1): "),
        "{table}"
    );
    assert!(table.contains("| (6, 3, 1, 1): 50.99 |"), "{table}");

    // Another task (other weights, the same motion): its own hash, no paper, and never merged.
    let other = task_with(&dir, |task| task["weights"]["control"] = 0.002.into());
    let edited = solve("edited.json", "actuation", &["--task", path(&other)]);
    let edited_hash = read_json(&edited)["inputs"]["task_hash"].clone();
    assert_ne!(edited_hash, hash);
    let table = succeed_in(&dir, &["table", path(&edited)]);
    let title = format!(
        "# Co-design of task {} (task hash {}): ",
        path(&other),
        edited_hash.as_str().unwrap()
    );
    assert!(table.starts_with(&title), "{table}");
    assert!(
        !table.contains("50.99") && !table.contains("(paper)"),
        "{table}"
    );
    let output = codesign_in(&dir, &["table", path(&built_in), path(&edited)]);
    fails_saying(&output, "are results of different tasks");
    fails_saying(
        &output,
        &format!("{} (task hash {}", path(&built_in), hash.as_str().unwrap()),
    );
    fails_saying(&output, path(&edited));

    // The built-in task on another motion keeps its hash (the task as read) but is no longer
    // the paper's problem.
    let short = solve("short.json", "actuation", &["--steps", "5"]);
    assert_eq!(read_json(&short)["inputs"]["task_hash"], hash);
    let table = succeed_in(&dir, &["table", path(&short)]);
    assert!(table.starts_with("# Co-design of task built-in"), "{table}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn from_runs_refuses_a_result_of_another_task() {
    let dir = scratch("from-runs-task");
    for folder in ["original", "runs", "capacity"] {
        std::fs::create_dir_all(dir.join(folder)).unwrap();
        for entry in std::fs::read_dir(root().join("results/quick").join(folder)).unwrap() {
            let from = entry.unwrap().path();
            if from.extension().is_some_and(|e| e == "json") {
                std::fs::copy(&from, dir.join(folder).join(from.file_name().unwrap())).unwrap();
            }
        }
    }
    let original = dir.join("original/joint-1kg.json");
    let mut document = read_json(&original);
    document["inputs"]["task_hash"] = "0123456789abcdef".into();
    std::fs::write(&original, document.to_string()).unwrap();
    let output = codesign_in(&dir, &["reproduce", "--quick", "--from-runs", path(&dir)]);
    fails_saying(
        &output,
        &format!("{} is a result of another task", path(&original)),
    );
    fails_saying(&output, "(task hash 0123456789abcdef, task file built-in)");
    std::fs::remove_dir_all(&dir).unwrap();
}
