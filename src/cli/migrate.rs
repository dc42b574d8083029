//! `codesign migrate`: result files, tables and evaluation logs of older versions brought to the
//! version this build writes and reads, in place.

use crate::report::migrate::{plan, Kind, Migration};
use crate::report::{ReadFailure, ReportError};
use std::path::{Path, PathBuf};

/// Flags of `codesign migrate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Result files (`solve`, `optimize`, `capacity`), tables and evaluation logs
    /// (`*.log.jsonl`) to bring to this version, or folders, whose `*.json` and `*.log.jsonl`
    /// files are migrated at every depth (other JSON in them is left alone).
    #[arg(required = true, value_name = "PATHS")]
    paths: Vec<PathBuf>,
    /// Write nothing: list the files of an older version and what would change, and exit 1 if
    /// there is any.
    #[arg(long)]
    check: bool,
    /// Replace each old file without keeping its original (by default kept beside it as
    /// `NAME.orig`, and a file whose `NAME.orig` exists is refused).
    #[arg(long)]
    no_backup: bool,
}

/// Plans every file first (any file unreadable, damaged or newer stops the command before
/// anything is written), then writes the migrated ones.
pub fn run(args: &Args) -> Result<(), String> {
    let mut plans = Vec::new();
    let mut others = 0;
    // A file named twice (by itself and in a folder, or through a link) is migrated once.
    let mut seen = std::collections::HashSet::new();
    for path in &args.paths {
        let walked = path.is_dir();
        for file in files_of(path)? {
            if !seen.insert(std::fs::canonicalize(&file).unwrap_or_else(|_| file.clone())) {
                continue;
            }
            match plan(&file)? {
                Some(migration) => plans.push(migration),
                None if walked => others += 1,
                None => Err(ReportError::Read {
                    path: file,
                    why: ReadFailure::NotADocument,
                })?,
            }
        }
    }
    let old: Vec<&Migration> = plans.iter().filter(|m| m.is_old()).collect();
    for migration in &old {
        say!("{}: {}", migration.path.display(), words(migration));
        for change in &migration.changes {
            say!("  {change}");
        }
        if !args.check {
            if let Some(kept) = migration.apply(!args.no_backup)? {
                say!("  original kept as {}", kept.display());
            }
        }
    }
    let current = plans.len() - old.len();
    let left = match others {
        0 => String::new(),
        n => format!(", {n} other JSON files left alone"),
    };
    if args.check && !old.is_empty() {
        return Err(format!(
            "{} of {} files are of an older version{left}: run `codesign migrate` on them \
             without --check",
            old.len(),
            plans.len()
        ));
    }
    let done = if args.check { "to migrate" } else { "migrated" };
    say!("{} {done}, {current} current{left}", old.len());
    Ok(())
}

/// What a migration does to its file, in words.
fn words(migration: &Migration) -> String {
    match migration.kind {
        Kind::Document(schema, version) => {
            format!("{} version {version} -> {}", schema.tag(), schema.version())
        }
        Kind::Log => "evaluation log of an older format".to_owned(),
    }
}

/// The files `path` names: itself, or for a folder its `*.json` and `*.log.jsonl` files at
/// every depth, in order of their paths (symbolic links to folders and hidden entries are not
/// followed).
fn files_of(path: &Path) -> Result<Vec<PathBuf>, String> {
    if !path.is_dir() {
        return Ok(vec![path.to_owned()]);
    }
    let mut found = Vec::new();
    let mut folders = vec![path.to_owned()];
    while let Some(folder) = folders.pop() {
        let entries = std::fs::read_dir(&folder)
            .map_err(|e| format!("cannot read folder {}: {e}", folder.display()))?;
        for entry in entries {
            let entry =
                entry.map_err(|e| format!("cannot read folder {}: {e}", folder.display()))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let kind = entry
                .file_type()
                .map_err(|e| format!("{}: {e}", entry.path().display()))?;
            if name.starts_with('.') {
                continue;
            }
            if kind.is_dir() {
                folders.push(entry.path());
            } else if name.ends_with(".json") || name.ends_with(".log.jsonl") {
                found.push(entry.path());
            }
        }
    }
    found.sort();
    Ok(found)
}
