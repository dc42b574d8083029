//! Writing output files whole or not at all, and never over anything but a regular file.
//!
//! Symbolic links are followed: writing to a link replaces the regular file it points to and
//! keeps the link. A link to nothing, a folder, a device, a FIFO or a socket is refused, and so
//! is an output that is one of the command's inputs.

use std::fs::{File, Metadata, TryLockError};
use std::io::Write;
use std::os::unix::fs::{FileTypeExt, MetadataExt};
use std::path::{Path, PathBuf};

/// Checks, before any work, that `path` (given by `flag`, e.g. `--out`) can take a result: its
/// folder exists and is writable, it is absent or a regular file (through symbolic links), and
/// it is none of `inputs` (each named by where it came from, e.g. `--task`). Creates nothing
/// that outlives the call.
pub fn check_output(flag: &str, path: &Path, inputs: &[(&str, &Path)]) -> Result<(), String> {
    let target = resolve_target(path).map_err(|error| format!("{flag} {error}"))?;
    if let Ok(output) = std::fs::metadata(&target) {
        for (source, input) in inputs {
            if std::fs::metadata(input).is_ok_and(|input| same_file(&input, &output)) {
                return Err(format!(
                    "{flag} {}: that is an input of this command ({source} {}); writing there \
                     would destroy it, choose another path",
                    path.display(),
                    input.display()
                ));
            }
        }
    }
    let probe = temporary_beside(&target, "probe")?;
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|error| {
            format!(
                "{flag} {}: cannot write in its folder {}: {error}",
                path.display(),
                folder_of(&target).display()
            )
        })?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Whether two metadata describe the same file (device and inode).
fn same_file(a: &Metadata, b: &Metadata) -> bool {
    a.dev() == b.dev() && a.ino() == b.ino()
}

/// The regular file that writing `path` replaces, or `path` itself when it does not exist:
/// symbolic links are followed; anything else but a regular file is refused, naming its kind.
fn resolve_target(path: &Path) -> Result<PathBuf, String> {
    let shown = path.display();
    let target = match std::fs::symlink_metadata(path) {
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(path.to_owned()),
        Err(error) => return Err(format!("{shown}: {error}")),
        Ok(meta) if meta.file_type().is_symlink() => std::fs::canonicalize(path).map_err(|_| {
            format!("{shown}: a symbolic link to a missing file; links are followed only to existing regular files")
        })?,
        Ok(_) => path.to_owned(),
    };
    let meta = std::fs::metadata(&target).map_err(|error| format!("{shown}: {error}"))?;
    let kind = meta.file_type();
    let refused = if kind.is_file() {
        return Ok(target);
    } else if kind.is_dir() {
        "a folder"
    } else if kind.is_char_device() || kind.is_block_device() {
        "a device"
    } else if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    };
    Err(format!(
        "{shown}: is {refused}; codesign writes only regular files and leaves it untouched"
    ))
}

/// The folder holding `path` (`.` for a bare file name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A hidden name beside `path` for this process: `.NAME.TAG<pid>`.
fn temporary_beside(path: &Path, tag: &str) -> Result<PathBuf, String> {
    let name = path
        .file_name()
        .ok_or_else(|| format!("cannot write {}: not a file path", path.display()))?;
    Ok(folder_of(path).join(format!(
        ".{}.{tag}{}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename, so that a
/// reader (or an interrupted run) never sees a half-written file. A symbolic link is followed
/// (the file it points to is replaced); a target that is not a regular file is refused and left
/// as it is. Errors name the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let target = resolve_target(path).map_err(|error| format!("cannot write {error}"))?;
    let temporary = temporary_beside(&target, "tmp")?;
    let written = std::fs::File::create(&temporary)
        .and_then(|mut file| file.write_all(bytes).and_then(|()| file.sync_all()))
        .and_then(|()| std::fs::rename(&temporary, &target));
    written.map_err(|error| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot write {}: {error}", path.display())
    })
}

/// Serialises `value` as pretty JSON and writes it atomically to `path`.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), String> {
    let mut text = serde_json::to_string_pretty(value)
        .map_err(|error| format!("cannot serialise {}: {error}", path.display()))?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// Creates `folder` and its parents; errors name it.
pub fn create_folder(folder: &Path) -> Result<(), String> {
    std::fs::create_dir_all(folder)
        .map_err(|error| format!("cannot create folder {}: {error}", folder.display()))
}

/// Takes the advisory lock (`flock`) of `file` without waiting. When another process holds
/// it, fails at once naming `what`, that process, and the `elsewhere` flag that avoids it.
pub fn lock_or_name_holder(file: &File, what: &str, elsewhere: &str) -> Result<(), String> {
    match file.try_lock() {
        Ok(()) => Ok(()),
        Err(TryLockError::WouldBlock) => Err(format!(
            "{what} is in use by another run ({}): wait for it to end or stop it, or pass \
             another {elsewhere}",
            lock_holder(file)
        )),
        Err(TryLockError::Error(e)) => Err(format!("cannot lock {what}: {e}")),
    }
}

/// The process that holds the lock on `file`, as `pid N`, from Linux's /proc/locks.
fn lock_holder(file: &File) -> String {
    let (Ok(meta), Ok(locks)) = (file.metadata(), std::fs::read_to_string("/proc/locks")) else {
        return "process unknown".to_owned();
    };
    let inode = meta.ino().to_string();
    locks
        .lines()
        .map(|line| line.split_whitespace().collect::<Vec<_>>())
        .filter(|fields| fields.get(1) == Some(&"FLOCK"))
        .find(|fields| {
            fields
                .get(5)
                .and_then(|device| device.rsplit(':').next())
                .is_some_and(|found| found == inode)
        })
        .and_then(|fields| fields.get(4).map(|pid| format!("pid {pid}")))
        .unwrap_or_else(|| "process unknown".to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let folder =
            std::env::temp_dir().join(format!("codesign-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&folder);
        create_folder(&folder).unwrap();
        folder
    }

    #[test]
    fn writes_whole_files_and_names_unwritable_paths() {
        let folder = scratch("whole");
        let path = folder.join("out.json");
        write_json(&path, &serde_json::json!({"a": 1})).unwrap();
        write_json(&path, &serde_json::json!({"a": 2})).unwrap();
        let read: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(read["a"], 2);
        let leftovers = std::fs::read_dir(&folder).unwrap().count();
        assert_eq!(leftovers, 1, "temporary files left behind");
        let error = write_json(&folder.join("missing/out.json"), &1).unwrap_err();
        assert!(error.contains("missing/out.json"), "{error}");
        let error = check_output("--out", &folder.join("missing/out.json"), &[]).unwrap_err();
        assert!(error.starts_with("--out ") && error.contains("cannot write in its folder"));
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn follows_links_and_refuses_special_files_and_inputs() {
        let folder = scratch("special");
        let real = folder.join("real.json");
        std::fs::write(&real, "old").unwrap();
        let link = folder.join("link.json");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        check_output("--out", &link, &[]).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        let dangling = folder.join("dangling.json");
        std::os::unix::fs::symlink(folder.join("nothing"), &dangling).unwrap();
        assert!(write_atomic(&dangling, b"x")
            .unwrap_err()
            .contains("missing file"));
        let error = check_output("--out", Path::new("/dev/null"), &[]).unwrap_err();
        assert!(error.contains("is a device"), "{error}");
        assert!(write_atomic(Path::new("/dev/null"), b"x").is_err());
        assert!(write_atomic(&folder, b"x")
            .unwrap_err()
            .contains("a folder"));
        let error = check_output("--out", &link, &[("--task", &real)]).unwrap_err();
        assert!(error.contains("input of this command (--task"), "{error}");
        assert_eq!(
            std::fs::read_dir(&folder).unwrap().count(),
            3,
            "probe left behind"
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
