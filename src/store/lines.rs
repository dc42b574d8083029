//! Reading a log line by line, never more than one bounded line in memory: a file of any size
//! at a log's path costs at most [`MAX_LOG_LINE_BYTES`] to read, whatever it holds.

use std::io::{BufRead, Read};

/// The longest line a log holds, bytes, its end included: its header carries the run's task
/// (at most 1 MiB as read, a little more escaped), an entry one evaluation (a reason at most
/// 4 KiB).
pub const MAX_LOG_LINE_BYTES: u64 = 4 << 20;

/// One line read from a log.
#[derive(Debug, PartialEq, Eq)]
pub(super) enum Line {
    /// A whole line, its end included.
    Whole(String),
    /// The last line of the file, without its end (an append cut short).
    Torn(String),
    /// A line longer than [`MAX_LOG_LINE_BYTES`]: no line of a log.
    TooLong,
    /// A line that is not UTF-8 text: no line of a log.
    NotText,
}

impl Line {
    /// The line's text, whole or torn; else what makes it no line of a log.
    pub(super) fn text(self) -> Result<String, String> {
        match self {
            Line::Whole(text) | Line::Torn(text) => Ok(text),
            Line::TooLong => Err(format!(
                "a line longer than {MAX_LOG_LINE_BYTES} bytes, which no log writes"
            )),
            Line::NotText => Err("a line that is not UTF-8 text".to_owned()),
        }
    }
}

/// The next line of `reader`; None at the end of the file.
pub(super) fn next_line(reader: &mut impl BufRead) -> std::io::Result<Option<Line>> {
    let mut bytes = Vec::new();
    reader
        .by_ref()
        .take(MAX_LOG_LINE_BYTES + 1)
        .read_until(b'\n', &mut bytes)?;
    if bytes.is_empty() {
        return Ok(None);
    }
    if bytes.len() as u64 > MAX_LOG_LINE_BYTES {
        return Ok(Some(Line::TooLong));
    }
    let whole = bytes.ends_with(b"\n");
    Ok(Some(match (String::from_utf8(bytes), whole) {
        (Ok(text), true) => Line::Whole(text),
        (Ok(text), false) => Line::Torn(text),
        (Err(_), _) => Line::NotText,
    }))
}

#[cfg(test)]
mod tests {
    use super::{next_line, Line, MAX_LOG_LINE_BYTES};
    use std::io::{BufReader, Read};

    #[test]
    fn lines_are_read_whole_torn_or_refused_without_reading_on() {
        let mut reader = BufReader::new(&b"{\"a\":1}\n\xff\n{\"cut"[..]);
        let mut next = || next_line(&mut reader).unwrap();
        assert_eq!(next(), Some(Line::Whole("{\"a\":1}\n".to_owned())));
        assert_eq!(next(), Some(Line::NotText));
        assert_eq!(next(), Some(Line::Torn("{\"cut".to_owned())));
        assert_eq!(next(), None);
        // An endless line (a device, a huge file) is refused after the bound, not read whole.
        let mut zeros = BufReader::new(std::io::repeat(b'0').take(1 << 40));
        assert_eq!(next_line(&mut zeros).unwrap(), Some(Line::TooLong));
        let exactly = "x".repeat(MAX_LOG_LINE_BYTES as usize - 1) + "\n";
        let mut reader = BufReader::new(exactly.as_bytes());
        assert_eq!(next_line(&mut reader).unwrap(), Some(Line::Whole(exactly)));
    }
}
