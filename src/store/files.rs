//! Writing output files whole or not at all, and never over anything but a regular file.
//!
//! Symbolic links are followed: writing to a link replaces the regular file it points to and
//! keeps the link. A link to nothing, a folder, a device, a FIFO or a socket is refused, and so
//! is an output that is one of the command's inputs or a file the user may not write. A file
//! replaced keeps its permission bits. Temporary files never open what is already at their name.

use super::{Action, FileKind, Refusal, StoreError};
use codesign_core::signals;
use std::ffi::{CString, OsStr};
use std::fs::{File, Metadata, OpenOptions, Permissions};
use std::io::{Read, Write};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::{FileTypeExt, MetadataExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

/// How many names a temporary file beside an output tries before giving up.
const ATTEMPTS: usize = 100;

/// Checks, before any work, that `path` can take a result: its folder exists and is writable, it
/// is absent or a regular file (through symbolic links) that this user may write, and it is none
/// of `inputs` (each named by where it came from, e.g. `--task`). Creates nothing that outlives
/// the call.
pub fn check_output(path: &Path, inputs: &[(&str, &Path)]) -> Result<(), StoreError> {
    let refused = |why| StoreError::Refused {
        path: path.to_owned(),
        why,
    };
    check_name(path).map_err(refused)?;
    let (target, _) = resolve_target(path).map_err(refused)?;
    if let Ok(output) = std::fs::metadata(&target) {
        for (source, input) in inputs {
            if std::fs::metadata(input).is_ok_and(|input| same_file(&input, &output)) {
                return Err(refused(Refusal::Input {
                    source: (*source).to_owned(),
                    input: input.to_path_buf(),
                }));
            }
        }
    }
    let (probe, name) = create_beside(&target, "probe")?.map_err(|error| {
        refused(Refusal::FolderNotWritable {
            folder: folder_of(&target),
            why: error.to_string(),
        })
    })?;
    drop(probe);
    let _ = std::fs::remove_file(&name);
    Ok(())
}

/// [`check_output`] for a result file a command is given: besides, it must be no evaluation log,
/// by its name (`x.log.jsonl`) or its first line, where a symbolic link points too, which would
/// replace another run's log.
pub fn check_result(path: &Path, inputs: &[(&str, &Path)]) -> Result<(), StoreError> {
    if is_log(path) || is_log(&resolved(path)) {
        return Err(StoreError::Refused {
            path: path.to_owned(),
            why: Refusal::LogName,
        });
    }
    check_output(path, inputs)
}

/// Whether `path` is an evaluation log, or would be one: named like one (`x.log.jsonl`), or a
/// file whose first line is a log's header, whatever its name.
fn is_log(path: &Path) -> bool {
    if path.to_string_lossy().ends_with(".log.jsonl") {
        return true;
    }
    // Only a regular file is read, opened without blocking: a FIFO is no log, and opening one
    // for reading would wait for a writer.
    if !std::fs::metadata(path).is_ok_and(|meta| meta.is_file()) {
        return false;
    }
    let opened = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path);
    let Ok(file) = opened else {
        return false;
    };
    let prefix = super::LOG_HEADER_PREFIX.as_bytes();
    let mut head = Vec::with_capacity(prefix.len());
    file.take(prefix.len() as u64)
        .read_to_end(&mut head)
        .is_ok_and(|_| head == prefix)
}

/// The longest file name Linux takes, bytes.
const NAME_MAX: usize = 255;

/// The most a temporary file's name adds to its output's: `.`, `.probe`, a process id of up to
/// 7 digits and `.NN`.
const TEMPORARY_SUFFIX: usize = 18;

/// Refuses a path that names a folder (ends in `/`, `/.` or `/..`, or is `.` or `..`) or whose
/// file name is too long to be written through a temporary file beside it.
fn check_name(path: &Path) -> Result<(), Refusal> {
    let bytes = path.as_os_str().as_bytes();
    let folder = [&b"/"[..], b"/.", b"/.."]
        .iter()
        .any(|end| bytes.ends_with(end))
        || bytes == b"."
        || bytes == b"..";
    if folder {
        return Err(Refusal::NamesFolder);
    }
    let bytes = path.file_name().map_or(0, |name| name.len());
    let limit = NAME_MAX - TEMPORARY_SUFFIX;
    if bytes > limit {
        return Err(Refusal::NameTooLong { bytes, limit });
    }
    Ok(())
}

/// Whether two metadata describe the same file (device and inode).
pub fn same_file(a: &Metadata, b: &Metadata) -> bool {
    a.dev() == b.dev() && a.ino() == b.ino()
}

/// The file that writing `path` replaces: the regular file a symbolic link `path` points to, or
/// `path` itself (when it is no link, or a link that [`check_output`] refuses).
pub fn resolved(path: &Path) -> PathBuf {
    resolve_target(path).map_or_else(|_| path.to_owned(), |(target, _)| target)
}

/// The regular file that writing `path` replaces, with its permission bits, or `path` itself
/// when it does not exist: symbolic links are followed; anything else but a regular file is
/// refused, naming its kind, and so is a regular file this user may not write.
fn resolve_target(path: &Path) -> Result<(PathBuf, Option<u32>), Refusal> {
    let unreadable = |error: std::io::Error| Refusal::Unreadable(error.to_string());
    let target = match std::fs::symlink_metadata(path) {
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
            return Ok((path.to_owned(), None))
        }
        Err(error) => return Err(unreadable(error)),
        Ok(meta) if meta.file_type().is_symlink() => {
            std::fs::canonicalize(path).map_err(|_| Refusal::DanglingLink)?
        }
        Ok(_) => path.to_owned(),
    };
    let meta = std::fs::metadata(&target).map_err(unreadable)?;
    let kind = meta.file_type();
    let refused = if kind.is_file() {
        let mode = meta.mode() & 0o777;
        return if may_write(&target, mode) {
            Ok((target, Some(mode)))
        } else {
            Err(Refusal::NotWritable { mode })
        };
    } else if kind.is_dir() {
        FileKind::Folder
    } else if kind.is_char_device() || kind.is_block_device() {
        FileKind::Device
    } else if kind.is_fifo() {
        FileKind::Fifo
    } else if kind.is_socket() {
        FileKind::Socket
    } else {
        FileKind::Other
    };
    Err(Refusal::Kind(refused))
}

/// Whether this user may replace the regular file at `path` of permission bits `mode`: it has a
/// write bit (a file marked read-only is refused, to root too), and the system grants this user
/// write access to it.
fn may_write(path: &Path, mode: u32) -> bool {
    let Ok(name) = CString::new(path.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: `name` is a NUL-terminated string that outlives the call, which only reads it.
    mode & 0o222 != 0 && unsafe { libc::access(name.as_ptr(), libc::W_OK) } == 0
}

/// The folder holding `path` (`.` for a bare file name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates a new hidden file beside `path` for this process, `.NAME.TAG<pid>`, or
/// `.NAME.TAG<pid>.N` while a name is taken (by a file an interrupted run left, or a link planted
/// there): exclusively (`O_EXCL`) and never through a symbolic link (`O_NOFOLLOW`), so that
/// nothing already at a name is opened, let alone written. Returns the file and its name, or the
/// system's reason it could not be created; a `path` that names no file is refused.
fn create_beside(path: &Path, tag: &str) -> Result<std::io::Result<(File, PathBuf)>, StoreError> {
    let name = path.file_name().ok_or_else(|| StoreError::NotAFilePath {
        path: path.to_owned(),
    })?;
    let folder = folder_of(path);
    let mut attempt = 0;
    loop {
        let temporary = folder.join(temporary_name(name, tag, attempt));
        let created = OpenOptions::new()
            .write(true)
            .create_new(true)
            .custom_flags(libc::O_NOFOLLOW)
            .open(&temporary);
        attempt += 1;
        match created {
            Err(error)
                if error.kind() == std::io::ErrorKind::AlreadyExists && attempt < ATTEMPTS => {}
            created => return Ok(created.map(|file| (file, temporary))),
        }
    }
}

/// The `attempt`-th hidden name beside the file `name` for this process: `.NAME.TAG<pid>`, then
/// `.NAME.TAG<pid>.N`.
fn temporary_name(name: &OsStr, tag: &str, attempt: usize) -> String {
    let base = format!(".{}.{tag}{}", name.to_string_lossy(), std::process::id());
    match attempt {
        0 => base,
        n => format!("{base}.{n}"),
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename, so that a
/// reader (or an interrupted run) never sees a half-written file. A symbolic link is followed
/// (the file it points to is replaced, keeping its permission bits); a target that is not a
/// regular file, or that this user may not write, is refused and left as it is. Errors name the
/// path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), StoreError> {
    let not_written = |why| StoreError::NotWritten {
        path: path.to_owned(),
        why,
    };
    let (target, mode) = resolve_target(path).map_err(not_written)?;
    // Resolved at the write itself: a link made to a log after the checks before the run.
    if is_log(&target) {
        return Err(not_written(Refusal::LogName));
    }
    replace_whole(path, &target, mode, bytes)
}

/// Replaces the evaluation log at `path`, read as a text of FNV-1a hash `read`, with `after`
/// whole, as [`write_atomic`] writes a result, holding the log's lock meanwhile: a run that has
/// it open makes this fail, naming the run, and none opens it before the new file is in place
/// (`codesign migrate`). Refuses a log that no longer holds what was read; keeps the original
/// as [`keep_original`] does when `keep`, and returns the name it is kept under.
pub fn rewrite_log(
    path: &Path,
    read: &str,
    after: &[u8],
    keep: bool,
) -> Result<Option<PathBuf>, StoreError> {
    let (target, mode) = resolve_target(path).map_err(|why| StoreError::NotWritten {
        path: path.to_owned(),
        why,
    })?;
    let thing = super::Thing::EvaluationLog;
    let mut held =
        File::open(&target).map_err(|e| StoreError::io(Action::Open(thing), path, &e))?;
    super::lock::lock_file(&held, thing, path)?;
    let mut now = Vec::new();
    held.read_to_end(&mut now)
        .map_err(|e| StoreError::io(Action::Read, path, &e))?;
    if codesign_core::hash::fnv1a(&now) != read {
        return Err(StoreError::Replaced {
            path: path.to_owned(),
        });
    }
    let kept = keep.then(|| keep_original(path)).transpose()?;
    replace_whole(path, &target, mode, after).inspect_err(|_| {
        kept.as_ref().map(std::fs::remove_file);
    })?;
    Ok(kept)
}

/// Keeps the file at `path` (the one a symbolic link points to) under the name `NAME.orig`
/// beside it, as a second name of the same file, before it is replaced; refuses where that
/// name is taken, so that no earlier original is lost. Returns the name kept.
pub fn keep_original(path: &Path) -> Result<PathBuf, StoreError> {
    let target = resolved(path);
    let mut name = target.as_os_str().to_owned();
    name.push(".orig");
    let kept = PathBuf::from(name);
    std::fs::hard_link(&target, &kept)
        .map_err(|e| StoreError::io(Action::Create(super::Thing::Original), &kept, &e))?;
    Ok(kept)
}

/// Writes `bytes` through a temporary file beside `target` (what `path` resolves to, of
/// permission bits `mode` where it exists) and renames it into place.
fn replace_whole(
    path: &Path,
    target: &Path,
    mode: Option<u32>,
    bytes: &[u8],
) -> Result<(), StoreError> {
    let failed = |error: std::io::Error| StoreError::io(Action::Write, path, &error);
    // INT, TERM and HUP wait until the temporary is renamed into place or removed.
    let _deferral = signals::defer();
    let (mut file, temporary) = create_beside(target, "tmp")?.map_err(failed)?;
    let written = mode
        .map_or(Ok(()), |mode| {
            file.set_permissions(Permissions::from_mode(mode))
        })
        .and_then(|()| file.write_all(bytes))
        .and_then(|()| file.sync_all())
        .and_then(|()| std::fs::rename(&temporary, target));
    written.map_err(|error| {
        let _ = std::fs::remove_file(&temporary);
        failed(error)
    })
}

/// Serialises `value` as pretty JSON (with a final line end) and writes it atomically to `path`.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), StoreError> {
    let mut text = serde_json::to_string_pretty(value).map_err(|error| StoreError::Serialise {
        path: path.to_owned(),
        why: error.to_string(),
    })?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// Creates `folder` and its parents.
pub fn create_folder(folder: &Path) -> Result<(), StoreError> {
    std::fs::create_dir_all(folder)
        .map_err(|error| StoreError::io(Action::CreateFolder, folder, &error))
}

/// Checks, before any work, that [`create_folder`] can give `folder`: it is a folder (a
/// symbolic link to one is followed), or the nearest part of its path that exists is a folder
/// this user may write in. Nothing is created.
pub fn check_folder(folder: &Path) -> Result<(), StoreError> {
    let refuse = |why: String| StoreError::Io {
        action: Action::CreateFolder,
        path: folder.to_owned(),
        why,
    };
    let mut existing = folder;
    loop {
        match std::fs::metadata(existing) {
            Ok(meta) if meta.is_dir() => break,
            Ok(_) if existing == folder => return Err(refuse("it exists and is no folder".into())),
            Ok(_) => return Err(refuse(format!("{} is no folder", existing.display()))),
            Err(_) if std::fs::symlink_metadata(existing).is_ok() => {
                return Err(refuse(format!(
                    "{} is a symbolic link to nothing",
                    existing.display()
                )))
            }
            // Missing, or under a file (which the next part of the loop names).
            Err(error)
                if matches!(
                    error.kind(),
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
                ) => {}
            Err(error) => return Err(StoreError::io(Action::CreateFolder, folder, &error)),
        }
        existing = match existing.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ if existing != Path::new(".") => Path::new("."),
            _ => return Err(refuse("the working folder is gone".into())),
        };
    }
    let writable = CString::new(existing.as_os_str().as_bytes()).is_ok_and(|name| {
        // SAFETY: `name` is a NUL-terminated string that outlives the call, which only reads it.
        unsafe { libc::access(name.as_ptr(), libc::W_OK | libc::X_OK) == 0 }
    });
    match writable {
        true => Ok(()),
        false => Err(refuse(format!(
            "this user may not write in {}",
            existing.display()
        ))),
    }
}

/// Removes `path`, a file or a folder with what it holds, when it exists: an output of an
/// earlier run that this run no longer makes. Returns whether there was one.
pub fn remove_stale(path: &Path) -> Result<bool, StoreError> {
    let removed = match std::fs::symlink_metadata(path) {
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(error) => Err(error),
        Ok(meta) if meta.is_dir() => std::fs::remove_dir_all(path),
        Ok(_) => std::fs::remove_file(path),
    };
    removed
        .map(|()| true)
        .map_err(|error| StoreError::io(Action::Remove, path, &error))
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
        assert!(error.to_string().contains("missing/out.json"), "{error}");
        let missing = folder.join("missing/out.json");
        let error = check_output(&missing, &[]).unwrap_err();
        assert!(
            matches!(&error, StoreError::Refused { path, why: Refusal::FolderNotWritable { .. } }
                if *path == missing),
            "{error:?}"
        );
        assert!(error.to_string().starts_with(&format!(
            "{}: cannot write in its folder",
            missing.display()
        )));
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn follows_links_and_refuses_special_files_and_inputs() {
        let folder = scratch("special");
        let real = folder.join("real.json");
        std::fs::write(&real, "old").unwrap();
        let link = folder.join("link.json");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        check_output(&link, &[]).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        let dangling = folder.join("dangling.json");
        std::os::unix::fs::symlink(folder.join("nothing"), &dangling).unwrap();
        let error = write_atomic(&dangling, b"x").unwrap_err();
        assert!(error.to_string().contains("missing file"), "{error}");
        let error = check_output(Path::new("/dev/null"), &[]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "/dev/null: is a device; codesign writes only regular files and leaves it untouched"
        );
        assert!(write_atomic(Path::new("/dev/null"), b"x").is_err());
        let error = write_atomic(&folder, b"x").unwrap_err();
        assert_eq!(
            error,
            StoreError::NotWritten {
                path: folder.clone(),
                why: Refusal::Kind(FileKind::Folder)
            }
        );
        assert!(error.to_string().starts_with("cannot write "), "{error}");
        let error = check_output(&link, &[("--task", &real)]).unwrap_err();
        assert!(
            error.to_string().contains("input of this command (--task"),
            "{error}"
        );
        assert_eq!(
            std::fs::read_dir(&folder).unwrap().count(),
            3,
            "probe left behind"
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_replaced_file_keeps_its_mode_and_a_read_only_one_is_refused() {
        let folder = scratch("mode");
        let out = folder.join("out.json");
        let mode = |path: &Path| std::fs::metadata(path).unwrap().mode() & 0o777;
        let chmod = |path: &Path, mode: u32| {
            std::fs::set_permissions(path, Permissions::from_mode(mode)).unwrap()
        };
        write_atomic(&out, b"first").unwrap();
        for kept in [0o600, 0o664] {
            chmod(&out, kept);
            check_output(&out, &[]).unwrap();
            write_atomic(&out, b"again").unwrap();
            assert_eq!(mode(&out), kept);
        }
        chmod(&out, 0o444);
        let why = Refusal::NotWritable { mode: 0o444 };
        let error = check_output(&out, &[]).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!(
                "{}: is not writable by this user (mode 444); codesign leaves it untouched",
                out.display()
            )
        );
        let error = write_atomic(&out, b"lost").unwrap_err();
        assert_eq!(
            error,
            StoreError::NotWritten {
                path: out.clone(),
                why
            }
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "again");
        assert_eq!(mode(&out), 0o444);
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn temporaries_never_follow_a_link_planted_at_their_name() {
        let folder = scratch("planted");
        let victim = folder.join("victim");
        std::fs::write(&victim, "precious").unwrap();
        let out = folder.join("out.json");
        let pid = std::process::id();
        for tag in ["tmp", "probe"] {
            let planted = folder.join(format!(".out.json.{tag}{pid}"));
            std::os::unix::fs::symlink(&victim, &planted).unwrap();
        }
        check_output(&out, &[]).unwrap();
        write_atomic(&out, b"result").unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "result");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        for tag in ["tmp", "probe"] {
            let planted = folder.join(format!(".out.json.{tag}{pid}"));
            let meta = std::fs::symlink_metadata(&planted).unwrap();
            assert!(meta.file_type().is_symlink(), "{tag}");
        }
        assert_eq!(
            std::fs::read_dir(&folder).unwrap().count(),
            4,
            "temporary left behind"
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_stale_output_is_removed_file_or_folder_and_a_missing_one_is_no_error() {
        let folder = scratch("stale");
        let file = folder.join("capacity.json");
        std::fs::write(&file, "{}").unwrap();
        let plots = folder.join("best-joint-3kg");
        create_folder(&plots).unwrap();
        std::fs::write(plots.join("tcp_path.svg"), "<svg/>").unwrap();
        assert!(remove_stale(&file).unwrap());
        assert!(remove_stale(&plots).unwrap());
        assert!(!file.exists() && !plots.exists());
        assert!(!remove_stale(&file).unwrap());
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
