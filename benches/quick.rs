//! The wall time of the README's main job, `codesign reproduce --quick` (the paper's experiment
//! on its reduced budget, with the default workers: one per core), each run into a fresh
//! temporary folder and timed as a whole command, process start included.
//!
//! `cargo bench --bench quick [-- --runs N] [--before BIN]`: N reproductions (default 3). With
//! `--before`, another build of codesign (e.g. `cargo build --release` in a `git worktree` of an
//! earlier commit) runs the same reproduction, alternating with this build so that both see the
//! same machine, and the ratio of the medians is printed. The machine's load average is printed
//! before and after.

mod common;

use codesign::stats::median;
use common::{load, timed};
use std::path::{Path, PathBuf};
use std::process::Command;

/// What the command line asks for.
struct Options {
    runs: usize,
    before: Option<PathBuf>,
}

fn options() -> Options {
    let mut options = Options {
        runs: 3,
        before: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--runs" => {
                let runs = args.next().expect("--runs takes a number, e.g. 3");
                options.runs = runs.parse().expect("--runs: a whole number, e.g. 3");
            }
            "--before" => {
                let binary = args.next().expect("--before takes a codesign binary");
                options.before = Some(PathBuf::from(binary));
            }
            // `cargo bench` passes --bench; other flags are the harness's, not ours.
            _ => {}
        }
    }
    options
}

/// One quick reproduction by `binary` into a fresh folder under `dir`; its wall time, s.
fn reproduce(binary: &Path, dir: &Path) -> f64 {
    let out = dir.join("quick");
    if out.exists() {
        std::fs::remove_dir_all(&out).expect("the last run's folder is removed");
    }
    let (_, wall) = timed(
        Command::new(binary)
            .args(["reproduce", "--quick", "--out-dir"])
            .arg(&out)
            // Run where the task's relative paths resolve, as the README's main job does.
            .current_dir(env!("CARGO_MANIFEST_DIR")),
    );
    wall
}

fn main() {
    let options = options();
    let dir = std::env::temp_dir().join(format!("codesign-quick-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let this = PathBuf::from(env!("CARGO_BIN_EXE_codesign"));
    let mut builds = vec![("this build", this)];
    if let Some(before) = options.before {
        builds.insert(0, ("before", before));
    }
    println!("load average before: {}", load());
    let mut walls = vec![Vec::new(); builds.len()];
    for run in 0..options.runs {
        for ((name, binary), walls) in builds.iter().zip(&mut walls) {
            let wall = reproduce(binary, &dir);
            println!("run {run}: {name} ({}): {wall:.1} s", binary.display());
            walls.push(wall);
        }
    }
    let medians: Vec<f64> = walls.iter().map(|w| median(w)).collect();
    for ((name, _), median) in builds.iter().zip(&medians) {
        println!(
            "reproduce --quick, {name}: median of {} runs {median:.1} s",
            options.runs
        );
    }
    if let [before, after] = medians[..] {
        println!(
            "this build takes {:.2} of the time before ({:.1}x faster)",
            after / before,
            before / after
        );
    }
    println!("load average after: {}", load());
    std::fs::remove_dir_all(&dir).ok();
}
