//! Advisory locks (`flock`) that keep two runs off one output: taken without waiting, and when
//! another process holds one, the error names that process.
//!
//! A lock lasts as long as the open file that holds it: dropping the file releases it, and so
//! does the end of the process, however it ends.

use super::{Action, StoreError, Thing};
use std::fs::{File, TryLockError};
use std::os::unix::fs::MetadataExt;
use std::path::Path;

/// Takes the lock of `file` (the `thing` at `path`) without waiting. Fails at once when another
/// process holds it, naming that process.
pub fn lock_file(file: &File, thing: Thing, path: &Path) -> Result<(), StoreError> {
    match file.try_lock() {
        Ok(()) => Ok(()),
        Err(TryLockError::WouldBlock) => Err(StoreError::Locked {
            thing,
            path: path.to_owned(),
            pid: holder(file),
        }),
        Err(TryLockError::Error(error)) => Err(StoreError::io(Action::Lock(thing), path, &error)),
    }
}

/// Opens the output folder `folder` and takes its lock, so that two runs never write one folder
/// at once; the lock is held until the returned handle is dropped.
pub fn lock_folder(folder: &Path) -> Result<File, StoreError> {
    let thing = Thing::OutputFolder;
    let handle =
        File::open(folder).map_err(|error| StoreError::io(Action::Open(thing), folder, &error))?;
    lock_file(&handle, thing, folder)?;
    Ok(handle)
}

/// The process that holds the lock on `file`, from Linux's /proc/locks (None when unknown).
fn holder(file: &File) -> Option<u32> {
    let inode = file.metadata().ok()?.ino().to_string();
    let locks = std::fs::read_to_string("/proc/locks").ok()?;
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
        .and_then(|fields| fields.get(4)?.parse().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_fails_at_once_naming_the_holder() {
        let folder = std::env::temp_dir().join(format!("codesign-lock-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let held = lock_folder(&folder).unwrap();
        let error = lock_folder(&folder).unwrap_err();
        assert_eq!(
            error,
            StoreError::Locked {
                thing: Thing::OutputFolder,
                path: folder.clone(),
                pid: Some(std::process::id()),
            }
        );
        assert!(error.to_string().contains("is in use by another run (pid "));
        drop(held);
        drop(lock_folder(&folder).unwrap());
        let missing = folder.join("missing");
        let error = lock_folder(&missing).unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with("cannot open the output folder "),
            "{error}"
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
