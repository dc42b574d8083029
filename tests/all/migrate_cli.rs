//! `codesign migrate`: each older version of each document, and an evaluation log written before
//! checksums, migrated and then read by this build's readers; a current file left byte for
//! byte; an older file read without migration refused, naming `codesign migrate`; every
//! committed file current. The fixtures are in `tests/data/migrate/` (its README says how they
//! were made).

use crate::support;

use codesign::design::optimize::EvaluationLog;
use codesign::design::run::OptimizeInputs;
use codesign::store::log::{LogHeader, Start};
use std::path::{Path, PathBuf};
use support::{codesign, fails_saying, root, scratch};

/// Every fixture of an older version: (file, its kind and version as `migrate` names them).
const OLD: [(&str, &str); 9] = [
    ("solve-v0.json", "codesign/solve version 0 -> 2"),
    ("solve-v1.json", "codesign/solve version 1 -> 2"),
    ("capacity-v0.json", "codesign/capacity version 0 -> 2"),
    ("capacity-v1.json", "codesign/capacity version 1 -> 2"),
    ("optimize-v0.json", "codesign/optimize version 0 -> 3"),
    ("optimize-v1.json", "codesign/optimize version 1 -> 3"),
    ("optimize-v2.json", "codesign/optimize version 2 -> 3"),
    ("table-v1.json", "codesign/table version 1 -> 2"),
    ("unchecked.log.jsonl", "evaluation log of an older format"),
];

/// The fixtures copied into a scratch folder.
fn fixtures(name: &str) -> PathBuf {
    let dir = scratch(name);
    for (file, _) in OLD {
        std::fs::copy(root().join("tests/data/migrate").join(file), dir.join(file)).unwrap();
    }
    dir
}

fn text(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

fn path_str(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Read without migration, each older result is refused, naming the file and the command that
/// upgrades it; `--check` lists them all and fails, writing nothing.
#[test]
fn an_older_file_is_refused_naming_migrate() {
    let dir = fixtures("refused");
    for (file, _) in &OLD[..7] {
        let path = dir.join(file);
        let output = codesign(&["table", path_str(&path)]);
        fails_saying(
            &output,
            &format!(
                "run `codesign migrate {}` to bring it to this version",
                path.display()
            ),
        );
    }
    let before: Vec<String> = OLD.iter().map(|(f, _)| text(&dir.join(f))).collect();
    let output = codesign(&["migrate", "--check", path_str(&dir)]);
    fails_saying(&output, "9 of 9 files are of an older version");
    let stdout = String::from_utf8_lossy(&output.stdout);
    for ((file, words), was) in OLD.iter().zip(&before) {
        let path = dir.join(file);
        assert!(
            stdout.contains(&format!("{}: {words}", path.display())),
            "{stdout}"
        );
        assert_eq!(&text(&path), was, "--check wrote {file}");
    }
}

/// Each older document, migrated, reads with this build's reader (`table` reads results); the
/// original is kept beside it; the migrated file is current for a second migration, left byte
/// for byte.
#[test]
fn each_older_version_migrates_and_reads() {
    let dir = fixtures("each");
    for (file, words) in OLD {
        let path = dir.join(file);
        let was = text(&path);
        // Named twice, it is migrated once.
        let output = codesign(&["migrate", path_str(&path), path_str(&path)]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success(),
            "{file}: {stdout}{}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert!(
            stdout.contains(&format!("{}: {words}", path.display())),
            "{stdout}"
        );
        assert!(stdout.contains("1 migrated, 0 current"), "{stdout}");
        assert_eq!(
            text(&dir.join(format!("{file}.orig"))),
            was,
            "{file}: the original kept"
        );
        let migrated = text(&path);
        assert_ne!(migrated, was);
        let again = codesign(&["migrate", path_str(&path)]);
        assert!(String::from_utf8_lossy(&again.stdout).contains("0 migrated, 1 current"));
        assert_eq!(
            text(&path),
            migrated,
            "{file} changed by a second migration"
        );
    }
    for version in ["v0", "v1"] {
        let solve = dir.join(format!("solve-{version}.json"));
        let run = dir.join(format!("optimize-{version}.json"));
        let capacity = dir.join(format!("capacity-{version}.json"));
        let output = codesign(&[
            "table",
            path_str(&solve),
            path_str(&run),
            path_str(&capacity),
        ]);
        let table = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert!(table.contains("(task hash f33c7ee2226afd46)"), "{table}");
    }
    let none = support::read_json(&dir.join("optimize-v2.json"));
    assert_eq!(
        (none["version"].as_u64(), &none["best_cost"]),
        (Some(3), &serde_json::Value::Null)
    );
    let table = support::read_json(&dir.join("table-v1.json"));
    assert_eq!(
        table["rows"][1]["after"]["per_seed"],
        serde_json::json!([[0, null]])
    );
    let capacity = support::read_json(&dir.join("capacity-v0.json"));
    assert_eq!(capacity["inputs"]["ends"], "hold");
    assert_eq!(capacity["tool"]["linear_solver"], "mumps");
}

/// A log written before checksums, migrated, resumes under its run's settings (MUMPS, IPOPT's
/// verdict, cold starts: what the run ran with), every entry checked; unmigrated, resuming it
/// is refused, naming `codesign migrate`.
#[test]
fn a_log_without_checksums_migrates_and_resumes() {
    let dir = fixtures("log");
    let log = dir.join("unchecked.log.jsonl");
    let old = dir.join("old.log.jsonl");
    std::fs::copy(&log, &old).unwrap();
    let output = codesign(&["migrate", "--no-backup", path_str(&log)]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(!dir.join("unchecked.log.jsonl.orig").exists());
    let migrated = text(&log);
    let header: LogHeader = serde_json::from_str(migrated.lines().next().unwrap()).unwrap();
    assert!(header.checksums);
    let inputs: OptimizeInputs = serde_json::from_value(header.run).unwrap();
    assert_eq!(inputs.linear_solver.name(), "mumps");
    let (resumed, finished) = EvaluationLog::open(&log, &inputs, Start::Resume).unwrap();
    assert_eq!(finished.len(), 10);
    drop(resumed);
    assert_eq!(text(&log), migrated, "resuming rewrote the log");
    let error = EvaluationLog::open(&old, &inputs, Start::Resume).unwrap_err();
    assert!(
        error
            .to_string()
            .contains(&format!("run `codesign migrate {}`", old.display())),
        "{error}"
    );
}

/// Every committed result, table and log is current but the older-version fixtures of these
/// tests: `migrate --check` on the repository's folders names those alone; and a current file
/// migrated is left byte for byte, with no original kept.
#[test]
fn every_committed_file_is_current() {
    let folders: Vec<String> = ["results", "tests/data", "examples", "robots", "benches"]
        .iter()
        .map(|folder| root().join(folder).to_string_lossy().into_owned())
        .collect();
    let mut args = vec!["migrate", "--check"];
    args.extend(folders.iter().map(String::as_str));
    let output = codesign(&args);
    fails_saying(&output, &format!("{} of ", OLD.len()));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let fixtures = root().join("tests/data/migrate");
    let named: Vec<&str> = (stdout.lines())
        .filter(|line| !line.starts_with(' '))
        .filter_map(|line| line.split(": ").next())
        .collect();
    assert_eq!(named.len(), OLD.len(), "{stdout}");
    for file in named {
        assert!(
            Path::new(file).starts_with(&fixtures),
            "{file} is of an older version"
        );
    }
    let dir = scratch("current");
    let current = dir.join("run.json");
    std::fs::copy(
        root().join("results/linkage/ankle-joint-seed0.json"),
        &current,
    )
    .unwrap();
    let was = std::fs::read(&current).unwrap();
    let output = codesign(&["migrate", path_str(&dir)]);
    assert!(String::from_utf8_lossy(&output.stdout).contains("0 migrated, 1 current"));
    assert_eq!(std::fs::read(&current).unwrap(), was);
    assert!(!dir.join("run.json.orig").exists());
}

/// A file that is no codesign document, given by name, is an error; in a folder it is left
/// alone. A kept original is never overwritten.
#[test]
fn other_files_and_kept_originals_are_left_alone() {
    let dir = scratch("other");
    let task = dir.join("task.json");
    std::fs::copy(root().join("robots/tasks/pick_place.json"), &task).unwrap();
    fails_saying(
        &codesign(&["migrate", path_str(&task)]),
        "no codesign result, table or evaluation log",
    );
    let output = codesign(&["migrate", path_str(&dir)]);
    assert!(String::from_utf8_lossy(&output.stdout).contains("1 other JSON files left alone"));
    let solve = dir.join("solve.json");
    std::fs::copy(root().join("tests/data/migrate/solve-v1.json"), &solve).unwrap();
    std::fs::write(dir.join("solve.json.orig"), "kept").unwrap();
    fails_saying(&codesign(&["migrate", path_str(&solve)]), "solve.json.orig");
    assert_eq!(text(&dir.join("solve.json.orig")), "kept");
    assert_eq!(
        text(&solve),
        text(&root().join("tests/data/migrate/solve-v1.json"))
    );
}
