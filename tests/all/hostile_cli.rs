//! Hostile inputs and environments, third round (issue 25): every path written is guarded,
//! every input is bounded, and every failure gives a clear error and the right exit code.

use crate::support;

use std::fs::File;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use support::{
    codesign, codesign_command, fails_saying, refused_as_usage, root, scratch, task_with,
};

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Runs codesign with stdout and stderr sent to the given files.
fn codesign_into(args: &[&str], stdout: Stdio, stderr: Stdio) -> Output {
    codesign_command(root(), args)
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .expect("the codesign binary runs")
}

fn full() -> Stdio {
    Stdio::from(File::options().write(true).open("/dev/full").unwrap())
}

/// Item 2: an IPOPT log file would write over whatever it names (here the task file itself);
/// the option is refused before anything is opened.
#[test]
fn an_ipopt_output_file_is_refused_and_the_file_it_names_kept() {
    let dir = scratch("output-file");
    let task = task_with(&dir, |_| {});
    let text = std::fs::read_to_string(&task).unwrap();
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["solver"]["options"]["output_file"] = path(&task).into();
    let edited = value.to_string();
    std::fs::write(&task, &edited).unwrap();
    let output = codesign(&["solve", "--steps", "2", "--task", path(&task)]);
    fails_saying(
        &output,
        "solver.options.output_file: codesign writes no IPOPT log file",
    );
    assert_eq!(std::fs::read_to_string(&task).unwrap(), edited);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 21: a whole number for a real IPOPT option is taken as a number.
#[test]
fn a_whole_number_sets_a_real_option() {
    let dir = scratch("max-cpu-time");
    let task = task_with(&dir, |task| {
        task["solver"]["options"]["max_cpu_time"] = 100.into();
    });
    let output = codesign(&["solve", "--steps", "2", "--task", path(&task)]);
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 20: errors, help and version on a full disk or a closed stdout exit non-zero without a
/// panic; a reader that closes its pipe early ends the command quietly.
#[test]
fn exit_codes_on_full_disks_closed_outputs_and_pipes() {
    let failed = codesign_into(&["solve", "--ratios", "1,2"], Stdio::null(), full());
    assert_eq!(failed.status.code(), Some(1));
    let usage = codesign_into(&["--no-such-flag"], Stdio::null(), full());
    assert_eq!(usage.status.code(), Some(2));
    for flag in ["--help", "--version"] {
        let output = codesign_into(&[flag], full(), Stdio::piped());
        assert_eq!(output.status.code(), Some(1), "{flag}: {}", stderr(&output));
        assert!(stderr(&output).contains("cannot write the output on stdout"));
    }
    let binary = env!("CARGO_BIN_EXE_codesign");
    for args in ["--version", "task"] {
        let closed = Command::new("sh")
            .args(["-c", &format!("exec '{binary}' {args} >&-")])
            .output()
            .unwrap();
        fails_saying(&closed, "stdout is closed");
    }
    // The reader is gone before codesign writes: its write fails with EPIPE.
    let script = format!("{{ sleep 0.3; '{binary}' task; }} | true; echo ${{PIPESTATUS[0]}}");
    let piped = Command::new("bash").args(["-c", &script]).output().unwrap();
    assert!(piped.status.success());
    assert_eq!(String::from_utf8_lossy(&piped.stdout).trim(), "0");
    assert_eq!(stderr(&piped), "");
}

/// Item 10: numbers out of any sensible range are refused before a solve, naming the flag or
/// the field; a flag out of its range is a usage error, exit 2 (issue 38, item 16).
#[test]
fn absurd_numbers_are_refused_before_any_solve() {
    let dir = scratch("ranges");
    let out = dir.join("o.json");
    let output = codesign(&["optimize", "--solve-timeout", "1e300", "--out", path(&out)]);
    refused_as_usage(
        &output,
        "--solve-timeout 1e300: must be 1 to 604800 seconds",
    );
    // A resolution below adjacent floats would bisect forever.
    for (command, flag) in [
        (
            &["capacity", "--resolution", "1e-300"][..],
            "--resolution 1e-300: must be a mass from 0.000001 kg",
        ),
        (
            &[
                "optimize",
                "--objective",
                "capacity",
                "--capacity-resolution",
                "1e-300",
            ][..],
            "--capacity-resolution 1e-300: must be a mass from 0.000001 kg",
        ),
    ] {
        let mut args = command.to_vec();
        args.extend(["--out", path(&out)]);
        refused_as_usage(&codesign(&args), flag);
    }
    // Below a second no worker can say hello in time, and the worker would be blamed.
    let output = codesign(&["optimize", "--solve-timeout", "1e-300", "--out", path(&out)]);
    refused_as_usage(
        &output,
        "--solve-timeout 1e-300: must be 1 to 604800 seconds",
    );
    refused_as_usage(
        &codesign(&["solve", "--duration", "1e-300"]),
        "the duration must be a number of seconds >= 0.01",
    );
    for (field, edit) in [
        (
            "gravity = [0.0, 0.0, -1e308] is longer than 1000",
            ("gravity", 2, -1e308),
        ),
        (
            "tcp.point = [1e300, 0.0, 0.15] is longer than 100",
            ("tcp", 0, 1e300),
        ),
    ] {
        let task = task_with(&dir, |task| match edit.0 {
            "gravity" => task["gravity"][edit.1] = edit.2.into(),
            _ => task["tcp"]["point"][edit.1] = edit.2.into(),
        });
        let output = codesign(&["solve", "--task", path(&task)]);
        fails_saying(&output, field);
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
    assert_eq!(left.len(), 1, "only the task file: {left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 57, item 6: the capacity search's settings are checked by the library's one rule,
/// which Python applies too: a subnormal `--max` or `--first-step` (which the search would
/// report as a capacity of 5e-324 kg) is refused, naming the flag, before any solve.
#[test]
fn capacity_settings_below_a_milligram_are_refused() {
    let out = scratch("capacity-settings").join("c.json");
    for (flag, value) in [
        ("--max", "5e-324"),
        ("--first-step", "5e-324"),
        ("--max", "1e-7"),
    ] {
        let output = codesign(&["capacity", flag, value, "--out", path(&out)]);
        refused_as_usage(
            &output,
            &format!("{flag} {value}: must be a mass from 0.000001 kg (a milligram"),
        );
        assert!(!out.exists());
    }
}

/// Item 11: no more workers than designs in a generation, and a note above the core count.
#[test]
fn workers_are_capped_at_the_population() {
    let dir = scratch("workers");
    let out = dir.join("o.json");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 4.into());
    let output = codesign(&[
        "optimize",
        "--task",
        path(&task),
        "--workers",
        "100000",
        "--population",
        "5",
        "--generations",
        "0",
        "--out",
        path(&out),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let said = stderr(&output);
    assert!(
        said.contains("--workers 100000: a generation has 5 designs, so 5 workers are started"),
        "{said}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 17: a run is never resumed on an edited robot: the log records the URDF's hash.
#[test]
fn a_run_does_not_resume_on_an_edited_robot() {
    let dir = scratch("robot-edit");
    let urdf = dir.join("arm.urdf");
    let original = std::fs::read_to_string(root().join("robots/belt_arm.urdf")).unwrap();
    std::fs::write(&urdf, &original).unwrap();
    let task = task_with(&dir, |task| {
        task["robot"] = "arm.urdf".into();
        task["motion"]["steps"] = 4.into();
    });
    let out = dir.join("o.json");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "optimize",
            "--task",
            path(&task),
            "--population",
            "5",
            "--generations",
            "0",
            "--workers",
            "1",
            "--out",
            path(&out),
        ];
        args.extend_from_slice(extra);
        codesign(&args)
    };
    let first = run(&[]);
    assert!(first.status.success(), "{}", stderr(&first));
    let heavier = original.replacen("<mass value=\"0.36192\"", "<mass value=\"3\"", 1);
    assert_ne!(heavier, original, "the URDF holds the mass to edit");
    std::fs::write(&urdf, heavier).unwrap();
    let log = dir.join("o.log.jsonl");
    let before = std::fs::read(&log).unwrap();
    fails_saying(&run(&["--resume"]), "robot_hash: log");
    assert_eq!(std::fs::read(&log).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 8: devices, FIFOs and huge files are refused at once as inputs, naming them; nothing
/// is read whole first.
#[test]
fn inputs_must_be_regular_files_of_bounded_size() {
    let dir = scratch("inputs");
    let fifo = dir.join("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let huge = dir.join("huge.json");
    let file = File::create(&huge).unwrap();
    file.set_len(2 << 30).unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["table", "/dev/zero"],
            "/dev/zero: is a device, not a regular file",
        ),
        (
            &["solve", "--task", "/dev/zero"],
            "task file /dev/zero: is a device",
        ),
        (
            &["solve", "--task", "/dev/urandom"],
            "is a device, not a regular file",
        ),
        (
            &["solve", "--robot", "/dev/zero"],
            "/dev/zero: file: is a device",
        ),
        (
            &["solve", "--task", path(&fifo)],
            "is a FIFO, not a regular file",
        ),
        (&["solve", "--task", path(&huge)], "is larger than 1 MiB"),
    ];
    for (args, expected) in cases {
        fails_saying(&codesign(args), expected);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Items 9 and 21: a URDF of 10,000 links is refused at once; empty, non-XML, cut and xacro
/// files each say what they are; a task with a byte order mark reads.
#[test]
fn urdfs_and_tasks_as_users_have_them() {
    let dir = scratch("urdfs");
    let mut long = String::from("<robot name=\"long\">");
    for i in 0..10_000 {
        long.push_str(&format!("<link name=\"l{i}\"/>"));
    }
    long.push_str("</robot>");
    let cases = [
        (
            long.as_str(),
            "10000 links and 0 moving joints: at most 1000 links",
        ),
        ("", "the file is empty"),
        ("{\"robot\": 1}", "not a URDF: it has no <robot> element"),
        ("<robot name=\"x\"><link name=\"a\"/>", "is it cut short?"),
        (
            "<robot xmlns:xacro=\"x\"><xacro:property name=\"l\" value=\"1\"/></robot>",
            "this is a xacro file: run xacro first",
        ),
    ];
    for (k, (text, expected)) in cases.into_iter().enumerate() {
        let urdf = dir.join(format!("robot{k}.urdf"));
        std::fs::write(&urdf, text).unwrap();
        let output = codesign(&["dynamics", "--robot", path(&urdf), "--q", "0,0,0,0"]);
        fails_saying(&output, expected);
    }
    let task = task_with(&dir, |_| {});
    let text = std::fs::read_to_string(&task).unwrap();
    std::fs::write(&task, format!("\u{feff}{text}")).unwrap();
    let output = codesign(&["solve", "--steps", "2", "--task", path(&task)]);
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Copies the committed quick reproduction's results (not its logs) into a scratch folder.
fn quick_results(name: &str) -> std::path::PathBuf {
    let dir = scratch(name);
    for folder in ["original", "runs", "capacity"] {
        std::fs::create_dir_all(dir.join(folder)).unwrap();
        for entry in std::fs::read_dir(root().join("results/quick").join(folder)).unwrap() {
            let from = entry.unwrap().path();
            if from.extension().is_some_and(|e| e == "json") {
                std::fs::copy(&from, dir.join(folder).join(from.file_name().unwrap())).unwrap();
            }
        }
    }
    dir
}

/// Edits the JSON file at `file` in place.
fn edit_json(file: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    edit(&mut value);
    std::fs::write(file, serde_json::to_string_pretty(&value).unwrap()).unwrap();
}

/// Item 18: a run made with other settings than the plan's is never merged as the plan's.
#[test]
fn from_runs_refuses_runs_of_other_settings() {
    let dir = quick_results("from-runs");
    let run = dir.join("runs/actuation-1kg-seed0.json");
    edit_json(&run, |doc| doc["inputs"]["population"] = 6.into());
    let output = codesign(&["reproduce", "--quick", "--from-runs", path(&dir)]);
    fails_saying(&output, "actuation-1kg-seed0.json is not the plan's run");
    fails_saying(&output, "population: recorded 6, planned");
    // Another seed's result under this one's name.
    std::fs::copy(dir.join("runs/actuation-1kg-seed1.json"), &run).unwrap();
    let output = codesign(&["reproduce", "--quick", "--from-runs", path(&dir)]);
    fails_saying(&output, "seed: recorded 1, planned 0");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 19: a result given twice, under one name or two, and an edited negative cost are
/// refused by `table`.
#[test]
fn table_refuses_duplicates_and_edited_costs() {
    let dir = quick_results("table");
    let run = dir.join("runs/actuation-1kg-seed0.json");
    let twin = dir.join("twin.json");
    std::fs::copy(&run, &twin).unwrap();
    for pair in [[&run, &run], [&run, &twin]] {
        let output = codesign(&["table", path(pair[0]), path(pair[1])]);
        fails_saying(&output, "hold the same result");
    }
    edit_json(&twin, |doc| doc["best_cost"] = (-5.0).into());
    let output = codesign(&["table", path(&twin)]);
    fails_saying(&output, "best_cost = -5 is not a trajectory cost");
    // A capacity run's best cost is minus a capacity, or the penalty when no design was
    // feasible (every joint-space design in torque mode `paper` cannot hold the arm at rest);
    // nothing in between.
    let capacity = dir.join("runs/joint-capacity-seed0.json");
    edit_json(&capacity, |doc| doc["best_cost"] = 1e6.into());
    let output = codesign(&["table", path(&capacity)]);
    assert!(output.status.success(), "{}", stderr(&output));
    edit_json(&capacity, |doc| doc["best_cost"] = 5.0.into());
    let output = codesign(&["table", path(&capacity)]);
    fails_saying(&output, "best_cost = -5 is not a trajectory cost");
    let seeds = codesign(&[
        "table",
        path(&run),
        path(&dir.join("runs/actuation-1kg-seed1.json")),
    ]);
    assert!(seeds.status.success(), "{}", stderr(&seeds));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 21: `reproduce` messages: --plan checks the task, --from-runs a missing folder creates
/// nothing.
#[test]
fn reproduce_checks_before_it_plans_or_merges() {
    let dir = scratch("plan");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 0.into());
    let out = dir.join("out");
    let output = codesign(&[
        "reproduce",
        "--quick",
        "--plan",
        "--task",
        path(&task),
        "--out-dir",
        path(&out),
    ]);
    fails_saying(&output, "motion.steps = 0");
    assert!(
        !out.exists(),
        "the plan's folders were made for an invalid task"
    );
    let missing = dir.join("missing");
    let output = codesign(&["reproduce", "--quick", "--from-runs", path(&missing)]);
    fails_saying(&output, "--from-runs");
    fails_saying(&output, "not a folder");
    assert!(!missing.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 1: a plot planted as a link to the task file is refused before the solve; the task
/// file stays as it was.
#[test]
fn a_plot_never_writes_through_a_link_to_an_input() {
    let dir = scratch("plot-link");
    let task = task_with(&dir, |_| {});
    let before = std::fs::read(&task).unwrap();
    let plots = dir.join("plots");
    std::fs::create_dir(&plots).unwrap();
    std::os::unix::fs::symlink(&task, plots.join("tcp_path.svg")).unwrap();
    let output = codesign(&[
        "solve",
        "--steps",
        "2",
        "--task",
        path(&task),
        "--plot",
        path(&plots),
    ]);
    fails_saying(&output, "--plot");
    fails_saying(&output, "that is an input of this command (--task");
    assert_eq!(std::fs::read(&task).unwrap(), before);
    // A folder not made yet is made, with every plot: the four charts, the four motors'
    // torque-speed figures, the arm's poses and its animation.
    let fresh = dir.join("fresh");
    let output = codesign(&[
        "solve",
        "--steps",
        "2",
        "--task",
        path(&task),
        "--plot",
        path(&fresh),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(std::fs::read_dir(&fresh).unwrap().count(), 10);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--check-derivatives` writes no result and no plot: with `--out` or `--plot` it is a usage
/// error naming both flags, where it ignored them and exited 0.
#[test]
fn the_derivative_checker_refuses_the_outputs_it_would_not_write() {
    let dir = scratch("check-derivatives");
    let out = dir.join("cd.json");
    for flag in ["--out", "--plot"] {
        let output = codesign(&[
            "solve",
            "--steps",
            "1",
            "--check-derivatives",
            flag,
            path(&out),
        ]);
        refused_as_usage(&output, "'--check-derivatives' cannot be used with");
        refused_as_usage(&output, flag);
    }
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A gear ratio that is no finite number, and `--resume` of a gradient run, are usage errors
/// (exit 2), as `--payload nan` and the other flags' conflicts are.
#[test]
fn ratios_that_are_no_numbers_and_a_resumed_gradient_run_are_usage_errors() {
    for command in ["solve", "check", "capacity"] {
        for ratios in ["nan,12,1,1", "inf,12,1,1", "6,-inf,1,1"] {
            let output = codesign(&[command, "--ratios", ratios]);
            refused_as_usage(&output, "a gear ratio must be a finite number");
            refused_as_usage(&output, "--ratios");
        }
    }
    let dir = scratch("gradient-resume");
    let out = dir.join("g.json");
    let output = codesign(&[
        "optimize",
        "--method",
        "gradient",
        "--resume",
        "--out",
        path(&out),
    ]);
    refused_as_usage(&output, "--resume: only CMA-ES runs are resumed");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `--plot` folder that cannot be made (a regular file, a device, a path through a file, a
/// folder this user may not write) is refused before the solve, which prints nothing.
#[test]
fn a_plot_folder_that_cannot_be_made_is_refused_before_the_solve() {
    let dir = scratch("plot-folder");
    let task = task_with(&dir, |_| {});
    let file = dir.join("file");
    std::fs::write(&file, "x").unwrap();
    let locked = dir.join("locked");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    let root = unsafe { libc::geteuid() } == 0;
    let mut cases = vec![
        (file.clone(), "it exists and is no folder"),
        (PathBuf::from("/dev/null"), "it exists and is no folder"),
        (file.join("plots"), "is no folder"),
    ];
    // Root may write in any folder whatever its permission bits.
    if !root {
        cases.push((locked.join("plots"), "this user may not write in"));
    }
    for (folder, expected) in cases {
        let output = codesign(&[
            "solve",
            "--steps",
            "2",
            "--task",
            path(&task),
            "--plot",
            path(&folder),
        ]);
        fails_saying(&output, "--plot: cannot create folder");
        fails_saying(&output, expected);
        assert!(
            output.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&output.stdout)
        );
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Items 4, 5 and 12: where the log goes, a file that is no log is left alone; an --out named
/// like a log, or naming a folder, or too long a name, is refused before any work; nothing is
/// left behind.
#[test]
fn outputs_that_would_replace_what_they_should_not_are_refused_first() {
    let dir = scratch("log-place");
    let optimize = |out: &Path| {
        codesign(&[
            "optimize",
            "--population",
            "5",
            "--generations",
            "0",
            "--workers",
            "1",
            "--out",
            path(out),
        ])
    };
    let foreign = dir.join("b.log.jsonl");
    for text in ["{\"hello\": 1}\n".to_owned(), "x".repeat(4 << 20)] {
        std::fs::write(&foreign, &text).unwrap();
        fails_saying(&optimize(&dir.join("b.json")), "is not an evaluation log");
        assert_eq!(std::fs::read_to_string(&foreign).unwrap(), text);
    }
    std::fs::remove_file(&foreign).unwrap();
    fails_saying(
        &optimize(&dir.join("x.log.jsonl")),
        "is an evaluation log (named .log.jsonl",
    );
    fails_saying(
        &codesign(&["solve", "--out", path(&dir.join("y.log.jsonl"))]),
        "is an evaluation log",
    );
    let folder = format!("{}/", dir.join("newdir2").display());
    fails_saying(
        &optimize(Path::new(&folder)),
        "ends in /, /. or /..: it names a folder",
    );
    fails_saying(&codesign(&["solve", "--out", &folder]), "ends in /");
    // `a.json/.` names the folder a.json, refused before the run, not at its end (issue 38).
    let dotted = format!("{}/.", dir.join("a.json").display());
    fails_saying(&optimize(Path::new(&dotted)), "it names a folder");
    fails_saying(&codesign(&["solve", "--out", &dotted]), "it names a folder");
    fails_saying(&codesign(&["capacity", "--out", &folder]), "ends in /");
    let long = dir.join("a".repeat(255));
    fails_saying(
        &codesign(&["solve", "--out", path(&long)]),
        "its file name is 255 bytes long; at most",
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "something was left"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A small co-design run in `dir` (a 4-interval task, population 5) with `extra` flags.
fn small_run(dir: &Path, extra: &[&str]) -> Command {
    let task = task_with(dir, |task| task["motion"]["steps"] = 4.into());
    let out = dir.join("o.json");
    let mut args = vec![
        "optimize".to_owned(),
        "--task".to_owned(),
        path(&task).to_owned(),
        "--population".to_owned(),
        "5".to_owned(),
        "--out".to_owned(),
        path(&out).to_owned(),
    ];
    args.extend(extra.iter().map(|a| a.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    codesign_command(root(), &args)
}

/// Whether a process whose command line is `marker` (its words joined by spaces) still runs
/// (read from /proc; a zombie left to be reaped has an empty command line and does not count).
fn running(marker: &str) -> bool {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return false;
    };
    entries.flatten().any(|entry| {
        std::fs::read(entry.path().join("cmdline")).is_ok_and(|bytes| {
            let text: String = bytes
                .iter()
                .map(|&b| if b == 0 { ' ' } else { b as char })
                .collect();
            text.trim_end() == marker
        })
    })
}

/// Issue 57, item 4: the gradient method on worker processes believes no lie either. A worker
/// that answers every feasible design at J = 1e-9, its merit and feasible cost alike (a lie no
/// check of one answer can see), fails the run: this process solves the best design again from
/// the start its worker was given and finds another cost.
#[test]
fn a_lying_worker_of_the_gradient_method_is_caught_at_the_best_design() {
    let dir = scratch("gradient-liar");
    let liar = concat!(
        r#"{} worker | sed -u -e 's/"cost":[^,]*,"feasible":true/"cost":1e-9,"feasible":true/'"#,
        r#" -e 's/"value":[^,]*/"value":1e-9/' -e 's/"feasible_cost":[^,]*/"feasible_cost":1e-9/'"#
    );
    let run = |command: &str| {
        let flags = [
            "--method",
            "gradient",
            "--gradient-iterations",
            "2",
            "--workers",
            "2",
            "--worker-command",
            command,
        ];
        small_run(&dir, &flags).output().unwrap()
    };
    let output = run(liar);
    fails_saying(
        &output,
        "this process's own evaluation of it finds it feasible at a fitness of",
    );
    fails_saying(&output, "the answers of the workers (`");
    assert!(!dir.join("o.json").exists(), "a result was written");
    // Honest workers are believed.
    let output = run("{} worker");
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Items 13, 14 and 21: a worker command that floods its output, or never says hello, fails the
/// run at once, naming the command, and leaves no process behind; so does TERM to the run.
#[test]
fn workers_that_flood_or_hang_are_stopped_with_all_they_started() {
    let dir = scratch("flood");
    let output = small_run(
        &dir,
        &["--generations", "0", "--worker-command", "cat /dev/zero"],
    )
    .output()
    .unwrap();
    fails_saying(&output, "no codesign hello");
    fails_saying(&output, "not the worker protocol");
    let hang = "sleep 987";
    let output = small_run(
        &dir,
        &[
            "--generations",
            "0",
            "--solve-timeout",
            "2",
            "--worker-command",
            hang,
        ],
    )
    .output()
    .unwrap();
    fails_saying(&output, "said no hello within 2 s");
    assert!(!running(hang), "a hung worker was left running");
    // TERM, HUP (a closed terminal or ssh session), or KILL (no handler runs: the workers'
    // watchdogs see the run's process gone) while workers (each with a child of its own) are
    // busy.
    for (signal, sleep) in [
        (libc::SIGTERM, "sleep 986"),
        (libc::SIGHUP, "sleep 985"),
        (libc::SIGKILL, "sleep 984"),
    ] {
        let command = format!("{sleep} & exec {{}} worker");
        let out = dir.join(format!("signal-{signal}.json"));
        let mut child = codesign_command(
            root(),
            &[
                "optimize",
                "--population",
                "20",
                "--generations",
                "50",
                "--workers",
                "2",
                "--worker-command",
                &command,
                "--out",
                path(&out),
            ],
        )
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
        support::wait_for(std::time::Duration::from_secs(20), || running(sleep));
        std::thread::sleep(std::time::Duration::from_millis(500));
        // SAFETY: a signal to the child this test started.
        unsafe { libc::kill(child.id() as i32, signal) };
        let status = child.wait().unwrap();
        assert!(!status.success());
        std::thread::sleep(std::time::Duration::from_millis(300));
        assert!(
            !running(sleep),
            "signal {signal} left the workers' children running"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Items 15 and 16: answers for other designs, or with impossible costs, are refused; a run
/// whose every evaluation failed that way exits 1; its resumption solves those designs again
/// instead of replaying the failures.
#[test]
fn worker_answers_are_checked_and_failures_never_replayed() {
    let dir = scratch("answers");
    // Issue 38, item 3: besides, costs above any the scoring writes, a status no solve gives,
    // and a negative time.
    let failed = "evaluations failed for a reason not the design's";
    let liars = [
        // Penalised designs at 1e300 are refused; a feasible one at 1e300 ends the run
        // (first: the last liar's log is resumed below).
        (
            r#"{} worker | sed -u 's/"cost":[^,]*/"cost":1e300/'"#,
            "costs 1e300, at or above it",
        ),
        // A plausible lie: every feasible design at J = 1e-9. Only the run's own evaluation
        // of the best design can tell.
        (
            r#"{} worker | sed -u 's/"cost":[^,]*,"feasible":true/"cost":1e-9,"feasible":true/'"#,
            "this process's own evaluation of it finds it feasible at a fitness of",
        ),
        (
            r#"{} worker | sed -u 's/"ratios":\[[0-9.e+-]*/"ratios":[1.5/'"#,
            failed,
        ),
        (
            r#"{} worker | sed -u 's/"cost":[^,]*/"cost":-1e300/'"#,
            failed,
        ),
        (
            r#"{} worker | sed -u 's/"status":"[A-Za-z_]*"/"status":"Solved_By_Magic"/'"#,
            failed,
        ),
        (
            r#"{} worker | sed -u 's/"seconds":[-0-9.e+]*/"seconds":-1e308/'"#,
            failed,
        ),
    ];
    for (liar, expected) in liars {
        let output = small_run(
            &dir,
            &[
                "--generations",
                "0",
                "--workers",
                "1",
                "--worker-command",
                liar,
                "--overwrite",
            ],
        )
        .output()
        .unwrap();
        fails_saying(&output, expected);
        assert!(!dir.join("o.json").exists(), "a result was written");
    }
    let log = std::fs::read_to_string(dir.join("o.log.jsonl")).unwrap();
    assert!(log.contains("Worker_Failed"), "{log}");
    let output = small_run(&dir, &["--generations", "0", "--workers", "1", "--resume"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("o.json")).unwrap()).unwrap();
    assert_eq!(result["replayed"], 0, "worker failures were replayed");
    // Issue 38, item 5: a penalty at or below a feasible cost would rank penalised designs
    // with or above it; the run fails naming the design instead of reporting one of them best.
    std::fs::remove_file(dir.join("o.json")).unwrap();
    for penalty in ["0", "1"] {
        let output = small_run(
            &dir,
            &[
                "--generations",
                "0",
                "--workers",
                "1",
                "--penalty",
                penalty,
                "--overwrite",
            ],
        )
        .output()
        .unwrap();
        fails_saying(
            &output,
            &format!("--penalty {penalty}: the feasible design r = "),
        );
        assert!(!dir.join("o.json").exists(), "a result was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 8: a worker reading an endless line stops with an error instead of filling the memory.
#[test]
fn a_worker_refuses_an_endless_line() {
    let output = codesign_command(root(), &["worker"])
        .stdin(File::open("/dev/zero").unwrap())
        .output()
        .unwrap();
    fails_saying(&output, "not the worker protocol");
}
