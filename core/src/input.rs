//! Reading the files a command is given: regular files only, up to a stated size, so that a
//! device, a FIFO or a huge file is refused at once instead of hanging or filling the memory.

use std::fmt;
use std::io::Read;
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::Path;

/// The largest task file, bytes: a task is a few kB.
pub const MAX_TASK_BYTES: u64 = 1 << 20;

/// The largest URDF, bytes: the largest public robot descriptions are a few MB.
pub const MAX_URDF_BYTES: u64 = 32 << 20;

/// The largest result file, bytes: a full co-design run's document is a few MB.
pub const MAX_RESULT_BYTES: u64 = 256 << 20;

/// Why an input file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum InputError {
    /// The system refused (missing, no permission, ...): its message.
    Io(String),
    /// Not a regular file: what it is instead (a folder, a device, a FIFO, a socket).
    NotRegular(&'static str),
    /// Larger than the limit, bytes.
    TooLarge(u64),
    /// Not UTF-8 text.
    NotText,
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InputError::Io(message) => write!(f, "cannot read: {message}"),
            InputError::NotRegular(kind) => write!(f, "is {kind}, not a regular file"),
            InputError::TooLarge(limit) => write!(
                f,
                "is larger than {} MiB, more than any file of its kind holds",
                limit >> 20
            ),
            InputError::NotText => f.write_str("is not UTF-8 text"),
        }
    }
}

impl std::error::Error for InputError {}

/// What a file that is not regular is, in words.
fn kind(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        "a folder"
    } else if file_type.is_char_device() || file_type.is_block_device() {
        "a device"
    } else if file_type.is_fifo() {
        "a FIFO"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// Reads the regular file at `path` (symbolic links followed) as text, at most `limit` bytes;
/// a leading UTF-8 byte order mark is dropped. Never blocks on a FIFO.
pub fn read_text(path: &Path, limit: u64) -> Result<String, InputError> {
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .map_err(|e| InputError::Io(e.to_string()))?;
    let meta = file.metadata().map_err(|e| InputError::Io(e.to_string()))?;
    if !meta.is_file() {
        return Err(InputError::NotRegular(kind(meta.file_type())));
    }
    if meta.len() > limit {
        return Err(InputError::TooLarge(limit));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| InputError::Io(e.to_string()))?;
    if bytes.len() as u64 > limit {
        return Err(InputError::TooLarge(limit));
    }
    let text = String::from_utf8(bytes).map_err(|_| InputError::NotText)?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = std::env::temp_dir().join(format!("codesign-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.json");
        std::fs::write(&file, "\u{feff}{}").unwrap();
        assert_eq!(read_text(&file, 100).unwrap(), "{}");
        assert_eq!(read_text(&file, 2), Err(InputError::TooLarge(2)));
        assert_eq!(
            read_text(&dir, 100),
            Err(InputError::NotRegular("a folder"))
        );
        let zero = read_text(Path::new("/dev/zero"), 100);
        assert_eq!(zero, Err(InputError::NotRegular("a device")));
        std::fs::write(&file, [0xff, 0xfe]).unwrap();
        assert_eq!(read_text(&file, 100), Err(InputError::NotText));
        let missing = read_text(&dir.join("missing"), 100).unwrap_err();
        assert!(
            missing.to_string().starts_with("cannot read: "),
            "{missing}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
