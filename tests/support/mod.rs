//! Fixtures shared by the end-to-end tests: the repository's paths, the binary, scratch folders,
//! and headless Chromium (`chromium`).
// Each test module uses part of this module.
#![allow(dead_code)]

pub mod chromium;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The repository's root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The task file the built-in task is compiled from.
pub fn task_path() -> PathBuf {
    root().join("robots/tasks/pick_place.json")
}

/// The solve settings of the task file's `solver` section, with `linear_solver`.
pub fn settings(
    linear_solver: codesign_core::ipopt::LinearSolver,
) -> codesign_core::solve::SolveSettings {
    let file =
        codesign_core::model::task::TaskFile::load(&task_path()).expect("the task file loads");
    let mut settings = codesign_core::solve::SolveSettings::from_section(file.solver.as_ref())
        .expect("its solver section is valid");
    settings.linear_solver = Some(linear_solver);
    settings
}

/// The codesign binary, to run in `dir`.
pub fn codesign_command(dir: &Path, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_codesign"));
    command.args(args).current_dir(dir);
    command
}

/// Runs codesign in `dir` to completion.
pub fn codesign_in(dir: &Path, args: &[&str]) -> Output {
    codesign_command(dir, args)
        .output()
        .expect("the codesign binary runs")
}

/// Runs codesign in the repository's root to completion.
pub fn codesign(args: &[&str]) -> Output {
    codesign_in(root(), args)
}

/// Starts codesign in the repository's root with its output discarded, to run beside a second
/// command.
pub fn start_in_background(args: &[&str]) -> Child {
    codesign_command(root(), args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the codesign binary starts")
}

/// Waits until `started` holds, failing after `limit`.
pub fn wait_for(limit: Duration, started: impl Fn() -> bool) {
    let start = Instant::now();
    while !started() {
        assert!(start.elapsed() < limit, "the first run did not start");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// An empty folder outside the repository, named for this process, the running test (its
/// thread's name: the test's path, unique in the binary) and `name`.
pub fn scratch(name: &str) -> PathBuf {
    let thread = std::thread::current();
    let test: String = (thread.name().unwrap_or("main").chars())
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let dir = std::env::temp_dir().join(format!("codesign-{}-{test}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Asserts that the command failed with exit code 1 and that its error says `expected`.
pub fn fails_saying(output: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(expected), "{stderr}");
}

/// Asserts that the command was refused as a usage error (exit code 2, a flag out of its range,
/// as clap's own) and that its error says `expected`.
pub fn refused_as_usage(output: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(expected), "{stderr}");
}

/// The repository's task with its robot's path made absolute and `edit` applied, written to
/// `dir/task.json`.
pub fn task_with(dir: &Path, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read_to_string(task_path()).unwrap();
    let mut task: serde_json::Value = serde_json::from_str(&text).unwrap();
    task["robot"] = root().join("robots/belt_arm.urdf").to_str().unwrap().into();
    edit(&mut task);
    let file = dir.join("task.json");
    std::fs::write(&file, task.to_string()).unwrap();
    file
}

/// Runs codesign in `dir`, failing the test on an error; returns its stdout.
pub fn succeed_in(dir: &Path, args: &[&str]) -> String {
    let output = codesign_in(dir, args);
    assert!(
        output.status.success(),
        "codesign {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// The JSON document in the file at `path`.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Runs codesign in the repository's root with `args` and `--out out`, asserting exit 0: its
/// stdout and the result file's JSON.
pub fn succeed_with_out(args: &[&str], out: &Path) -> (String, serde_json::Value) {
    let out_text = out.to_str().expect("a UTF-8 path").to_owned();
    let mut all = args.to_vec();
    all.extend(["--out", &out_text]);
    let output = codesign(&all);
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        read_json(out),
    )
}
