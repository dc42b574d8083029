//! Outputs replaced with care: a temporary file never follows a link planted at its name, every
//! name of one output shares one lock, and a file replaced keeps its permissions while one the
//! user may not write is refused.

use crate::support;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::time::Duration;
use support::{codesign, fails_saying, scratch, start_in_background, wait_for};

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A short co-design run's flags, writing to `out`.
fn optimize(out: &Path) -> Vec<String> {
    [
        "optimize",
        "--payload",
        "1",
        "--population",
        "8",
        "--generations",
        "3",
        "--workers",
        "1",
        "--out",
        path(out),
    ]
    .map(str::to_owned)
    .to_vec()
}

/// The flags of a run whose worker starts only once the file `gate` exists: the run holds its
/// evaluation log, locked, and has written nothing else until then.
fn gated(out: &Path, gate: &Gate) -> Vec<String> {
    let mut flags = optimize(out);
    let wait = format!(
        "while [ ! -e '{}' ]; do sleep 0.01; done; exec {{}} worker",
        path(&gate.0)
    );
    flags.extend(["--worker-command".to_owned(), wait]);
    flags
}

/// The file that lets gated runs go on: created by [`Gate::open`], or when dropped at the latest,
/// so that a failing test leaves no run waiting.
struct Gate(PathBuf);

impl Gate {
    fn open(&self) {
        std::fs::write(&self.0, "").unwrap();
    }
}

impl Drop for Gate {
    fn drop(&mut self) {
        let _ = std::fs::write(&self.0, "");
    }
}

/// Starts `flags` in the background and waits until its log at `log` holds its header.
fn start_holding(flags: &[String], log: &Path) -> std::process::Child {
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let run = start_in_background(&flags);
    wait_for(Duration::from_secs(300), || {
        std::fs::read_to_string(log).is_ok_and(|t| t.ends_with('\n'))
    });
    run
}

/// Whether `path` holds a run's result document.
fn holds_a_result(path: &Path) -> bool {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str::<serde_json::Value>(&text).is_ok_and(|v| v["best_cost"].is_number())
}

#[test]
fn a_link_planted_at_a_temporary_name_is_never_followed() {
    let dir = scratch("planted");
    let out = dir.join("o.json");
    let victim = dir.join("victim");
    std::fs::write(&victim, "precious").unwrap();
    let gate = Gate(dir.join("gate"));
    let mut run = start_holding(&gated(&out, &gate), &dir.join("o.log.jsonl"));
    // The name the run's temporary file of its result would take.
    let planted = dir.join(format!(".o.json.tmp{}", run.id()));
    std::os::unix::fs::symlink(&victim, &planted).unwrap();
    gate.open();
    assert!(run.wait().unwrap().success());
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert!(holds_a_result(&out));
    let planted = std::fs::symlink_metadata(&planted).unwrap();
    assert!(planted.file_type().is_symlink());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_name_of_one_output_shares_its_lock() {
    let dir = scratch("alias");
    let out = dir.join("a.json");
    std::fs::write(&out, "{}").unwrap();
    let alias = dir.join("alias.json");
    std::os::unix::fs::symlink("a.json", &alias).unwrap();
    let gate = Gate(dir.join("gate"));
    // The log, and so the lock, sits beside the file the link points to.
    let mut first = start_holding(&gated(&alias, &gate), &dir.join("a.log.jsonl"));
    assert!(!dir.join("alias.log.jsonl").exists());
    for flag in [None, Some("--resume"), Some("--overwrite")] {
        let mut second = optimize(&out);
        second.extend(flag.map(str::to_owned));
        let second: Vec<&str> = second.iter().map(String::as_str).collect();
        let output = codesign(&second);
        fails_saying(
            &output,
            &format!("in use by another run (pid {})", first.id()),
        );
    }
    gate.open();
    assert!(first.wait().unwrap().success());
    assert!(holds_a_result(&out));
    assert!(std::fs::symlink_metadata(&alias)
        .unwrap()
        .file_type()
        .is_symlink());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_replaced_output_keeps_its_mode_and_a_read_only_one_is_refused() {
    let dir = scratch("mode");
    let out = dir.join("r.json");
    let solve = || codesign(&["solve", "--steps", "2", "--out", path(&out)]);
    let mode = || std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    let chmod =
        |mode: u32| std::fs::set_permissions(&out, std::fs::Permissions::from_mode(mode)).unwrap();
    assert!(solve().status.success());
    chmod(0o600);
    let output = solve();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(mode(), 0o600);
    chmod(0o444);
    let before = std::fs::read(&out).unwrap();
    fails_saying(
        &solve(),
        &format!(
            "--out {}: is not writable by this user (mode 444)",
            out.display()
        ),
    );
    assert_eq!(std::fs::read(&out).unwrap(), before);
    assert_eq!(mode(), 0o444);
    std::fs::remove_dir_all(&dir).unwrap();
}
