//! Outputs that never destroy what they replace, runs that cannot collide, and failures that say
//! so: each bad command gives a clear error, a non-zero exit, and leaves everything as it was.

use crate::support;

use std::path::Path;
use std::process::Command;
use std::time::Duration;
use support::{
    codesign, fails_saying, refused_as_usage, scratch, start_in_background, task_with, wait_for,
};

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn special_files_symlinks_and_inputs_are_never_replaced() {
    let dir = scratch("out");
    let fifo = dir.join("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let solve = |out: &Path| codesign(&["solve", "--steps", "2", "--out", path(out)]);
    fails_saying(&solve(Path::new("/dev/null")), "/dev/null: is a device");
    fails_saying(&solve(&fifo), "is a FIFO");
    assert!(std::os::unix::fs::FileTypeExt::is_fifo(
        &std::fs::metadata(&fifo).unwrap().file_type()
    ));
    fails_saying(&solve(&dir), "is a folder");
    fails_saying(
        &solve(&dir.join("missing/result.json")),
        "cannot write in its folder",
    );
    let task = task_with(&dir, |_| {});
    let before = std::fs::read(&task).unwrap();
    let output = codesign(&[
        "solve",
        "--steps",
        "2",
        "--task",
        path(&task),
        "--out",
        path(&task),
    ]);
    fails_saying(&output, "that is an input of this command (--task");
    assert_eq!(std::fs::read(&task).unwrap(), before);
    // A link is followed: the file it points to takes the result, the link stays.
    let real = dir.join("real.json");
    std::fs::write(&real, "old").unwrap();
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let output = solve(&link);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&real).unwrap().contains("\"cost\""));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn table_outputs_never_collide_with_each_other_or_an_input() {
    let dir = scratch("table");
    let result = dir.join("res.json");
    let output = codesign(&["solve", "--steps", "2", "--out", path(&result)]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let before = std::fs::read(&result).unwrap();
    let output = codesign(&["table", path(&result), "--out", path(&dir.join("res.md"))]);
    fails_saying(&output, "that is an input of this command");
    assert_eq!(std::fs::read(&result).unwrap(), before);
    assert!(!dir.join("res.md").exists(), "nothing written on refusal");
    let named = dir.join("y.json");
    let output = codesign(&["table", path(&result), "--out", path(&named)]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let markdown = std::fs::read_to_string(&named).unwrap();
    assert!(
        markdown.starts_with('#') || markdown.contains("| "),
        "{markdown}"
    );
    let json = std::fs::read_to_string(dir.join("y.json.json")).unwrap();
    serde_json::from_str::<serde_json::Value>(&json).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sizes_are_limited_and_bad_arguments_create_nothing() {
    for steps in ["99999999999", "18446744073709551615"] {
        let output = codesign(&["solve", "--steps", steps]);
        refused_as_usage(&output, "the number of intervals must be 1 to 5000");
    }
    refused_as_usage(&codesign(&["solve", "--duration", "1e9"]), "--duration");
    refused_as_usage(&codesign(&["solve", "--payload", "1e7"]), "to 1000 kg");
    refused_as_usage(&codesign(&["solve", "--payload", "1e-320"]), "a milligram");
    let dir = scratch("sizes");
    let out = dir.join("o.json");
    for (flag, value) in [("--population", "0"), ("--generations", "99999999")] {
        let output = codesign(&["optimize", flag, value, "--out", path(&out)]);
        refused_as_usage(&output, &format!("{flag} {value}: must be"));
    }
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "a file was created"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 57, item 10: a step size whose samples fall far outside the design box, up to designs
/// that are no finite number (which the log wrote as nulls, and then refused to resume), is
/// refused before the run, naming the flag; nothing is created.
#[test]
fn a_step_size_wider_than_the_design_box_is_refused_naming_the_flag() {
    let dir = scratch("sigma");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 4.into());
    let out = dir.join("o.json");
    for sigma in ["1e308", "1.5", "inf", "NaN"] {
        let output = codesign(&[
            "optimize",
            "--task",
            path(&task),
            "--population",
            "5",
            "--generations",
            "1",
            "--workers",
            "1",
            "--sigma",
            sigma,
            "--out",
            path(&out),
        ]);
        refused_as_usage(
            &output,
            &format!("--sigma {sigma}: must be a positive number at most 1"),
        );
        assert!(
            !out.exists() && !dir.join("o.log.jsonl").exists(),
            "{sigma}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_rejected_solver_option_fails_the_run_before_it_starts() {
    let dir = scratch("option");
    let task = task_with(&dir, |task| {
        task["solver"]["options"] = serde_json::json!({"no_such_option": 3});
    });
    let out = dir.join("o.json");
    let output = codesign(&[
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
    ]);
    fails_saying(
        &output,
        "solver: IPOPT rejected option `no_such_option` = 3",
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("task.json")]);
    let output = codesign(&["solve", "--steps", "2", "--task", path(&task)]);
    fails_saying(&output, "task.json solver: IPOPT rejected option");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// With `solver.max_iter` 0 no solve reaches an optimum: `solve` says the design was not
/// judged, and an `optimize` run in which no design was judged fails, where both reported
/// infeasible designs with zero deficits and exited 0.
#[test]
fn solves_short_of_an_optimum_judge_no_design() {
    let dir = scratch("max-iter");
    let task = task_with(&dir, |task| task["solver"]["max_iter"] = 0.into());
    let output = codesign(&["solve", "--steps", "2", "--task", path(&task)]);
    fails_saying(
        &output,
        "the elastic solve ended with Maximum_Iterations_Exceeded short of an optimum",
    );
    let out = dir.join("o.json");
    let output = codesign(&[
        "optimize",
        "--task",
        path(&task),
        "--population",
        "5",
        "--generations",
        "1",
        "--workers",
        "1",
        "--out",
        path(&out),
    ]);
    fails_saying(&output, "no design was judged");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_second_run_on_one_output_fails_at_once_naming_the_first() {
    let dir = scratch("lock");
    let out = dir.join("o.json");
    let log = dir.join("o.log.jsonl");
    // Actuation space without payload, where about half the samples are solved: the first run
    // lasts seconds (in joint space no design holds the load at rest, and a run of unsolved
    // designs would end before the second one starts).
    let args = [
        "optimize",
        "--payload",
        "0",
        "--space",
        "actuation",
        "--population",
        "50",
        "--generations",
        "4",
    ];
    let mut first_args = args.to_vec();
    first_args.extend(["--workers", "1", "--out", path(&out)]);
    let mut first = start_in_background(&first_args);
    wait_for(Duration::from_secs(300), || {
        std::fs::read_to_string(&log).map_or(0, |t| t.lines().count()) >= 2
    });
    for flag in [None, Some("--resume"), Some("--overwrite")] {
        let mut second: Vec<&str> = args.to_vec();
        second.extend(["--workers", "1", "--out", path(&out)]);
        second.extend(flag);
        let output = codesign(&second);
        fails_saying(
            &output,
            &format!("in use by another run (pid {})", first.id()),
        );
    }
    assert!(first.wait().unwrap().success());
    let lines = std::fs::read_to_string(&log).unwrap();
    for line in lines.lines() {
        serde_json::from_str::<serde_json::Value>(line).expect("no torn line");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 57, item 11: one rule for both methods. A result whose evaluation log sits beside it
/// (a CMA-ES run's) is replaced by a gradient run only with --overwrite, which deletes that log,
/// as a CMA-ES run is refused and then starts afresh.
#[test]
fn a_logged_result_is_replaced_by_either_method_only_with_overwrite() {
    let dir = scratch("gradient-over-cmaes");
    let task = task_with(&dir, |task| task["motion"]["steps"] = 4.into());
    let (out, log) = (dir.join("o.json"), dir.join("o.log.jsonl"));
    let run = |extra: &[&str]| {
        let mut args = vec![
            "optimize",
            "--task",
            path(&task),
            "--payload",
            "0",
            "--space",
            "actuation",
            "--workers",
            "1",
            "--out",
            path(&out),
        ];
        args.extend(extra);
        codesign(&args)
    };
    let cmaes = ["--population", "5", "--generations", "0"];
    let first = run(&cmaes);
    assert!(first.status.success(), "{}", stderr(&first));
    let read = |file: &Path| std::fs::read_to_string(file).unwrap();
    let (result, logged) = (read(&out), read(&log));
    let gradient = ["--method", "gradient", "--gradient-iterations", "1"];
    for refused in [&cmaes[..], &gradient[..]] {
        fails_saying(
            &run(refused),
            "o.log.jsonl exists already: pass --resume to continue that run, or --overwrite",
        );
        assert_eq!((read(&out), read(&log)), (result.clone(), logged.clone()));
    }
    let replaced = run(&[&gradient[..], &["--overwrite"]].concat());
    assert!(replaced.status.success(), "{}", stderr(&replaced));
    assert!(
        !log.exists(),
        "the replaced run's log was left beside another run's result"
    );
    assert_eq!(support::read_json(&out)["inputs"]["method"], "gradient");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_failed_write_on_stdout_is_an_error() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let output = support::codesign_command(support::root(), &["dynamics", "--q", "0,0,0,0"])
        .stdout(full)
        .output()
        .unwrap();
    fails_saying(&output, "cannot write the output on stdout");
}

#[test]
fn errors_name_the_real_source_of_the_bad_value() {
    let dir = scratch("source");
    let task = task_with(&dir, |task| {
        task["transmission"]["original"] = serde_json::json!([6.0, 3.0, 1.0, 100.0]);
    });
    let solve = ["solve", "--steps", "2", "--task", path(&task)];
    let capacity = ["capacity", "--task", path(&task)];
    for command in [&solve[..], &capacity[..]] {
        let output = codesign(command);
        fails_saying(&output, "task.json transmission.original (6");
        assert!(!String::from_utf8_lossy(&output.stderr).contains("--ratios"));
    }
    let urdf = dir.join("cut.urdf");
    std::fs::write(&urdf, "<robot name=\"r\">\n  <link name=\"a\">\n").unwrap();
    let output = codesign(&["solve", "--robot", path(&urdf)]);
    fails_saying(&output, "cut.urdf: robot: not a readable URDF");
    fails_saying(&output, "ends before its closing </robot>");
    let one = dir.join("one.json");
    let two = dir.join("two.json");
    for (out, steps) in [(&one, "2"), (&two, "3")] {
        let output = codesign(&["solve", "--steps", steps, "--out", path(out)]);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let output = codesign(&["table", path(&one), path(&two)]);
    fails_saying(&output, "describe different motions");
    let output = codesign(&["table", path(&one), path(&one)]);
    fails_saying(
        &output,
        "both solve the original design at 0 kg in actuation space",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_second_reproduction_on_one_folder_fails_at_once() {
    let dir = scratch("reproduce");
    let out_dir = dir.join("results");
    let args = [
        "reproduce",
        "--quick",
        "--seeds",
        "1",
        "--out-dir",
        path(&out_dir),
    ];
    let mut first = start_in_background(&args);
    wait_for(Duration::from_secs(60), || {
        out_dir.join("original").exists()
    });
    let output = codesign(&args);
    let expected = format!("is in use by another run (pid {})", first.id());
    first.kill().unwrap();
    first.wait().unwrap();
    fails_saying(&output, &expected);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// IPOPT's options file in the working folder is never read (issue 38, item 2): with
/// `max_iter 2` and an `output_file` in `ipopt.opt`, a solve there converges as anywhere else
/// and the file it names is not written; a task naming an options file is refused.
#[test]
fn an_ipopt_options_file_in_the_working_folder_is_ignored() {
    let dir = scratch("ipopt-opt");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me\n").unwrap();
    std::fs::write(
        dir.join("ipopt.opt"),
        format!("max_iter 2\nmu_init 10\noutput_file {}\n", path(&victim)),
    )
    .unwrap();
    let args = [
        "solve",
        "--space",
        "actuation",
        "--payload",
        "0",
        "--steps",
        "10",
    ];
    let here = support::codesign_in(&dir, &args);
    let elsewhere = codesign(&args);
    for output in [&here, &elsewhere] {
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let first = |output: &std::process::Output| {
        let text = String::from_utf8_lossy(&output.stdout).into_owned();
        text.lines().next().unwrap_or_default().to_owned()
    };
    assert_eq!(first(&here), first(&elsewhere));
    assert!(first(&here).contains("Solve_Succeeded"), "{}", first(&here));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me\n");
    let task = support::task_with(&dir, |task| {
        task["solver"]["options"]["option_file_name"] = "ipopt.opt".into();
    });
    let refused = codesign(&["solve", "--task", path(&task), "--payload", "0"]);
    support::fails_saying(
        &refused,
        "solver.options.option_file_name: codesign reads no",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output that is a symbolic link to an evaluation log, or a file that is a log by its first
/// line under another name, is refused and left as it is (issue 38, item 1).
#[test]
fn an_output_that_is_a_log_through_a_link_or_its_content_is_refused() {
    let dir = scratch("log-link");
    let log = dir.join("a.log.jsonl");
    let committed = support::root().join("results/quick/hold/runs/joint-1kg-seed0.log.jsonl");
    std::fs::copy(&committed, &log).unwrap();
    let renamed = dir.join("renamed.json");
    std::fs::copy(&committed, &renamed).unwrap();
    let link = dir.join("b.json");
    std::os::unix::fs::symlink(&log, &link).unwrap();
    let before = std::fs::read(&log).unwrap();
    for out in [&link, &renamed] {
        let output = codesign(&[
            "solve",
            "--space",
            "actuation",
            "--payload",
            "0",
            "--steps",
            "4",
            "--out",
            path(out),
        ]);
        fails_saying(&output, "is an evaluation log");
        let table = codesign(&[
            "table",
            path(&support::root().join("results/quick/original/actuation-0kg.json")),
            "--out",
            path(out),
        ]);
        assert_eq!(table.status.code(), Some(1), "{}", path(out));
    }
    assert_eq!(std::fs::read(&log).unwrap(), before);
    assert_eq!(std::fs::read(&renamed).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 38, item 16: the task (and its robot) given by another spelling of the same path is
/// the same run, and resumes; a task of other content is not.
#[test]
fn another_spelling_of_the_task_path_resumes_the_run() {
    let dir = scratch("spelling");
    let robot = support::root().join("robots/belt_arm.urdf");
    std::fs::copy(robot, dir.join("belt_arm.urdf")).unwrap();
    let task = task_with(&dir, |task| {
        task["robot"] = "belt_arm.urdf".into();
        task["motion"]["steps"] = 4.into();
    });
    let run = |task: &str, start: &str| {
        support::codesign_in(
            &dir,
            &[
                "optimize",
                "--task",
                task,
                "--population",
                "5",
                "--generations",
                "1",
                "--workers",
                "1",
                "--out",
                "o.json",
                start,
            ],
        )
    };
    let first = run("task.json", "--overwrite");
    assert!(first.status.success(), "{}", stderr(&first));
    let absolute = task.to_str().unwrap().to_owned();
    for spelling in [
        "./task.json",
        &format!("../{}/task.json", file_name(&dir)),
        &absolute,
    ] {
        let again = run(spelling, "--resume");
        assert!(again.status.success(), "{spelling}: {}", stderr(&again));
        let result: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("o.json")).unwrap()).unwrap();
        assert_eq!(result["replayed"], 10, "{spelling}");
    }
    // Other content under the same name is another run.
    task_with(&dir, |task| {
        task["robot"] = "belt_arm.urdf".into();
        task["motion"]["steps"] = 5.into();
    });
    fails_saying(&run("task.json", "--resume"), "belongs to a different run");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn stderr(output: &std::process::Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn file_name(path: &Path) -> &str {
    path.file_name().unwrap().to_str().unwrap()
}

/// Numbers a user gives reach the messages as people write them (issue 57, item 21): a design
/// of 1e308 or 5e-324 is echoed as such, not as a 300-digit expansion, by `solve`, `capacity`
/// and `check`.
#[test]
fn messages_write_huge_and_tiny_numbers_in_exponent_form() {
    let longest_line = |output: &std::process::Output| {
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        let longest = stderr.lines().map(str::len).max().unwrap_or(0);
        assert!(longest < 200, "{stderr}");
    };
    let solve = codesign(&["solve", "--payload", "0.5", "--ratios", "1e308,1e308"]);
    fails_saying(
        &solve,
        "--ratios 1e308, 1e308: invalid design: the design has 2 ratios",
    );
    longest_line(&solve);
    let capacity = codesign(&["capacity", "--ratios", "1e308,1,1,1"]);
    fails_saying(
        &capacity,
        "--ratios 1e308, 1, 1, 1: invalid design: r1 = 1e308 is outside [1, 9]",
    );
    longest_line(&capacity);
    let check = codesign(&["check", "--ratios", "5e-324,1e308,1,1"]);
    fails_saying(&check, "design: r1 = 5e-324 is outside [1, 9]");
    longest_line(&check);
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(
        text.contains("design r = (0.0000, 1e308, 1.0000, 1.0000)"),
        "{text}"
    );
}
